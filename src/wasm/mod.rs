//! The only module that knows about JavaScript: thin, stateless converters from the core's
//! functions to `#[wasm_bindgen]` exports. One call per user action; results cross as plain
//! objects (serde) or `Float64Array` columns; errors as `JsError` with the core's message.

use wasm_bindgen::prelude::*;

pub mod analysis;
#[cfg(feature = "bench")]
pub mod bench;
pub mod budget;
pub mod cmm;
pub mod compensation;
pub mod curves;
pub mod examples;
pub mod gap;
pub mod geometry;
pub mod identify;
pub mod machine;
pub mod plan;
pub mod pool;
pub mod program;
pub mod settings;

/// Converts a core result to a plain JS object (maps as objects, not `Map`): serialised to JSON
/// text by serde_json and parsed by the browser's `JSON.parse` (one serialiser for the native
/// CLI and the page keeps the wasm small). Non-finite numbers become `null`, as in the CLI's JSON.
pub(crate) fn to_js<T: serde::Serialize>(value: &T) -> Result<JsValue, JsError> {
    let text = serde_json::to_string(value)
        .map_err(|e| JsError::new(&format!("could not convert the result for the page: {e}")))?;
    js_sys::JSON::parse(&text)
        .map_err(|_| JsError::new("could not convert the result for the page: JSON.parse failed"))
}

/// Reads a plain JS object (settings, lists) into a core type through `JSON.stringify`;
/// `undefined` and `null` read as JSON `null`.
pub(crate) fn from_js<T: serde::de::DeserializeOwned>(value: JsValue) -> Result<T, String> {
    let text: String = if value.is_undefined() || value.is_null() {
        "null".into()
    } else {
        js_sys::JSON::stringify(&value)
            .map_err(|_| "not a plain object (JSON.stringify failed)".to_string())?
            .into()
    };
    serde_json::from_str(&text).map_err(|e| e.to_string())
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
