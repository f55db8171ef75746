//! The CLI contract of `shared/spec/cli.md` for `testpiece points` and `testpiece envelope
//! [--surface-max]`: the printed CSV matches the reference vectors (tests/data/reference/, an
//! independent implementation) within the tolerances of `testpiece::tolerance`.

use crate::cli_common::{testpiece, testpiece_ok};
use testpiece::tolerance::{ENVELOPE_MM, POINTS_MM, SURFACE_MAX_MM};

fn run(args: &[&str]) -> Vec<csv::StringRecord> {
    let out = testpiece_ok(args);
    csv::Reader::from_reader(out.as_bytes())
        .records()
        .map(Result::unwrap)
        .collect()
}

fn reference(name: &str) -> (csv::StringRecord, Vec<csv::StringRecord>) {
    let path = format!("{}/tests/data/reference/{name}", env!("CARGO_MANIFEST_DIR"));
    let mut r = csv::Reader::from_path(path).unwrap();
    let header = r.headers().unwrap().clone();
    (header, r.records().map(Result::unwrap).collect())
}

/// Largest difference over the numeric columns; text columns must be equal.
fn max_diff(got: &[csv::StringRecord], want: &[csv::StringRecord]) -> f64 {
    assert_eq!(got.len(), want.len());
    let mut worst: f64 = 0.0;
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.len(), w.len());
        for (a, b) in g.iter().zip(w) {
            match (a.parse::<f64>(), b.parse::<f64>()) {
                (Ok(x), Ok(y)) => worst = worst.max((x - y).abs()),
                _ => assert_eq!(a, b),
            }
        }
    }
    worst
}

#[test]
fn points_command_matches_points_csv() {
    let (_, want) = reference("points.csv");
    let d = max_diff(&run(&["points"]), &want);
    println!("testpiece points vs points.csv: max |diff| = {d:e}");
    assert!(d <= POINTS_MM);
}

#[test]
fn envelope_command_matches_envelope_csv() {
    let (_, want) = reference("envelope.csv");
    let d = max_diff(&run(&["envelope"]), &want);
    println!("testpiece envelope vs envelope.csv: max |diff| = {d:e}");
    assert!(d <= ENVELOPE_MM);
}

#[test]
fn surface_max_command_matches_envelope_surface_max_csv() {
    let (_, want) = reference("envelope_surface_max.csv");
    let got = run(&["envelope", "--surface-max"]);
    // the maximum overcut to 1e-4 mm; its location to 1e-3 in u and 0.5 mm in z
    for (g, w) in got.iter().zip(&want) {
        assert_eq!(&g[0], &w[0]);
        let f = |r: &csv::StringRecord, i: usize| r[i].parse::<f64>().unwrap();
        println!(
            "surface {}: max_overcut diff {:e}, u diff {:e}, z diff {:e}",
            &g[0],
            f(g, 1) - f(w, 1),
            f(g, 2) - f(w, 2),
            f(g, 3) - f(w, 3)
        );
        assert!((f(g, 1) - f(w, 1)).abs() <= SURFACE_MAX_MM);
        assert!((f(g, 2) - f(w, 2)).abs() <= 1e-3);
        assert!((f(g, 3) - f(w, 3)).abs() <= 0.5);
    }
}

#[test]
fn unknown_options_fail_with_a_message() {
    let (ok, _, stderr) = testpiece(&["envelope", "--bogus"]);
    assert!(!ok);
    assert!(stderr.contains("--bogus"));
}
