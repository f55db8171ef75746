//! `testpiece sensitivity` (cli.md) against tests/data/reference/sensitivity_*.csv, and the
//! identifiability figures of spec s-shape.md (correlations and condition numbers).

use crate::cli_common::{testpiece, testpiece_ok};
use nalgebra::DMatrix;
use testpiece::machine::Branch;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::{sensitivity_matrix, Mode, SensitivityOptions};
use testpiece::tolerance::SENSITIVITY_REL;

fn table(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = text.lines();
    let h = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (h, rows)
}

#[test]
fn cli_matches_reference_in_both_modes_and_branches() {
    for (args, file) in [
        (vec![], "sensitivity_physical.csv"),
        (vec!["--mode", "paper"], "sensitivity_paper.csv"),
        (
            vec!["--mode", "paper", "--branch", "positive"],
            "sensitivity_paper_bpositive.csv",
        ),
        (
            vec!["--branch", "positive"],
            "sensitivity_physical_bpositive.csv",
        ),
    ] {
        let out = testpiece_ok(&[&["sensitivity"][..], &args[..]].concat());
        let (h1, a) = table(&out);
        let path = format!("{}/tests/data/reference/{file}", env!("CARGO_MANIFEST_DIR"));
        let (h2, b) = table(&std::fs::read_to_string(path).unwrap());
        assert_eq!(h1, h2);
        assert_eq!(a.len(), 100);
        for k in 2..10 {
            let col: Vec<f64> = b.iter().map(|r| r[k].parse().unwrap()).collect();
            let scale = col.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (ra, want) in a.iter().zip(&col) {
                let got: f64 = ra[k].parse().unwrap();
                assert!(
                    (got - want).abs() <= SENSITIVITY_REL * scale,
                    "{file} {}: {got} vs {want}",
                    h1[k]
                );
            }
        }
    }
    let (ok, _, stderr) = testpiece(&["sensitivity", "--mode", "wrong"]);
    assert!(!ok);
    assert!(stderr.contains("wrong"));
}

fn correlation(m: &DMatrix<f64>, i: usize, j: usize) -> f64 {
    let (a, b) = (m.column(i), m.column(j));
    a.dot(&b) / (a.norm() * b.norm())
}

fn condition(m: &DMatrix<f64>) -> f64 {
    let mut s = m.clone();
    for mut c in s.column_iter_mut() {
        let n = c.norm();
        c /= n;
    }
    let sv = s.svd(false, false).singular_values;
    sv.max() / sv.min()
}

#[test]
fn identifiability_figures_of_the_spec() {
    // s-shape.md: paper mode EA0Z/EA0C −0.9996, EB0Z/EB0C −0.9999, condition 323; physical mode
    // −0.76 and −0.82, condition 8.4 (columns scaled to unit norm; cosines of the columns).
    let part = SShape::iso();
    let pts = builtin_points(&part);
    for (mode, c_a, c_b, cond) in [
        (Mode::Paper, -0.9996, -0.9999, 323.0),
        (Mode::Physical, -0.76, -0.82, 8.4),
    ] {
        let opts = SensitivityOptions::default()
            .with_mode(mode)
            .with_branch(Branch::Signed);
        let m = sensitivity_matrix(
            &part,
            &pts,
            &testpiece::sensitivity::axis_values(&part, &pts, &opts).unwrap(),
            &opts,
            &testpiece::sensitivity::error_set::error_set(&opts.chain, opts.branch)
                .unwrap()
                .params(),
        )
        .unwrap()
        .values;
        let (ra, rb, k) = (correlation(&m, 1, 3), correlation(&m, 2, 4), condition(&m));
        eprintln!("{mode:?}: corr(EA0Z,EA0C) {ra:.5}, corr(EB0Z,EB0C) {rb:.5}, condition {k:.2}");
        assert!(
            (ra - c_a).abs() < 0.006 && (rb - c_b).abs() < 0.006,
            "{ra} {rb}"
        );
        assert!((k - cond).abs() / cond < 0.01, "condition {k}");
    }
}
