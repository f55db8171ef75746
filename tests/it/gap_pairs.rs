//! Two effects at once (src/gap/pairs.rs): parts simulated from the reference signatures
//! (`effect_signatures.csv`, baseline `sensitivity_physical.csv`) with random location errors,
//! two candidates each at 4× the detection limit (unabsorbed RMS = 4 · 2.5σ) and noise σ = 1.5 µm.
//! Without the pair step these parts were `unexplained` with the stronger effect as `partial`.
use crate::gap_common::*;
use nalgebra::{DMatrix, DVector};
use testpiece::gap::diagnose;
use testpiece::identify::solve::Factor;
use testpiece::numerics::random::Sampler;

const SIGMA: f64 = 0.0015;

/// `baseline·ξ + Σ effects + noise`, each effect scaled so that the part of it the baseline cannot
/// absorb has an RMS of `ratio · 2.5σ`.
fn part(effects: &[(&str, f64)], seed: u64) -> Vec<f64> {
    let inp = input(vec![0.0; 100]);
    let a = &inp.baseline.matrix;
    let base = Factor::new(a, None);
    let mut rng = Sampler::new(seed);
    let xi = DVector::from_iterator(
        8,
        (0..8).map(|j| rng.uniform(-1.0, 1.0) * if j == 5 { 0.03 } else { 3e-4 }),
    );
    let mut y = a * xi;
    for (id, ratio) in effects {
        let c = inp
            .candidates
            .iter()
            .find(|c| c.effect.id() == *id)
            .unwrap();
        let s: &DMatrix<f64> = &c.signature.matrix;
        let dir = DVector::from_iterator(
            s.ncols(),
            (0..s.ncols()).map(|j| rng.sign() / s.column(j).norm()),
        );
        let e = s * dir;
        let un = base.unabsorbed_vec(&e).norm() / 10.0;
        y += e * (ratio * 2.5 * SIGMA / un);
    }
    for v in y.iter_mut() {
        *v += SIGMA * rng.normal();
    }
    y.iter().copied().collect()
}

fn named(v: &testpiece::gap::verdict::Verdict) -> Vec<String> {
    let f = &v.finding;
    let mut all = vec![v.id().to_string()];
    all.extend(f.equivalent().iter().map(|e| e.to_string()));
    if let Some(w) = f.with() {
        all.push(w.effect.to_string());
        all.extend(w.equivalent.iter().map(|e| e.to_string()));
    }
    all
}

#[test]
fn two_effects_together_are_both_named() {
    let ids: Vec<String> = input(vec![0.0; 100])
        .candidates
        .iter()
        .map(|c| c.effect.to_string())
        .collect();
    // Pairs the part can tell apart: not one of effects.md's near-equivalent pairs and not two
    // candidates of which one contains the other.
    let alike = |a: &str, b: &str| {
        let mut p = [a, b];
        p.sort();
        matches!(
            p,
            ["tool_radius", "tool_taper"]
                | ["c_index", "setup_error"]
                | ["backlash_b", "backlash_z"]
                | ["pivot_length", "scale_z"]
        )
    };
    let (mut total, mut both, mut unexplained_or_none) = (0, 0, 0);
    let mut seed = 100;
    for (i, a) in ids.iter().enumerate() {
        for b in &ids[i + 1..] {
            if alike(a, b) {
                continue;
            }
            seed += 1;
            let y = part(&[(a.as_str(), 4.0), (b.as_str(), 4.0)], seed);
            let r = diagnose(&input(y)).unwrap();
            // the report holds no per-point span of a fit (the search's, released: what a
            // backlash's take-up round holds of the round before, issue 31)
            let spans = |f: &testpiece::gap::which::CandidateFit| {
                f.unabsorbed_effect.len() + f.unabsorbed_basis.len()
            };
            assert_eq!(r.candidates.iter().map(spans).sum::<usize>(), 0, "{a}+{b}");
            assert_eq!(r.pair.as_ref().map_or(0, |p| spans(&p.fit)), 0, "{a}+{b}");
            let v = &r.verdict;
            let names = named(v);
            total += 1;
            if [a, b].iter().all(|p| names.contains(p)) {
                both += 1;
                assert!(v.finding.with().is_some());
                assert!(r
                    .summary
                    .lines()
                    .next()
                    .unwrap()
                    .contains(" together with "));
                // Both explained: what is left is the noise (σ = 1.5 µm) within 40 %; within
                // 2σ when the pair holds a near-equivalent in a member's place (e.g. backlash_z
                // for backlash_b), whose signature differs a little from the simulated one.
                let exact = v
                    .finding
                    .effects()
                    .iter()
                    .all(|e| [a, b].contains(&&e.to_string()));
                let bound = if exact { 1.4 } else { 2.0 };
                assert!(
                    v.rms_after < bound * SIGMA,
                    "{a}+{b}: {:?} {}",
                    v.finding.effects(),
                    v.rms_after
                );
            } else {
                println!("{a} + {b}: verdict {:?}", v.finding);
                if v.finding.effects().is_empty() {
                    unexplained_or_none += 1;
                }
            }
        }
    }
    println!(
        "two effects at 4x the limit: both named {both}/{total} = {:.1} %, {unexplained_or_none} left unexplained or none",
        100.0 * both as f64 / total as f64
    );
    // Floor: 85 % (measured when written: see the note of the pair step); a miss is mostly a
    // second effect that the first and the baseline together nearly absorb.
    assert!(both as f64 >= 0.85 * total as f64, "{both}/{total}");
}

#[test]
fn a_single_effect_is_not_paired_and_waviness_stays_unexplained() {
    for (id, seed) in [
        ("backlash_y", 11),
        ("tool_radius", 12),
        ("thermal_drift", 13),
    ] {
        let r = diagnose(&input(part(&[(id, 4.0)], seed))).unwrap();
        assert!(
            r.verdict.finding.with().is_none(),
            "{id}: paired with {:?}",
            r.verdict.finding.with()
        );
        assert!(r.pair.is_none());
    }
    // A waviness of 250 mm wavelength along the path (outside effects.md) at 4× the limit: two
    // candidates must not be combined to pass it off as explained.
    let inp = input(vec![0.0; 100]);
    let s: Vec<f64> = inp.points.iter().map(|p| p.s).collect();
    let base = Factor::new(&inp.baseline.matrix, None);
    let wave = DVector::from_iterator(
        100,
        s.iter()
            .map(|s| (2.0 * std::f64::consts::PI * s / 250.0).sin()),
    );
    let un = base.unabsorbed_vec(&wave).norm() / 10.0;
    let mut rng = Sampler::new(14);
    let y: Vec<f64> = wave
        .iter()
        .map(|w| w * 4.0 * 2.5 * SIGMA / un + SIGMA * rng.normal())
        .collect();
    let r = diagnose(&input(y)).unwrap();
    assert_eq!(r.verdict.id().as_str(), "unexplained", "{}", r.summary);
}

/// The part of `tests/data/gap/two_effects.csv`: the real part model (`part_model` at the 100
/// built-in points, not the reference signatures), location errors, backlash of Y and a tool
/// radius error each at 4× the detection limit, noise σ = 1.5 µm, written to 6 decimals (mm).
fn two_effects_file() -> String {
    use testpiece::cmm::write::{canonical_csv, Precision};
    use testpiece::effects::prepared::Prepared;
    use testpiece::part::{builtin_points, SShape};
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let prepared = Prepared::new(part, Default::default()).unwrap();
    let m = prepared
        .part_model(&pts, &prepared.axis_values(&pts).unwrap())
        .unwrap();
    let a = &m.baseline.matrix;
    let base = Factor::new(a, None);
    let mut rng = Sampler::new(7);
    let xi = DVector::from_iterator(
        a.ncols(),
        (0..a.ncols()).map(|j| rng.uniform(-1.0, 1.0) * if j == 5 { 0.03 } else { 3e-4 }),
    );
    let mut y = a * xi;
    let mut said = Vec::new();
    for id in ["backlash_y", "tool_radius"] {
        let c = m.candidates.iter().find(|c| c.effect.id() == id).unwrap();
        let s = c.signature.matrix.column(0).into_owned();
        let un = base.unabsorbed_vec(&s).norm() / 10.0;
        let v = 4.0 * 2.5 * SIGMA / un;
        y += s * v;
        said.push(format!("{id} {} = {v:.4e}", c.effect.parameters()[0].0));
    }
    for v in y.iter_mut() {
        *v += SIGMA * rng.normal();
    }
    canonical_csv(
        pts.iter().zip(y.iter().copied()),
        Precision::Decimals(6),
        Some(&format!(
            "testpiece synthetic part with two unmodelled effects (tests/it/gap_pairs.rs): location errors, {}, noise 1.5 um",
            said.join(", ")
        )),
    )
}

#[test]
fn a_measured_file_with_two_effects_gets_both() {
    let path = format!(
        "{}/tests/data/gap/two_effects.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = two_effects_file();
    if std::env::var_os("TESTPIECE_WRITE_EXAMPLES").is_some() {
        std::fs::create_dir_all(std::path::Path::new(&path).parent().unwrap()).unwrap();
        std::fs::write(&path, &text).unwrap();
    }
    let on_disk = std::fs::read_to_string(&path).unwrap();
    assert!(
        on_disk == text,
        "{path} differs from the generator: regenerate with TESTPIECE_WRITE_EXAMPLES=1"
    );
    let a = testpiece::analysis::analyse_once(
        on_disk.as_bytes(),
        "two_effects.csv",
        &Default::default(),
    )
    .unwrap();
    let d = a.diagnosis.into_report().unwrap();
    println!("{}", d.summary);
    let names = named(&d.verdict);
    for id in ["backlash_y", "tool_radius"] {
        assert!(names.iter().any(|n| n == id), "{id} not in {names:?}");
    }
    assert!(d.summary.starts_with("Verdict: "));
    assert!(d
        .summary
        .lines()
        .next()
        .unwrap()
        .contains(" together with "));
}

/// `testpiece validate --pairs` on the real part model: seed 1, 202 two-effect parts (each
/// distinguishable pair twice), each effect at 1.5..6× its detection limit. Measured when
/// written: both named 75.0 % at 404 cases (seed 2: 76.0 %); without the pair step 0.7 %, with
/// 133 of 404 parts called `none`. Floors: 65 % both named, at most 8 % `none`.
#[test]
fn validate_pairs_floor() {
    use testpiece::validate::{pairs_table, validate_pairs, ValidateOptions, ValidationModel};
    let part = testpiece::part::SShape::iso();
    let model = ValidationModel::at(&part, &testpiece::part::builtin_points(&part))
        .unwrap()
        .without_shapes();
    let r = validate_pairs(&model, &ValidateOptions::default().with_cases(202)).unwrap();
    print!("{}", pairs_table(&r));
    assert!(r.rate >= 0.65, "{}", r.rate);
    assert!(r.none as f64 <= 0.08 * r.cases as f64, "{}", r.none);
}

/// One effect at twice the limit and a second just under it (0.9×): alone, the first one's σ
/// holds the second (σ ≈ 3.7 µm against 1.5), so its visible part (7.5 µm) is under its own
/// limit and the part was `unexplained`. Fitted together, the first is visible against the
/// pair's σ and the second is significant but below the limit: the first is named alone, the
/// second among the effects possible below the limit (src/gap/pairs.rs, "A second effect below
/// the limit"). Measured: every part of the 3 pairs × 3 seeds.
#[test]
fn a_second_effect_below_the_limit_lets_the_first_be_named() {
    let mut found = Vec::new();
    for (first, second) in [
        ("tool_radius", "backlash_y"),
        ("thermal_drift", "backlash_c"),
        ("scale_x", "backlash_b"),
    ] {
        for seed in [21, 22, 23] {
            let r = diagnose(&input(part(&[(first, 2.0), (second, 0.9)], seed))).unwrap();
            let v = &r.verdict;
            let ok = named(v).iter().any(|n| n == first)
                && v.finding.with().is_none()
                && v.possible_below_limit.iter().any(|e| e.id() == second)
                && r.pair.as_ref().is_some_and(|p| p.second_below_limit);
            println!(
                "{first} + {second} (seed {seed}): {} {:?}",
                v.id(),
                v.possible_below_limit
            );
            found.push(ok);
        }
    }
    assert!(found.iter().all(|&ok| ok), "{found:?}");
}

/// The pairs are tried side by side on the threads (src/gap/pairs.rs): the report of a
/// diagnosis on 3 threads is the one on 1, bit for bit (its JSON text), on parts of two effects
/// at 4× the limit where a pair is named and where none is (an effect and a look-alike).
/// Tolerance: none (each pair's numbers are its own; tried and accepted in the pairs' order).
#[test]
fn pairs_on_threads_are_the_pairs_on_one_thread() {
    use testpiece::gap::{diagnose_with, DiagnoseOptions};
    use testpiece::numerics::parallel::Threads;
    let parts = [
        [("backlash_c", 4.0), ("tool_radius", 4.0)],
        [("thermal_drift", 4.0), ("scale_x", 4.0)],
        [("tool_radius", 4.0), ("tool_taper", 4.0)],
    ];
    let mut paired = 0;
    for (k, effects) in parts.iter().enumerate() {
        let inp = input(part(effects, 700 + k as u64));
        let on = |threads: usize| {
            let opts = DiagnoseOptions {
                threads: Threads::new(threads),
                ..DiagnoseOptions::default()
            };
            diagnose_with(&inp, opts).unwrap()
        };
        let (one, three) = (on(1), on(3));
        paired += usize::from(one.pair.is_some());
        assert_eq!(
            serde_json::to_string(&one).unwrap(),
            serde_json::to_string(&three).unwrap(),
            "{effects:?}"
        );
    }
    // both paths taken: a pair named (the first two parts) and none (the look-alikes)
    assert!(
        (1..parts.len()).contains(&paired),
        "{paired} of {} parts paired: the test would not try both paths",
        parts.len()
    );
}
