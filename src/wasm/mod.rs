//! The only module that knows about JavaScript: thin, stateless converters from the core's
//! functions to `#[wasm_bindgen]` exports. One call per user action; results cross as plain
//! objects (serde) or `Float64Array` columns; errors as `JsError` with the core's message.

use wasm_bindgen::prelude::*;

pub mod analysis;
pub mod bench;
pub mod budget;
pub mod cmm;
pub mod curves;
pub mod examples;
pub mod gap;
pub mod geometry;
pub mod identify;
pub mod machine;
pub mod pool;

/// Converts a core result to a plain JS object (maps as objects, not `Map`).
pub(crate) fn to_js<T: serde::Serialize>(value: &T) -> Result<JsValue, JsError> {
    let ser = serde_wasm_bindgen::Serializer::json_compatible();
    value
        .serialize(&ser)
        .map_err(|e| JsError::new(&format!("could not convert the result for the page: {e}")))
}

/// The crate version (same as `testpiece --version`).
#[wasm_bindgen]
pub fn version() -> String {
    crate::VERSION.to_string()
}

/// Summary of the built-in example part: `{version, curves: [{curve, z, length}]}` (mm).
#[wasm_bindgen(js_name = partSummary)]
pub fn part_summary() -> Result<JsValue, JsError> {
    to_js(&crate::summary::part_summary())
}
