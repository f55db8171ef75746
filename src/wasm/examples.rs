//! wasm exports of the example parts built into the page ([`crate::examples`]).

use wasm_bindgen::prelude::*;

use crate::examples::{example_text, EXAMPLES};

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
    example_text(name).map(String::into_bytes).ok_or_else(|| {
        let names: Vec<&str> = EXAMPLES.iter().map(|(n, _, _)| *n).collect();
        JsError::new(&format!(
            "no built-in example named {name:?}; the examples are {}",
            names.join(", ")
        ))
    })
}
