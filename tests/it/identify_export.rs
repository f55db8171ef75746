//! Compensation-table export (ISO 230-1 names) and synthetic parts (`simulate`).
#![allow(clippy::needless_range_loop)] // index loops read like the maths here

use crate::identify_common::*;
use testpiece::assert_near;
use testpiece::identify::export::*;
use testpiece::identify::*;
use testpiece::simulate::*;

#[test]
fn iso_names() {
    let iso = |n: &str| iso_230_1_name(&n.parse().unwrap());
    assert_eq!(iso("EX0B"), "E_X0B");
    assert_eq!(iso("EC0Y"), "E_C0Y");
    assert_eq!(iso("dR"), "dR");
    assert_eq!(iso("EXX1"), "EXX1");
}

/// CSV and JSON carry every parameter with value, unit and status, and read back to the values.
#[test]
fn compensation_table_csv_and_json() {
    let d = design("paper").with_tool_radius().unwrap();
    let id = identify(
        &d,
        &observations("table4_paper.csv", "deviation"),
        &IdentifyOptions::default(),
    )
    .unwrap();
    let csv = compensation_csv(&id, "none");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "name,iso_230_1,value,unit,std,status,fitted_with");
    assert_eq!(lines.len(), 10);
    let ex = lines.iter().find(|l| l.starts_with("EX0B,")).unwrap();
    let f: Vec<&str> = ex.split(',').collect();
    assert_eq!(f[1], "E_X0B");
    assert_near!(f[2].parse::<f64>().unwrap(), 0.0294, 1e-12);
    assert_eq!(f[3], "mm");
    assert_eq!(f[5], "identified");
    let ea = lines.iter().find(|l| l.starts_with("EA0Z,")).unwrap();
    assert!(ea.ends_with(",rad,,not_separable,none"), "{ea}");
    let json: serde_json::Value = serde_json::from_str(&compensation_json(&id, "none")).unwrap();
    let arr = json.as_array().unwrap();
    assert_eq!(arr.len(), 9);
    assert_eq!(arr[8]["name"], "dR");
    assert_near!(arr[8]["value"].as_f64().unwrap(), -0.02, 1e-12);
    assert_eq!(arr[8]["unit"], "mm");
    assert_eq!(arr[8]["fitted_with"], "none");
}

/// The CLI JSON fields of cli.md are present, in design order.
#[test]
fn identification_json_fields() {
    let d = design("physical");
    let id = identify(
        &d,
        &observations("examples/example_clean.csv", "deviation"),
        &IdentifyOptions::default(),
    )
    .unwrap();
    let v: serde_json::Value = serde_json::to_value(&id).unwrap();
    for k in [
        "parameters",
        "groups",
        "rank",
        "condition",
        "residual",
        "points_used",
        "points_excluded",
    ] {
        assert!(v.get(k).is_some(), "missing {k}");
    }
    let ex = &v["parameters"]["EX0B"];
    assert!(ex["value"].is_f64() && ex["std"].is_f64());
    assert!(v["residual"]["rms"].is_f64() && v["residual"]["max_abs"].is_f64());
    let text = serde_json::to_string(&id).unwrap();
    assert!(text.find("\"EC0Y\"").unwrap() < text.find("\"EC0B\"").unwrap());
}

#[test]
fn parse_error_lists() {
    let v = parse_errors("EX0B=0.03, EA0B=3e-4").unwrap();
    assert_eq!(
        v,
        vec![("EX0B".to_string(), 0.03), ("EA0B".to_string(), 3e-4)]
    );
    assert!(parse_errors("").unwrap().is_empty());
    assert_eq!(
        parse_errors("EX0B=0.03,EA0B").unwrap_err().to_string(),
        "error list item 2 `EA0B`: expected NAME=value, e.g. EX0B=0.03"
    );
    assert!(matches!(
        parse_errors("EX0B=abc"),
        Err(SimulateError::BadValue { .. })
    ));
    assert!(matches!(
        parse_errors("EX0B=1,EX0B=2"),
        Err(SimulateError::Duplicate { .. })
    ));
}

/// Noise-free simulation is A·x; the seeded noise is reproducible, has the asked σ (100 samples:
/// within 30 %), and identifying the simulated part gives the errors back within 3 std.
#[test]
fn simulate_and_identify_back() {
    let d = design("physical");
    let errs = ids(&parse_errors("EX0B=0.03,EA0B=3e-4").unwrap());
    let clean = simulate_deviation(&d, &errs, 0.0, 7).unwrap();
    let x = d.vector_from(&errs).unwrap();
    assert_eq!(clean, d.predict(&x));
    let noisy = simulate_deviation(&d, &errs, 0.0015, 7).unwrap();
    assert_eq!(noisy, simulate_deviation(&d, &errs, 0.0015, 7).unwrap());
    assert_ne!(noisy, simulate_deviation(&d, &errs, 0.0015, 8).unwrap());
    let sd = (noisy
        .iter()
        .zip(&clean)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        / 100.0)
        .sqrt();
    assert!((sd / 0.0015 - 1.0).abs() < 0.3, "{sd}");
    let id = identify(&d, &Observations::plain(noisy), &IdentifyOptions::default()).unwrap();
    for (j, p) in id.parameters.0.iter().enumerate() {
        assert!(
            ((p.value - x[j]) / p.std.unwrap()).abs() < 3.0,
            "{}",
            p.name()
        );
    }
    // A name that is no parameter is refused where it comes in; one the design lacks, here.
    assert!("EZ9Q".parse::<testpiece::parameter::ParamId>().is_err());
    assert!(simulate_deviation(&d, &ids(&[("EY0C", 1.0)]), 0.0, 1).is_err());
    assert!(simulate_deviation(&d, &errs, -1.0, 1).is_err());
}

/// The built-in design is the sensitivity stage's matrix: equal to sensitivity_<mode>.csv
/// within 1e-6 of each column's largest value (tolerance SENSITIVITY_REL).
#[test]
fn builtin_design_matches_reference_sensitivity() {
    for mode in ["physical", "paper"] {
        let m = testpiece::sensitivity::Mode::parse(mode).unwrap();
        let d = builtin_design(m, testpiece::machine::Branch::Signed, false).unwrap();
        let r = design(mode);
        assert_eq!(d.names(), r.names());
        for j in 0..8 {
            let colmax = r.matrix().column(j).amax();
            for i in 0..100 {
                assert_near!(
                    d.matrix()[(i, j)],
                    r.matrix()[(i, j)],
                    testpiece::tolerance::SENSITIVITY_REL * colmax
                );
            }
        }
    }
}

/// The exact model gives table4_paper.csv's `machine_exact` (eq. 12) plus `tool_radius`, and its
/// finite-difference Jacobian at 0 is the analytic eq. 14 design (relative FD_REL·100: central
/// differences of a function evaluated to ~1e-16 mm with steps 1e-7 rad).
#[test]
fn exact_model_matches_table4_and_design() {
    use testpiece::identify::refine::ExactModel;
    use testpiece::{machine::Branch, sensitivity::Mode};
    let d = builtin_design(Mode::Paper, Branch::Signed, true).unwrap();
    let m = ExactDefectModel::new(&d, Mode::Paper, Branch::Signed).unwrap();
    let x = d
        .vector_from(&ids(
            &parse_errors("EX0B=0.0294,EA0B=3.2419e-4,dR=-0.02").unwrap()
        ))
        .unwrap();
    let f = m.deviation(&x).unwrap();
    let exact = column("table4_paper.csv", "machine_exact");
    for i in 0..100 {
        assert_near!(f[i], exact[i] + 0.02, 1e-9);
    }
    let j = m.jacobian(&[0.0; 9]).unwrap();
    for c in 0..9 {
        let colmax = d.matrix().column(c).amax();
        for i in 0..100 {
            assert_near!(
                j[(i, c)],
                d.matrix()[(i, c)],
                100.0 * testpiece::tolerance::FD_REL * colmax
            );
        }
    }
}
