//! The gap diagnosis compiled to wasm and run under Node: the diagnosis inside the page's
//! `analyse` gives the three example parts of `tests/data/reference/examples/` the same verdicts
//! as the native core, and its `verdict_line` is the first line of the summary.
//!
//! Expected ids: the native `testpiece diagnose tests/data/reference/examples/<file> --json`
//! (`none`; `tool_radius` with `tool_taper` and, since issue 30, `tool_wear` equivalent; `backlash_c`), each also in the key's
//! `accept` list. The in-sample RMS after the verdict must agree with the native figures to
//! 1e-9 mm.

use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

const CLEAN: &[u8] = include_bytes!("../data/reference/examples/example_clean.csv");
const TOOL_RADIUS: &[u8] = include_bytes!("../data/reference/examples/example_tool_radius.csv");
const BACKLASH_C: &[u8] = include_bytes!("../data/reference/examples/example_backlash_c.csv");

/// (file, bytes, native verdict, native equivalents, native rms_after in mm).
const CASES: [(&str, &[u8], &str, &[&str], f64); 3] = [
    ("example_clean.csv", CLEAN, "none", &[], 1.258_175_4e-3),
    (
        "example_tool_radius.csv",
        TOOL_RADIUS,
        "tool_radius",
        &["tool_taper", "tool_wear"],
        1.536_512_9e-3,
    ),
    (
        "example_backlash_c.csv",
        BACKLASH_C,
        "backlash_c",
        &[],
        1.441_611_9e-3,
    ),
];

fn check(what: &str, verdict: &serde_json::Value, case: &(&str, &[u8], &str, &[&str], f64)) {
    let (file, _, id, equivalent, rms_after) = *case;
    assert_eq!(verdict["effect"], id, "{what} {file}");
    let eq: Vec<&str> = verdict["equivalent"]
        .as_array()
        .expect("equivalent")
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(eq, equivalent, "{what} {file}");
    // Native figures written with 8 significant digits.
    let got = verdict["rms_after"].as_f64().unwrap();
    assert!((got - rms_after).abs() < 1e-9, "{what} {file}: {got}");
}

#[wasm_bindgen_test]
fn analyse_carries_the_native_verdicts() {
    let prepared = crate::prepared();
    for case in &CASES {
        let js =
            testpiece::wasm::analysis::analyse(&prepared, case.1, case.0, JsValue::UNDEFINED, None)
                .expect("analysis");
        // (through JSON text: the per-point arrays are typed-array columns, src/wasm/columns.rs)
        let text: String = js_sys::JSON::stringify(&js).expect("JSON").into();
        let back: serde_json::Value = serde_json::from_str(&text).expect("plain object");
        assert_eq!(back["diagnosis"]["status"], "made", "{}", case.0);
        let d = &back["diagnosis"]["report"];
        assert!(d.is_object(), "{}: {}", case.0, back["diagnosis"]);
        check("analyse", &d["verdict"], case);
        let summary = d["summary"].as_str().expect("summary");
        assert_eq!(
            back["verdict_line"].as_str(),
            summary.lines().next(),
            "{}",
            case.0
        );
    }
}
