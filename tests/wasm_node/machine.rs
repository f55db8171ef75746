//! The `machine` / `sensitivity` core compiled to wasm and run under Node: the Figure-19 matrix
//! equals tests/data/reference/sensitivity_physical.csv (embedded at compile time: no files under
//! wasm) to the same relative 1e-6 as natively.

use wasm_bindgen_test::*;

use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::{sensitivity_matrix, SensitivityOptions};

const REFERENCE: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/data/reference/sensitivity_physical.csv"
));

#[wasm_bindgen_test]
fn sensitivity_matrix_matches_reference_under_wasm() {
    let part = SShape::iso();
    let points = builtin_points(&part);
    let opts = SensitivityOptions::default();
    let q = testpiece::sensitivity::axis_values(&part, &points, &opts).expect("axis values");
    let errors = testpiece::sensitivity::error_set::error_set(&opts.chain, opts.branch)
        .expect("error set")
        .params();
    let m = sensitivity_matrix(&part, &points, &q, &opts, &errors).expect("sensitivity");
    let rows: Vec<Vec<f64>> = REFERENCE
        .lines()
        .skip(1)
        .map(|l| l.split(',').skip(2).map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), m.values.nrows());
    for k in 0..8 {
        let scale = rows.iter().fold(0.0f64, |a, r| a.max(r[k].abs()));
        for (i, r) in rows.iter().enumerate() {
            assert!((m.values[(i, k)] - r[k]).abs() <= 1e-6 * scale);
        }
    }
}
