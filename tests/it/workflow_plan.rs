//! The measurement plan (issue 19, step 1) read back by the product itself:
//! - the plan's predicted std equals the std of the identification of a part measured at the
//!   plan's points (the same design, the same a priori σ) to 1e-9 relative;
//! - the DMIS program of `testpiece plan --dmis` parsed back gives `testpiece points` to 1e-6 mm
//!   (shared/spec/cli.md; `tolerance::POINTS_MM`).

use crate::cli_common;

use crate::cli_common::testpiece_ok;
use testpiece::analysis::{analyse, design_at, Session};
use testpiece::cmm::write::{canonical_csv, Precision};
use testpiece::identify::Status;
use testpiece::plan::{plan, read_dmis_points, PlanOptions};
use testpiece::tolerance::{PLAN_STD_REL as STD_REL, POINTS_MM};

/// A part measured at the points of a 13-per-curve plan with σ = 2 µm, deviations from known
/// errors plus a fixed ±1.5 µm pattern (the std does not depend on them: σ is a priori),
/// identified with `--sigma 0.002 --effects none`: every std and status as predicted.
#[test]
fn predicted_std_equals_the_identification_on_a_part_measured_with_the_plan() {
    for (per_curve, machine) in [
        ([13; 4], testpiece::settings::MachineChoice::Paper000),
        ([7, 9, 11, 13], testpiece::settings::MachineChoice::Paper002),
    ] {
        let opts = PlanOptions {
            per_curve,
            sigma: Some(0.002),
            machine,
            tool_radius: true,
            ..PlanOptions::default()
        };
        let prepared = opts.prepare().unwrap();
        let p = plan(&prepared, &opts).unwrap();
        let settings = testpiece::analysis::AnalysisOptions {
            keep_outliers: true,
            refine: false,
            ..opts.analysis(0.002)
        };
        let q = prepared.axis_values(&p.points).unwrap();
        let (design, _) = design_at(&prepared, &p.points, &q, &settings).unwrap();
        // The identification of the planned part on the same prepared settings.
        let session = Session::of(prepared);
        let truth: Vec<f64> = (0..design.cols())
            .map(|j| if j % 2 == 0 { 1e-5 } else { -2e-3 })
            .collect();
        let dev: Vec<f64> = design
            .predict(&truth)
            .iter()
            .enumerate()
            .map(|(i, d)| d + 0.0015 * (i as f64 * 1.7).sin())
            .collect();
        let csv = canonical_csv(p.points.iter().zip(dev), Precision::Shortest, None);
        let a = analyse(&session, csv.as_bytes(), "planned.csv", &settings).unwrap();
        assert_eq!(a.points.len(), p.points.len());
        let id = &a.identification;
        assert_eq!(
            id.names(),
            p.parameters
                .0
                .iter()
                .map(|(n, _)| n.clone())
                .collect::<Vec<_>>()
        );
        let mut compared = 0;
        for (name, pred) in &p.parameters.0 {
            let got = id.parameters.get(name).unwrap();
            assert_eq!(got.status, pred.status, "{name}");
            assert_eq!(got.unit(), pred.id.unit(), "{name}");
            match (got.std, pred.std) {
                (Some(s), Some(q)) => {
                    assert!(
                        ((s - q) / q).abs() <= STD_REL,
                        "{name}: identified std {s:e}, predicted {q:e}"
                    );
                    compared += 1;
                }
                (None, None) => assert_eq!(pred.status, Status::NotSeparable),
                other => panic!("{name}: {other:?}"),
            }
        }
        assert!(compared >= 5, "{compared} stds compared");
        assert_eq!(id.groups.len(), p.groups.len());
    }
}

/// `testpiece plan --dmis FILE` read back: 100 features, each with its measurement, at the
/// positions and normals of `testpiece points` (1e-6 mm, 1e-6 on the unit vectors), labels
/// `P<id>_<curve>`.
#[test]
fn dmis_points_equal_testpiece_points() {
    let dir = std::env::temp_dir().join(format!("testpiece-plan-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let dmis = dir.join("plan.dms");
    let csv = dir.join("plan.csv");
    testpiece_ok(&[
        "plan",
        "--dmis",
        dmis.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&dmis).unwrap();
    assert!(text.starts_with("DMISMN/"), "{}", &text[..80]);
    assert!(text.trim_end().ends_with("ENDFIL"));
    let read = read_dmis_points(&text).unwrap();
    let points = testpiece_ok(&["points"]);
    let rows: Vec<Vec<String>> = points
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    assert_eq!(read.len(), 100);
    assert_eq!(rows.len(), 100);
    for (d, r) in read.iter().zip(&rows) {
        assert_eq!(d.label, format!("P{}_{}", r[0], r[1]));
        let f = |k: usize| r[k].parse::<f64>().unwrap();
        let (xyz, n) = ([f(4), f(5), f(6)], [f(7), f(8), f(9)]);
        for k in 0..3 {
            assert!(
                (d.nominal[k] - xyz[k]).abs() <= POINTS_MM,
                "{} {k}",
                d.label
            );
            assert!((d.touch[k] - xyz[k]).abs() <= POINTS_MM, "{} {k}", d.label);
            assert!((d.normal[k] - n[k]).abs() <= 1e-6, "{} {k}", d.label);
            assert!((d.approach[k] - n[k]).abs() <= 1e-6, "{} {k}", d.label);
        }
    }
    let table = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(table.lines().next(), Some("id,curve,x,y,z,nx,ny,nz"));
    assert_eq!(table.lines().count(), 101);
    std::fs::remove_dir_all(&dir).ok();
}

/// The JSON of cli.md: `points`, `parameters` `{NAME: {std, status}}`, `groups`,
/// `detection_limits` `{effect id: {parameter: size}}`; more points, smaller std (√(25/50) for
/// twice the points on the same arcs, within 5 %: the layout is not exactly nested).
#[test]
fn json_fields_and_the_effect_of_more_points() {
    let v: serde_json::Value =
        serde_json::from_str(&testpiece_ok(&["plan", "--sigma", "0.002", "--json"])).unwrap();
    assert_eq!(v["points"].as_array().unwrap().len(), 100);
    assert!(v["parameters"]["EX0B"]["std"].as_f64().unwrap() > 0.0);
    assert_eq!(v["parameters"]["EA0B"]["status"], "identified");
    assert!(v["groups"].is_array());
    assert!(v["detection_limits"]["backlash_c"]["b"].as_f64().unwrap() > 0.0);
    assert!(v["detection_limits"]["tool_taper"]["g"].as_f64().unwrap() > 0.0);
    let w: serde_json::Value = serde_json::from_str(&testpiece_ok(&[
        "plan",
        "--sigma",
        "0.002",
        "--per-curve",
        "50",
        "--json",
    ]))
    .unwrap();
    let r = w["parameters"]["EX0B"]["std"].as_f64().unwrap()
        / v["parameters"]["EX0B"]["std"].as_f64().unwrap();
    assert!(
        (r - 0.5f64.sqrt()).abs() < 0.05 * 0.5f64.sqrt(),
        "ratio {r}"
    );
    let (ok, _, err) = cli_common::testpiece(&["plan", "--points", "2"]);
    assert!(!ok);
    assert!(err.contains("2 points in all: expected 4 to 4000"), "{err}");
    let (ok, _, err) = cli_common::testpiece(&["plan", "--sigma", "0.002", "--mpe", "3,75"]);
    assert!(!ok && err.contains("both give the CMM noise"), "{err}");
}
