//! The error budget of issue 10 for the page: one call per "compute" action, and the synthetic
//! example files (CAM path, NC trace, measured part) of `tests/data/budget/`.

use wasm_bindgen::prelude::*;

use crate::budget::{error_budget, read_cl, read_trace, BudgetOptions, TraceMachine};
use crate::machine::description::MachineDescription;

/// (file name, role, description, content) of the budget example files.
pub const BUDGET_EXAMPLES: [(&str, &str, &str, &str); 3] = [
    (
        "example_measured.csv",
        "cmm",
        "measured part: NC-trace deviation + EX0B, EA0B + 5 µm oversize tool + 1 µm noise (synthetic)",
        include_str!("../../tests/data/budget/example_measured.csv"),
    ),
    (
        "example_cl.apt",
        "cl",
        "CAM path: eq. 2 flank path every 1 mm, APT GOTO/x,y,z,i,j,k (synthetic)",
        include_str!("../../tests/data/budget/example_cl.apt"),
    ),
    (
        "example_trace.csv",
        "trace",
        "NC trace: X,Y,Z,B,C every 8 ms with a following error (synthetic)",
        include_str!("../../tests/data/budget/example_trace.csv"),
    ),
];

/// The error budget of a measured part. `cmm`, `cl` and `trace` are file bytes (`trace` may be
/// absent); `options` is a [`BudgetOptions`] object (`{analysis: {mode, branch, l0,
/// tool_radius, …}, tool_radius, mpe_constant_um, mpe_length_mm_per_um}`, any part absent:
/// defaults); `machine` is a JSON machine description for the trace (absent: paper 000's
/// machine with `options.analysis.l0`). Returns the [`crate::budget::Budget`] (mm); a bad file
/// throws the reader's message (line, column, text found, what was expected).
#[wasm_bindgen]
#[allow(clippy::too_many_arguments)]
pub fn budget(
    cmm: &[u8],
    cmm_name: &str,
    cl: &[u8],
    cl_name: &str,
    trace: Option<Vec<u8>>,
    trace_name: Option<String>,
    options: JsValue,
    machine: Option<String>,
) -> Result<JsValue, JsError> {
    let opts: BudgetOptions = if options.is_undefined() || options.is_null() {
        BudgetOptions::default()
    } else {
        serde_wasm_bindgen::from_value(options)
            .map_err(|e| JsError::new(&format!("bad budget settings: {e}")))?
    };
    let err = |e: crate::budget::BudgetError| JsError::new(&e.to_string());
    let m = match machine {
        Some(text) => {
            let d =
                MachineDescription::from_json(&text).map_err(|e| JsError::new(&e.to_string()))?;
            TraceMachine::from_description(&d).map_err(err)?
        }
        None => TraceMachine::paper000(opts.analysis.l0),
    };
    let path = read_cl(cl, cl_name).map_err(err)?;
    let tr = match trace {
        Some(bytes) => {
            let name = trace_name.unwrap_or_else(|| "trace.csv".to_string());
            Some(read_trace(&bytes, &name, &m).map_err(err)?)
        }
        None => None,
    };
    let b = error_budget(cmm, cmm_name, &path, tr.as_ref(), &opts).map_err(err)?;
    super::to_js(&b)
}

/// The budget example files: `[{name, role, description}]` (role `cmm`, `cl` or `trace`).
#[wasm_bindgen(js_name = budgetExampleList)]
pub fn budget_example_list() -> Result<JsValue, JsError> {
    let list: Vec<serde_json::Value> = BUDGET_EXAMPLES
        .iter()
        .map(|(n, r, d, _)| serde_json::json!({ "name": n, "role": r, "description": d }))
        .collect();
    super::to_js(&list)
}

/// The bytes of a budget example file, by name.
#[wasm_bindgen(js_name = budgetExampleBytes)]
pub fn budget_example_bytes(name: &str) -> Result<Vec<u8>, JsError> {
    BUDGET_EXAMPLES
        .iter()
        .find(|(n, _, _, _)| *n == name)
        .map(|(_, _, _, text)| text.as_bytes().to_vec())
        .ok_or_else(|| JsError::new(&format!("no budget example named {name:?}")))
}
