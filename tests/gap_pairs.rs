//! Two effects at once (src/gap/pairs.rs): parts simulated from the reference signatures
//! (`effect_signatures.csv`, baseline `sensitivity_physical.csv`) with random location errors,
//! two candidates each at 4× the detection limit (unabsorbed RMS = 4 · 2.5σ) and noise σ = 1.5 µm.
//! Without the pair step these parts were `unexplained` with the stronger effect as `partial`.
#![cfg(not(target_arch = "wasm32"))]
mod gap_common;
use gap_common::*;
use nalgebra::{DMatrix, DVector};
use testpiece::gap::diagnose;
use testpiece::gap::lsq::Factor;
use testpiece::gap::random::Sampler;

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
        let c = inp.candidates.iter().find(|c| c.id == *id).unwrap();
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
    let mut all = vec![v.effect.clone()];
    all.extend(v.equivalent.iter().cloned());
    all.extend(v.with.iter().cloned());
    all.extend(v.with_equivalent.iter().cloned());
    all
}

#[test]
fn two_effects_together_are_both_named() {
    let ids: Vec<String> = input(vec![0.0; 100])
        .candidates
        .iter()
        .map(|c| c.id.clone())
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
            let v = &r.verdict;
            let names = named(v);
            total += 1;
            if [a, b].iter().all(|p| names.contains(p)) {
                both += 1;
                assert_eq!(v.with.len(), 1);
                assert!(r
                    .summary
                    .lines()
                    .next()
                    .unwrap()
                    .contains(" together with "));
                // Both explained: what is left is the noise (σ = 1.5 µm) within 40 %.
                assert!(v.rms_after < 1.4 * SIGMA, "{a}+{b}: {}", v.rms_after);
            } else {
                println!(
                    "{a} + {b}: verdict {} with {:?} (equivalent {:?} / {:?})",
                    v.effect, v.with, v.equivalent, v.with_equivalent
                );
                if v.effect == "unexplained" || v.effect == "none" {
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
            r.verdict.with.is_empty(),
            "{id}: paired with {:?}",
            r.verdict.with
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
    assert_eq!(r.verdict.effect, "unexplained", "{}", r.summary);
}
