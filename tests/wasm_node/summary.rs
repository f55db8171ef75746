//! The part summary through the wasm export: the same numbers as the direct call.

use wasm_bindgen_test::*;

#[wasm_bindgen_test]
fn part_summary_matches_the_native_core_computation() {
    // Under wasm the library is the same Rust code: compare the exported call with a direct one.
    let direct = testpiece::summary::part_summary();
    let js = testpiece::wasm::part_summary().expect("part summary");
    let back: serde_json::Value = serde_wasm_bindgen::from_value(js).expect("plain object");
    let curves = back["curves"].as_array().expect("curves");
    assert_eq!(curves.len(), 4);
    for (c, d) in curves.iter().zip(&direct.curves) {
        assert_eq!(c["curve"], d.curve.as_str());
        assert_eq!(c["length"].as_f64().unwrap(), d.length);
    }
    // A_Z11 is 656.88 mm long (native `testpiece info`); the S is longer than its 250 mm span.
    assert!((curves[0]["length"].as_f64().unwrap() - 656.8847).abs() < 1e-3);
}
