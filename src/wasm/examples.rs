//! The example parts built into the page (so a newcomer sees a result at once, and the
//! single-file build needs no fetch): the three synthetic measured parts of
//! `tests/data/reference/examples/` (canonical CSV; their answer keys stay in the tests).

use wasm_bindgen::prelude::*;

/// (file name, what it is) of each built-in example, in menu order.
pub const EXAMPLES: [(&str, &str, &str); 3] = [
    (
        "example_backlash_c.csv",
        "S-shape part machined with C-axis backlash (synthetic, σ = 1.5 µm)",
        include_str!("../../tests/data/reference/examples/example_backlash_c.csv"),
    ),
    (
        "example_tool_radius.csv",
        "S-shape part machined with an oversize tool (synthetic, σ = 1.5 µm)",
        include_str!("../../tests/data/reference/examples/example_tool_radius.csv"),
    ),
    (
        "example_clean.csv",
        "S-shape part with machine errors only (synthetic, σ = 1.5 µm)",
        include_str!("../../tests/data/reference/examples/example_clean.csv"),
    ),
];

/// The built-in examples: `[{name, description}]`.
#[wasm_bindgen(js_name = exampleList)]
pub fn example_list() -> Result<JsValue, JsError> {
    let list: Vec<serde_json::Value> = EXAMPLES
        .iter()
        .map(|(n, d, _)| serde_json::json!({ "name": n, "description": d }))
        .collect();
    super::to_js(&list)
}

/// The bytes of a built-in example file, by name.
#[wasm_bindgen(js_name = exampleBytes)]
pub fn example_bytes(name: &str) -> Result<Vec<u8>, JsError> {
    EXAMPLES
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|(_, _, text)| text.as_bytes().to_vec())
        .ok_or_else(|| {
            let names: Vec<&str> = EXAMPLES.iter().map(|(n, _, _)| *n).collect();
            JsError::new(&format!(
                "no built-in example named {name:?}; the examples are {}",
                names.join(", ")
            ))
        })
}
