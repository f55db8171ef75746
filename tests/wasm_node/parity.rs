//! Native and wasm give the same analysis of the three example files to 1e-12 relative
//! (issue 9). The native numbers are in tests/data/parity/analysis_examples.json, written at
//! full precision by the native test `edge_parity.rs` (which also keeps the file equal to the
//! native results); here the same analyses run in wasm and every number of the serialised
//! `Analysis` is compared (`parity_common::compare`). The page's export `analyse` is called
//! too and must succeed.

#[path = "../parity_common/mod.rs"]
mod parity_common;

use parity_common::{analysis_value, compare, EXAMPLES, PARITY_REL};
use testpiece::analysis::{analyse, AnalysisOptions};
use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

const NATIVE: &str = include_str!("../data/parity/analysis_examples.json");

fn example(name: &str) -> &'static [u8] {
    match name {
        "example_clean.csv" => include_bytes!("../data/reference/examples/example_clean.csv"),
        "example_tool_radius.csv" => {
            include_bytes!("../data/reference/examples/example_tool_radius.csv")
        }
        "example_backlash_c.csv" => {
            include_bytes!("../data/reference/examples/example_backlash_c.csv")
        }
        _ => unreachable!("{name}"),
    }
}

#[wasm_bindgen_test]
fn analysis_of_the_examples_matches_native() {
    let native: serde_json::Value = serde_json::from_str(NATIVE).expect("analysis_examples.json");
    for name in EXAMPLES {
        let bytes = example(name);
        let a = analyse(bytes, name, &AnalysisOptions::default()).expect(name);
        let wasm = analysis_value(&a);
        let diff = compare(&native[name], &wasm, PARITY_REL);
        assert!(
            diff.is_empty(),
            "{name}: {} differences beyond {PARITY_REL:e}: {:?}",
            diff.len(),
            &diff[..diff.len().min(10)]
        );
        testpiece::wasm::analysis::analyse(bytes, name, JsValue::UNDEFINED)
            .unwrap_or_else(|_| panic!("{name}: the export failed"));
    }
}
