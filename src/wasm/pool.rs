//! wasm exports for several parts: pooled identification ([`crate::pool`]) and side-by-side
//! comparison ([`crate::compare`]).

use serde::Deserialize;
use wasm_bindgen::prelude::*;

use crate::compare::{compare, ParameterValue};
use crate::pool::{identify_pooled, PoolOptions};

#[derive(Deserialize)]
struct JsFile {
    name: String,
    #[serde(with = "serde_bytes_compat")]
    bytes: Vec<u8>,
}

/// `Uint8Array` or plain array of numbers → bytes.
mod serde_bytes_compat {
    use serde::{Deserialize, Deserializer};
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<u8>, D::Error> {
        Vec::<u8>::deserialize(d)
    }
}

/// Identifies one machine from several CMM files. `files`: `[{name, bytes: Uint8Array}]` (at
/// least 2); `options`: the settings of `analyse` plus `setup_per_part` (bool). Returns the
/// [`crate::pool::PooledIdentification`]: `{version, settings, parts: [{name, index, points,
/// excluded_rows, residual_rms, residual_mean}], shared, per_part, identification}` (mm, rad).
#[wasm_bindgen(js_name = analysePooled)]
pub fn analyse_pooled(files: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let files: Vec<JsFile> = serde_wasm_bindgen::from_value(files)
        .map_err(|e| JsError::new(&format!("pooled files: expected [{{name, bytes}}]: {e}")))?;
    let opts: PoolOptions = if options.is_undefined() || options.is_null() {
        PoolOptions::default()
    } else {
        serde_wasm_bindgen::from_value(options)
            .map_err(|e| JsError::new(&format!("bad pooling settings: {e}")))?
    };
    let list: Vec<(&[u8], &str)> = files
        .iter()
        .map(|f| (f.bytes.as_slice(), f.name.as_str()))
        .collect();
    let r = identify_pooled(&list, &opts).map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&r)
}

/// Compares two parts' parameters: `a`, `b` are `[{name, value, std (null if none), unit}]`.
/// Returns the [`crate::compare::Comparison`]: `{a, b, differences: [{name, unit, a, a_std, b,
/// b_std, diff (= b − a), std (= √(σa² + σb²)), z, flag}], different, suspect, summary}` with
/// `flag` one of `consistent` (|z| < 2), `suspect` (2 ≤ |z| < 3), `different` (|z| ≥ 3),
/// `undetermined` (no std).
#[wasm_bindgen(js_name = compareParameters)]
pub fn compare_parameters(
    a_name: &str,
    a: JsValue,
    b_name: &str,
    b: JsValue,
) -> Result<JsValue, JsError> {
    let parse = |v: JsValue, side: &str| -> Result<Vec<ParameterValue>, JsError> {
        serde_wasm_bindgen::from_value(v).map_err(|e| {
            JsError::new(&format!(
                "parameters of {side}: expected [{{name, value, std, unit}}]: {e}"
            ))
        })
    };
    let c = compare(a_name, &parse(a, a_name)?, b_name, &parse(b, b_name)?)
        .map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&c)
}
