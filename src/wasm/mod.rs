//! The only module that knows about JavaScript: thin converters from the core's functions to
//! `#[wasm_bindgen]` exports, one export per user action of the page (`www/`):
//!
//! | user action | export |
//! |---|---|
//! | the page opens | [`page::start`] (version, machines, examples, curves, words) |
//! | the machine, L0, branch or mode change | `new Prepared(settings)` ([`prepared`]: the one value the worker holds and passes back to the exports below that analyse) |
//! | a file or example is analysed | [`analysis::analyse`] / [`analysis::analyse_repeats`] |
//! | the machine settings change, a path surface is chosen | [`curves::curves_for`] |
//! | a cone is chosen | [`curves::cone_coefficients`] |
//! | several parts are pooled / compared | [`pool::analyse_pooled`] / [`pool::compare_parameters`] |
//! | the plan, the program, the correction, the budget | [`plan`], [`program`], [`compensation`], [`budget`] |
//!
//! Results cross as plain objects (serde) or `Float64Array` columns; errors as `JsError` with
//! the core's message (a file's rejected rows also as a field, [`analysis`]).

use wasm_bindgen::prelude::*;

// The page's first module (feature `page-core`): what the first view calls.
#[cfg(feature = "page-core")]
pub mod analysis;
#[cfg(feature = "bench")]
pub mod bench;
#[cfg(feature = "page-core")]
pub mod columns;
#[cfg(feature = "page-core")]
pub mod curves;
#[cfg(feature = "page-core")]
pub mod page;
#[cfg(feature = "page-core")]
pub mod pool;
// Both modules: each holds its own prepared settings (a wasm object lives in one module's memory).
pub mod prepared;
// The second module (feature `page-tools`): the views opened later.
#[cfg(feature = "page-tools")]
pub mod budget;
#[cfg(feature = "page-tools")]
pub mod compensation;
#[cfg(feature = "page-tools")]
pub mod plan;
#[cfg(feature = "page-tools")]
pub mod program;

/// Converts a core result to a plain JS object (maps as objects, not `Map`): serialised to JSON
/// text by serde_json and parsed by the browser's `JSON.parse` (one serialiser for the native
/// CLI and the page keeps the wasm small). Non-finite numbers become `null`, as in the CLI's JSON.
pub(crate) fn to_js<T: serde::Serialize>(value: &T) -> Result<JsValue, JsError> {
    let text = serde_json::to_string(value)
        .map_err(|e| JsError::new(&format!("could not convert the result for the page: {e}")))?;
    js_sys::JSON::parse(&text)
        .map_err(|_| JsError::new("could not convert the result for the page: JSON.parse failed"))
}

/// Reads the settings object `value` of a call into a core type through `JSON.stringify`;
/// `undefined` and `null` give the type's defaults. A bad object throws `{context}: {why}`
/// (`bad analysis settings: …`).
pub(crate) fn settings_from_js<T: serde::de::DeserializeOwned + Default>(
    value: JsValue,
    context: &str,
) -> Result<T, JsError> {
    if value.is_undefined() || value.is_null() {
        return Ok(T::default());
    }
    from_js(value, context)
}

/// Reads a plain JS object (settings, lists) into a core type through `JSON.stringify`;
/// `undefined` and `null` read as JSON `null`. A bad object throws `{context}: {why}`.
pub(crate) fn from_js<T: serde::de::DeserializeOwned>(
    value: JsValue,
    context: &str,
) -> Result<T, JsError> {
    let text: String = if value.is_undefined() || value.is_null() {
        "null".into()
    } else {
        js_sys::JSON::stringify(&value)
            .map_err(|_| {
                JsError::new(&format!(
                    "{context}: not a plain object (JSON.stringify failed)"
                ))
            })?
            .into()
    };
    serde_json::from_str(&text).map_err(|e| JsError::new(&format!("{context}: {e}")))
}
