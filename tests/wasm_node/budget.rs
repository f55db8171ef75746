//! The budget of issue 10 compiled to wasm and run under Node: the exported `budget` call on the
//! embedded example files adds up point by point (sum check) and gives the core's numbers, and a
//! bad CL file throws the reader's line/column message.

use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

use testpiece::budget::{error_budget, read_cl, read_trace, BudgetOptions, TraceMachine};
use testpiece::wasm::budget::{budget, budget_example_bytes};

#[wasm_bindgen_test]
fn the_exported_budget_adds_up_and_equals_the_core() {
    let cmm = budget_example_bytes("example_measured.csv")
        .ok()
        .expect("example");
    let cl = budget_example_bytes("example_cl.apt")
        .ok()
        .expect("example");
    let tr = budget_example_bytes("example_trace.csv")
        .ok()
        .expect("example");
    let js = budget(
        &cmm,
        "example_measured.csv",
        &cl,
        "example_cl.apt",
        Some(tr.clone()),
        Some("example_trace.csv".into()),
        JsValue::UNDEFINED,
        None,
    )
    .ok()
    .expect("budget");
    let v: serde_json::Value = serde_wasm_bindgen::from_value(js).unwrap();
    let points = v["points"].as_array().unwrap();
    assert_eq!(points.len(), 100);
    let core = error_budget(
        &cmm,
        "example_measured.csv",
        &read_cl(&cl, "example_cl.apt").unwrap(),
        Some(&read_trace(&tr, "example_trace.csv", &TraceMachine::default()).unwrap()),
        &BudgetOptions::default(),
    )
    .unwrap();
    for (p, c) in points.iter().zip(&core.points) {
        let f = |k: &str| p[k].as_f64().unwrap();
        let sum = f("design") + f("cam") + f("nc") + f("machine") + f("tool") + f("residual");
        assert!((sum - f("measured")).abs() < 1e-12);
        assert!((f("nc") - c.nc).abs() < 1e-12 && (f("machine") - c.machine).abs() < 1e-12);
    }
}

#[wasm_bindgen_test]
fn a_bad_cl_file_names_the_line_under_wasm() {
    let e = read_cl(b"GOTO/1,2,3,0,0,1\nGOTO/1,2,x,0,0,1\n", "p.apt").unwrap_err();
    assert!(e
        .to_string()
        .contains("line 2, column 3 'GOTO field 3': not a number: found 'x'"));
}

/// The page's budget examples are generated in the browser (not embedded, to keep the wasm
/// small): under wasm they are the files of tests/data/budget/ byte for byte (6 decimals).
#[wasm_bindgen_test]
fn the_generated_examples_are_the_committed_files() {
    for (name, disk) in [
        (
            "example_measured.csv",
            include_str!("../data/budget/example_measured.csv"),
        ),
        (
            "example_cl.apt",
            include_str!("../data/budget/example_cl.apt"),
        ),
        (
            "example_trace.csv",
            include_str!("../data/budget/example_trace.csv"),
        ),
    ] {
        let made = budget_example_bytes(name).ok().expect("example");
        assert!(made == disk.as_bytes(), "{name} differs under wasm");
    }
}
