//! What a real lab sends (issue 18 items 2, 3, 5 and 7): repeat measurements (σ from their
//! differences), an implausible noise estimate, other point layouts, and the per-condition floors
//! of `testpiece validate --conditions` on a fixed seed.

use crate::cli_common;

use testpiece::analysis::{analyse_once, analyse_repeats, AnalysisOptions, Diagnosis, Session};
use testpiece::part::{builtin_points, SShape};
use testpiece::validate::conditions::layout_points;
use testpiece::validate::{exact_machine_part, run_conditions, ValidationModel, CONDITIONS};

/// A simulated part (canonical CSV) of the CLI, `testpiece simulate ARGS`.
fn simulate(args: &[&str]) -> String {
    cli_common::testpiece_ok(&[&["simulate"], args].concat())
}

const ERRORS: &str = "EX0B=0.02,EA0B=2e-4,EB0C=1e-4,EC0Y=-1e-4";

/// The repeats `texts` (a.csv, b.csv, ...) analysed together with the default options.
fn analyse_texts(texts: &[String]) -> testpiece::analysis::Analysis {
    let names = ["a.csv", "b.csv", "c.csv", "d.csv", "e.csv"];
    let files: Vec<(&[u8], &str)> = texts
        .iter()
        .zip(names)
        .map(|(p, n)| (p.as_bytes(), n))
        .collect();
    let o = AnalysisOptions::default();
    analyse_repeats(&Session::new(&o).unwrap(), &files, &o).unwrap()
}

fn verdict(a: &testpiece::analysis::Analysis) -> String {
    match &a.diagnosis {
        Diagnosis::Made { report, .. } => report.verdict.id().to_string(),
        Diagnosis::NotMade { reason } => panic!("not diagnosed: {reason}"),
    }
}

/// Three measurements of one part (the same errors and backlash, noise σ = 1.5 µm from three
/// seeds): σ is the pure error of their differences, within its sampling error (200 dof:
/// ±5 % a standard deviation; 20 % = 4 sd), the mean's σ is that over √3, and the diagnosis
/// names the backlash with σ given by the repeats.
#[test]
fn repeats_give_sigma_from_their_differences() {
    let parts: Vec<String> = ["3", "4", "5"]
        .iter()
        .map(|seed| {
            simulate(&[
                "--errors",
                ERRORS,
                "--effect",
                "backlash_c=4e-4",
                "--noise",
                "0.0015",
                "--seed",
                seed,
            ])
        })
        .collect();
    let a = analyse_texts(&parts);
    let r = a.repeat.as_ref().expect("a repeat report");
    assert_eq!((r.pure_error.repeats, r.pure_error.dof), (3, 200));
    assert!(
        (r.pure_error.sigma / 0.0015 - 1.0).abs() < 0.2,
        "{}",
        r.pure_error.sigma
    );
    assert_eq!(a.noise.source, testpiece::settings::NoiseKind::Repeat);
    assert_eq!(a.noise.sigma, Some(r.pure_error.sigma / 3f64.sqrt()));
    // the backlash leaves structure: lack of fit of the location errors alone
    assert!(r.lack_of_fit.p_value < 1e-6, "{:?}", r.lack_of_fit);
    assert_eq!(verdict(&a), "backlash_c");
    // a clean part measured twice: no lack of fit at the 1 % level, verdict none
    let clean: Vec<String> = ["6", "7"]
        .iter()
        .map(|seed| simulate(&["--errors", ERRORS, "--noise", "0.0015", "--seed", seed]))
        .collect();
    let a = analyse_texts(&clean);
    assert!(a.repeat.as_ref().unwrap().lack_of_fit.p_value > 0.01);
    assert_eq!(verdict(&a), "none");
}

/// The same part measured three times: re-probing repeats the part's own point-to-point scatter
/// (1.5 µm, its roughness and local form) and resamples only the CMM's (0.5 µm). The pure error
/// sees the CMM alone and the lack of fit against it rejects; the diagnosis adds the part's
/// scatter to the CMM's floor and calls the part noise, keeps its points, and σ is the total
/// (√(1.5² + 0.5²/3) = 1.53 µm) within 4 of its relative standard errors (≈ 0.13, dof ≈ 30).
/// Issue 29: before, this part was `unexplained` with three ordinary points thrown out.
#[test]
fn repeats_of_a_scattered_part_add_its_scatter_to_the_cmm() {
    use testpiece::numerics::random::Sampler;
    let (mut none, mut named) = (0, 0);
    let parts = 10;
    for seed in 0..parts {
        // the part: machine errors and 1.5 µm of its own scatter, fixed for this part
        let part = simulate(&[
            "--errors",
            ERRORS,
            "--noise",
            "0.0015",
            "--seed",
            &(20 + seed).to_string(),
        ]);
        let mut rng = Sampler::new(100 + seed);
        let measured: Vec<String> = (0..3)
            .map(|_| {
                let mut out = String::new();
                for (k, line) in part.lines().enumerate() {
                    if k == 0 {
                        out += line;
                    } else {
                        // the last column is the deviation (mm)
                        let (head, dev) = line.rsplit_once(',').unwrap();
                        let d: f64 = dev.parse().unwrap();
                        out += &format!("{head},{:.6}", d + 0.0005 * rng.normal());
                    }
                    out.push('\n');
                }
                out
            })
            .collect();
        let a = analyse_texts(&measured);
        let r = a.repeat.as_ref().unwrap();
        assert!(r.pure_error.sigma < 0.0008, "{}", r.pure_error.sigma);
        assert!(r.lack_of_fit.p_value < 1e-6, "{:?}", r.lack_of_fit);
        let Diagnosis::Made { report, .. } = &a.diagnosis else {
            panic!()
        };
        let n = &report.structure.noise;
        let total = (0.0015f64.powi(2) + 0.0005f64.powi(2) / 3.0).sqrt();
        assert!(n.part_scatter.is_some(), "{n:?}");
        assert!((n.used / total - 1.0).abs() < 0.5, "{n:?}");
        named += a.outliers.test.as_ref().map_or(0, |t| t.points.len());
        none += usize::from(verdict(&a) == "none");
    }
    // clean parts are `none` at least 95 % of the time (validate): 9 of 10 here; the outlier
    // test's family-wise α is 5 % a part (0.5 points expected over 10 parts), against a σ that
    // holds the part's scatter: at most 2
    assert!(none >= 9, "{none}/{parts}");
    assert!(named <= 2, "{named} points named over {parts} parts");
}

#[test]
fn repeats_on_the_command_line_and_their_refusals() {
    let dir = std::env::temp_dir().join(format!("testpiece-repeat-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_string_lossy().into_owned()
    };
    let a = write(
        "a.csv",
        &simulate(&["--errors", ERRORS, "--noise", "0.0015", "--seed", "8"]),
    );
    let b_text = simulate(&["--errors", ERRORS, "--noise", "0.0015", "--seed", "9"]);
    let b = write("b.csv", &b_text);
    for cmd in ["diagnose", "identify"] {
        let out = cli_common::testpiece_ok(&[cmd, &a, "--repeat", &b, "--json"]);
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["noise"]["source"], "repeat", "{cmd}");
        assert_eq!(v["repeat"]["pure_error"]["dof"], 100, "{cmd}");
        assert!(v["repeat"]["lack_of_fit"]["p_value"].as_f64().is_some());
    }
    let text = cli_common::testpiece_ok(&["diagnose", &a, "--repeat", &b]);
    assert!(text.contains("from 2 repeat measurements"), "{text}");
    // a point missing from the repeat is named
    let short: String = b_text
        .lines()
        .filter(|l| !l.starts_with("37,"))
        .map(|l| format!("{l}\n"))
        .collect();
    let c = write("c.csv", &short);
    let (ok, _, err) = cli_common::testpiece(&["diagnose", &a, "--repeat", &c]);
    assert!(!ok && err.contains("c.csv") && err.contains("37"), "{err}");
    // σ twice
    let (ok, _, err) = cli_common::testpiece(&["identify", &a, "--repeat", &b, "--sigma", "0.001"]);
    assert!(!ok && err.contains("given twice"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// σ̂ above what a CMM and a finished flank give (3 µm without a CMM figure,
/// `measurement::noise::PLAUSIBLE_CMM_SIGMA_MM`) is structure, never noise: white noise of
/// σ = 5 µm is `unexplained`, and the report asks for the CMM's figure. With that figure given
/// (5 µm: a coarse CMM), the bound is √(5² + 2.5²) µm and the same part is noise; 1.5 µm of noise
/// is noise without any figure.
#[test]
fn an_implausible_sigma_is_questioned() {
    use testpiece::gap::verdict::VerdictId;
    let noisy = simulate(&["--errors", ERRORS, "--noise", "0.005", "--seed", "3"]);
    let a = analyse_once(noisy.as_bytes(), "noisy.csv", &AnalysisOptions::default()).unwrap();
    let Diagnosis::Made { report, .. } = &a.diagnosis else {
        panic!()
    };
    let n = &report.structure.noise;
    // σ̂ within 4 of its relative standard errors (1/√(2·dof), dof ≈ 70) of 5 µm
    assert!((n.estimated / 0.005 - 1.0).abs() < 0.35, "{}", n.estimated);
    assert!(n.implausible && n.used == 0.003, "{n:?}");
    assert_eq!(
        report.verdict.id(),
        VerdictId::Unexplained,
        "{}",
        report.summary
    );
    assert!(report.summary.contains("--sigma"), "{}", report.summary);
    let given = AnalysisOptions {
        noise_sigma: Some(0.005),
        ..AnalysisOptions::default()
    };
    let a = analyse_once(noisy.as_bytes(), "noisy.csv", &given).unwrap();
    let Diagnosis::Made { report, .. } = &a.diagnosis else {
        panic!()
    };
    assert!(!report.structure.noise.implausible, "{}", report.summary);
    assert_eq!(report.verdict.id(), VerdictId::Noise, "{}", report.summary);
    let clean = simulate(&["--errors", ERRORS, "--noise", "0.0015", "--seed", "3"]);
    let a = analyse_once(clean.as_bytes(), "clean.csv", &AnalysisOptions::default()).unwrap();
    let Diagnosis::Made { report, .. } = &a.diagnosis else {
        panic!()
    };
    assert!(!report.structure.noise.implausible, "{}", report.summary);
    assert!(!report.summary.contains("--sigma"), "{}", report.summary);
}

/// Rows in any order, ids not 1-100, a third of the points, a curve not measured: diagnosed,
/// and the layout says what it limits.
#[test]
fn other_layouts_are_diagnosed_and_described() {
    let full = simulate(&["--errors", ERRORS, "--noise", "0.0015", "--seed", "5"]);
    let lines: Vec<&str> = full.lines().collect();
    let (header, rows) = (lines[0], &lines[1..]);
    // every third point, ids + 1000, rows reversed
    let mut every_third: Vec<String> = rows
        .iter()
        .step_by(3)
        .map(|l| {
            let (id, rest) = l.split_once(',').unwrap();
            format!("{},{rest}", id.parse::<u32>().unwrap() + 1000)
        })
        .collect();
    every_third.reverse();
    let text = format!("{header}\n{}\n", every_third.join("\n"));
    let a = analyse_once(text.as_bytes(), "third.csv", &AnalysisOptions::default()).unwrap();
    let Diagnosis::Made { report, .. } = &a.diagnosis else {
        panic!()
    };
    assert_eq!(report.layout.points, 34);
    assert!(!report.layout.full);
    assert!(report.layout.curves.iter().all(|c| c.smooth_degree == 3));
    assert!(
        report.summary.contains("Layout: 34 points"),
        "{}",
        report.summary
    );
    assert_eq!(report.verdict.id().to_string(), "none");
    // without curve B_Z25
    let three: Vec<&str> = rows
        .iter()
        .copied()
        .filter(|l| !l.contains("B_Z25"))
        .collect();
    let text = format!("{header}\n{}\n", three.join("\n"));
    let a = analyse_once(text.as_bytes(), "three.csv", &AnalysisOptions::default()).unwrap();
    let Diagnosis::Made { report, .. } = &a.diagnosis else {
        panic!()
    };
    assert_eq!(report.layout.not_measured, vec!["B_Z25".to_string()]);
    // the built-in layout is full and says nothing
    let a = analyse_once(full.as_bytes(), "full.csv", &AnalysisOptions::default()).unwrap();
    let Diagnosis::Made { report, .. } = &a.diagnosis else {
        panic!()
    };
    assert!(report.layout.full && !report.summary.contains("Layout:"));
}

/// `validate --conditions` on seed 1 (the seed the methods were chosen on), 60 parts per
/// condition: floors below the 418-part figures of the note (seed 1: 93.8-98.6 % per
/// condition except pairs, 75.4 %), leaving room for the sampling error of 60 parts (±3 %).
#[test]
fn conditions_hold_their_floors_on_a_fixed_seed() {
    let part = SShape::iso();
    let model = ValidationModel::at(&part, &builtin_points(&part)).unwrap();
    let exact = exact_machine_part(&model.baseline.params).unwrap();
    // every condition but pairs (tests/it/gap_pairs.rs has their floor)
    let which: Vec<&str> = CONDITIONS.into_iter().filter(|c| *c != "pairs").collect();
    let r = run_conditions(&part, &model, exact.as_ref(), &which, 60, 1).unwrap();
    assert_eq!(r.rows.len(), which.len());
    for row in &r.rows {
        assert_eq!(row.cases, 60, "{}", row.condition);
        assert!(row.rate >= 0.85, "{}: {:.3}", row.condition, row.rate);
    }
    let spikes = r.rows.iter().find(|w| w.condition == "spikes").unwrap();
    let (named, of) = spikes.none_spike_named.unwrap();
    // 33/34 before issue 30, 25/28 after: the seed's parts are drawn from the new catalogue, and
    // the 3 misses are verdicts, not spikes (a scale_y at 0.99x the limit named; a servo_lag_x at
    // 0.77x and a servo_common at 0.92x, whose peaked signatures the structure test sees, called
    // `unexplained`): every spike was named. Floor 0.85 (was 0.9).
    assert!(named as f64 >= 0.85 * of as f64, "{named}/{of}");
    assert!(
        r.overall.0 as f64 >= 0.92 * r.overall.1 as f64,
        "{:?}",
        r.overall
    );
}

#[test]
fn layout_points_leave_curves_out_in_order() {
    let part = SShape::iso();
    let p = layout_points(&part, 8, 3);
    assert_eq!(p.len(), 24);
    assert!(p.iter().all(|q| q.curve.name() != "B_Z25"));
    assert_eq!(p.last().unwrap().id, 24);
}
