//! The budget of issue 10 compiled to wasm and run under Node: the exported `budget` call on the
//! generated example files adds up point by point (sum check) and gives the core's numbers, the
//! page's `budgetExample` gives the same budget, and a bad CL file throws the reader's
//! line/column message.

use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

use testpiece::budget::{error_budget, read_cl, read_trace, BudgetOptions, TraceMachine};
use testpiece::wasm::budget::{budget, budget_example};

/// The text of a generated budget example file.
fn example(name: &str) -> Vec<u8> {
    let files = testpiece::budget::synthetic::example_files().expect("examples");
    let (_, text) = files.into_iter().find(|(n, _)| *n == name).expect(name);
    text.into_bytes()
}

#[wasm_bindgen_test]
fn the_exported_budget_adds_up_and_equals_the_core() {
    let cmm = example("example_measured.csv");
    let cl = example("example_cl.apt");
    let tr = example("example_trace.csv");
    let prepared = crate::prepared();
    let js = budget(
        &prepared,
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
    let session = testpiece::analysis::Session::new(&Default::default()).unwrap();
    let core = error_budget(
        &session,
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
    // The page's example button: the same files and the same budget in one call.
    let js = budget_example(&prepared, JsValue::UNDEFINED)
        .ok()
        .expect("budget example");
    let e: serde_json::Value = serde_wasm_bindgen::from_value(js).unwrap();
    assert_eq!(e["budget"]["points"], v["points"]);
    let roles: Vec<&str> = e["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["role"].as_str().unwrap())
        .collect();
    assert_eq!(roles, ["cmm", "cl", "trace"]);
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
        assert!(
            example(name) == disk.as_bytes(),
            "{name} differs under wasm"
        );
    }
}
