//! The gap diagnosis on the machine the analysis identifies (`analysis::diagnose_on_machine`):
//! paper 002's B-C tilting table gets its own location errors as the baseline and its own axes
//! for the backlash, scale and reversal candidates; paper 001's A-B head is diagnosed on its own
//! chain, with the candidates whose physics it has (`backlash_a`, `a_index`; no C axis).

use crate::cli_common::{testpiece, testpiece_ok};
use crate::edge_common::*;
use testpiece::analysis::{
    analyse_once, diagnose_on_machine, prepare, AnalysisOptions, Diagnosis, PointsModel,
};
use testpiece::effects::builtin::PartModel;
use testpiece::effects::prepared::Prepared;
use testpiece::gap::verdict::VerdictId;
use testpiece::identify::solve::{rms, Factor};
use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::AxisName;
use testpiece::numerics::random::Sampler;
use testpiece::parameter::Effect;
use testpiece::part::SShape;
use testpiece::sensitivity::SensitivityOptions;
use testpiece::settings::MachineChoice;

fn options(machine: MachineChoice) -> AnalysisOptions {
    AnalysisOptions {
        machine,
        ..AnalysisOptions::default()
    }
}

/// example_clean.csv analysed on `machine`.
fn analyse_clean(machine: MachineChoice) -> testpiece::analysis::Analysis {
    let bytes = data("reference/examples/example_clean.csv");
    analyse_once(&bytes, "clean.csv", &options(machine)).unwrap()
}

fn prepared(machine: MachineChoice) -> Prepared {
    let sopts = SensitivityOptions::default().with_chain(machine.chain(PAPER000_L0));
    Prepared::new(SShape::iso(), sopts).unwrap()
}

fn model_of(machine: MachineChoice) -> PartModel {
    let p = prepared(machine);
    p.part_model(&builtin(), &p.axis_values(&builtin()).unwrap())
        .unwrap()
}

/// Every candidate with physics on the machine, the location equivalents included.
fn every_candidate(machine: MachineChoice) -> PartModel {
    prepared(machine).builtin_model().clone()
}

/// The diagnosis of deviations `y` at the built-in points on `machine`.
fn diagnose_builtin(y: &[f64], machine: MachineChoice) -> Diagnosis {
    let o = options(machine);
    let p = prepare(&o).unwrap();
    diagnose_on_machine(&p, &PointsModel::new(&p, &builtin()), y, &o)
}

fn column(m: &PartModel, effect: Effect) -> Vec<f64> {
    let c = m.candidates.iter().find(|c| c.effect == effect).unwrap();
    c.signature.matrix.column(0).iter().copied().collect()
}

/// The tilting table's baseline is the location errors its identification uses (same names).
/// Its candidates are its own where the machine matters and paper 000's where it does not:
/// - the geometric and process effects (tool, overcut, setup) and the axes whose motion is the
///   same on both machines (Y, C) are bit for bit paper 000's;
/// - `c_index` is the negative of paper 000's: the primed C' turns the table the other way;
/// - backlash of B differs by more than its own size (B tilts the part, not the tool), and
///   backlash / scale of X differ;
/// - backlash and scale of Z, and the thermal drift along machine Z, are exactly zero: the tool
///   stays vertical, Z moves along the tool axis, which lies in the flank-milled wall
///   (`INVISIBLE_SIGNATURE`);
/// - `pivot_length` is not offered: the tool has no pivot (its B axis's height is EZ0B).
#[test]
fn the_tilting_table_model_is_its_own() {
    // c_index is not offered there (it is -0.976 EC0B on the part), but its formula is checked.
    assert!(model_of(MachineChoice::Paper002)
        .candidates
        .iter()
        .all(|c| c.effect != Effect::CIndex));
    let tilt = every_candidate(MachineChoice::Paper002);
    let a = analyse_clean(MachineChoice::Paper002);
    assert_eq!(tilt.baseline.names(), a.identification.names());
    let p000 = model_of(MachineChoice::Paper000);
    assert!(tilt
        .candidates
        .iter()
        .all(|c| c.effect != Effect::PivotLength));
    for c in p000
        .candidates
        .iter()
        .filter(|c| c.effect != Effect::PivotLength)
    {
        let own = column(&tilt, c.effect);
        let other = column(&p000, c.effect);
        let diff: Vec<f64> = own.iter().zip(&other).map(|(a, b)| a - b).collect();
        let (r_own, r_other, r_diff) = (rms(&own), rms(&other), rms(&diff));
        println!(
            "{}: rms {r_own:.3e} (tilting table), {r_other:.3e} (paper 000), difference {r_diff:.3e}",
            c.effect
        );
        match c.effect.id() {
            "backlash_b" | "backlash_x" | "scale_x" => {
                assert!(r_diff > 0.5 * r_other.min(r_own), "{}", c.effect)
            }
            "backlash_z" | "scale_z" | "thermal_drift" => {
                assert!(own.iter().all(|v| *v == 0.0), "{}", c.effect)
            }
            "c_index" => assert!(own.iter().zip(&other).all(|(a, b)| *a == -b)),
            "backlash_c" | "scale_y" => assert!(r_diff <= 1e-12 * r_other, "{}", c.effect),
            // the servo columns follow each machine's own axis rates (the tilting table's Z moves
            // along the tool axis, in the walls: its column is zero or rounding there)
            id if id.starts_with("servo_") => {
                assert!(own.iter().all(|v| v.is_finite()), "{}", c.effect)
            }
            _ => assert_eq!(own, other, "{}", c.effect),
        }
    }
}

/// A simulated tilting-table part: the machine's own location errors (1e-4 rad, 0.01 mm) plus
/// a backlash of its C axis whose visible (unabsorbed) part is 4× the detection limit 2.5σ,
/// plus N(0, σ²) noise with σ = 1.5 µm. Diagnosed on the tilting table, the verdict is
/// `backlash_c` or a candidate this part cannot tell from it.
#[test]
fn a_tilting_table_part_is_diagnosed_on_its_own_axes() {
    let m = model_of(MachineChoice::Paper002);
    let sigma = 0.0015;
    let backlash_c = Effect::Backlash(AxisName::C);
    let sig = column(&m, backlash_c);
    let base = Factor::new(&m.baseline.matrix, None);
    let sig_m = nalgebra::DMatrix::from_column_slice(sig.len(), 1, &sig);
    let visible: Vec<f64> = base.unabsorbed(&sig_m).iter().copied().collect();
    let b = 4.0 * 2.5 * sigma / rms(&visible);
    let mut rng = Sampler::new(3);
    let x: Vec<f64> = m
        .baseline
        .names()
        .iter()
        .map(|n| if n == "EX0B" { 0.01 } else { 1e-4 } * rng.sign())
        .collect();
    let y: Vec<f64> = (0..sig.len())
        .map(|i| {
            let loc: f64 = (0..x.len()).map(|j| m.baseline.matrix[(i, j)] * x[j]).sum();
            loc + b * sig[i] + sigma * rng.normal()
        })
        .collect();
    let d = diagnose_builtin(&y, MachineChoice::Paper002)
        .into_report()
        .unwrap();
    println!("b = {b:.3e} rad\n{}", d.summary);
    let v = &d.verdict;
    assert!(
        v.id() == VerdictId::Effect(backlash_c) || v.finding.equivalent().contains(&backlash_c),
        "{}",
        d.summary
    );
}

/// Paper 001's A-B head is diagnosed on its own chain: no machine substitution in the summary,
/// its own baseline, no C-axis candidate; a backlash of its A axis is named.
#[test]
fn the_a_b_head_is_diagnosed_on_its_own_chain() {
    let a = analyse_clean(MachineChoice::Paper001);
    let d = a.diagnosis.into_report().unwrap();
    assert!(!d.summary.contains("Machine:"), "{}", d.summary);
    let m = model_of(MachineChoice::Paper001);
    assert_eq!(m.baseline.names(), a.identification.names());
    assert!(m
        .candidates
        .iter()
        .all(|c| c.effect.axis() != Some(AxisName::C) && c.effect != Effect::CIndex));
    // A backlash of A at 4× the detection limit, on the machine's own errors and noise.
    let sigma = 0.0015;
    let backlash_a = Effect::Backlash(AxisName::A);
    let sig = column(&m, backlash_a);
    let base = Factor::new(&m.baseline.matrix, None);
    let sig_m = nalgebra::DMatrix::from_column_slice(sig.len(), 1, &sig);
    let visible: Vec<f64> = base.unabsorbed(&sig_m).iter().copied().collect();
    let b = 4.0 * 2.5 * sigma / rms(&visible);
    let mut rng = Sampler::new(5);
    let y: Vec<f64> = (0..sig.len())
        .map(|i| {
            let loc: f64 = (0..m.baseline.names().len())
                .map(|j| m.baseline.matrix[(i, j)] * 1e-4 * if j % 2 == 0 { 1.0 } else { -1.0 })
                .sum();
            loc + b * sig[i] + sigma * rng.normal()
        })
        .collect();
    let d = diagnose_builtin(&y, MachineChoice::Paper001)
        .into_report()
        .unwrap();
    println!("b = {b:.3e} rad\n{}", d.summary);
    let v = &d.verdict;
    assert!(
        v.id() == VerdictId::Effect(backlash_a) || v.finding.equivalent().contains(&backlash_a),
        "{}",
        d.summary
    );
}

/// The CLI: `diagnose --machine` gives the analysis' diagnosis on that machine (the same
/// verdict line as `analyse`), and an unknown machine is refused with the accepted values.
#[test]
fn the_cli_diagnoses_on_the_chosen_machine() {
    let file = format!(
        "{}/tests/data/reference/examples/example_backlash_c.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    for (m, choice) in [
        ("paper000", MachineChoice::Paper000),
        ("paper002", MachineChoice::Paper002),
        ("paper001", MachineChoice::Paper001),
    ] {
        let out = testpiece_ok(&["diagnose", &file, "--machine", m]);
        let text = std::fs::read(&file).unwrap();
        let a = analyse_once(&text, "b.csv", &options(choice)).unwrap();
        let d = a.diagnosis.clone().into_report().unwrap();
        assert_eq!(out.lines().next(), d.summary.lines().next(), "{m}");
        let lines: Vec<&str> = out.lines().collect();
        // the summary, then one line on the corrected identification (issue 17)
        assert_eq!(
            lines[lines.len() - 2],
            d.summary.lines().last().unwrap(),
            "{m}"
        );
        assert_eq!(
            lines[lines.len() - 1],
            format!("Corrected: {}", a.correction.summary),
            "{m}"
        );
    }
    let (ok, _, err) = testpiece(&["diagnose", &file, "--machine", "paper9"]);
    assert!(!ok);
    assert!(
        err.contains("--machine `paper9`: expected paper000, paper001 or paper002"),
        "{err}"
    );
}

/// `simulate --effect` adds `value × signature` of effects.md (the columns `part_model` gives the
/// diagnosis) to the simulated deviation, to rounding (the CSV holds the shortest round-trip
/// decimal of each value: 1e-15 mm), and `diagnose` names a simulated backlash of C.
#[test]
fn simulate_adds_an_effects_signature_that_diagnose_names() {
    let deviations = |csv: &str| -> Vec<f64> {
        csv.lines()
            .skip(1)
            .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
            .collect()
    };
    let base = ["simulate", "--errors", "EX0B=0.01,EA0B=1e-4", "--seed", "3"];
    let plain = deviations(&testpiece_ok(&base));
    let with: Vec<&str> = base
        .iter()
        .copied()
        .chain(["--effect", "backlash_c=6e-4,tool_taper.g=2e-4"])
        .collect();
    let both = deviations(&testpiece_ok(&with));
    let m = model_of(MachineChoice::Paper000);
    let sig = |e: Effect, j: usize| -> Vec<f64> {
        let c = m.candidates.iter().find(|c| c.effect == e).unwrap();
        c.signature.matrix.column(j).iter().copied().collect()
    };
    let (c, g) = (
        sig(Effect::Backlash(AxisName::C), 0),
        sig(Effect::ToolTaper, 1),
    );
    for i in 0..100 {
        let want = 6e-4 * c[i] + 2e-4 * g[i];
        assert!(
            (both[i] - plain[i] - want).abs() < 1e-15,
            "point {}: {} vs {want}",
            i + 1,
            both[i] - plain[i]
        );
    }
    let noisy: Vec<&str> = with[..5]
        .iter()
        .copied()
        .chain(["--effect", "backlash_c=6e-4", "--noise", "0.0015"])
        .collect();
    let path = std::env::temp_dir().join(format!("tp-sim-effect-{}.csv", std::process::id()));
    std::fs::write(&path, testpiece_ok(&noisy)).unwrap();
    let verdict = testpiece_ok(&["diagnose", path.to_str().unwrap()]);
    std::fs::remove_file(&path).ok();
    assert!(
        verdict.starts_with("Verdict: backlash of the C axis (`backlash_c`)"),
        "{verdict}"
    );
    let (ok, _, err) = testpiece(&[
        "simulate",
        "--errors",
        "EX0B=0.01",
        "--effect",
        "setup_error=1e-4",
    ]);
    assert!(
        !ok && err.contains("write `setup_error.<parameter>`"),
        "{err}"
    );
}
