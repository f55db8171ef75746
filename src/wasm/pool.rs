//! wasm exports for several parts: pooled identification ([`crate::pool`]) and side-by-side
//! comparison ([`crate::compare`]).

use wasm_bindgen::prelude::*;

use super::prepared::PreparedSettings;
use crate::compare::{compare, ParameterValue};
use crate::pool::{identify_pooled, PoolOptions};

/// `[{name, bytes: Uint8Array | number[]}]` → (name, bytes), read field by field (the bytes are
/// not passed through JSON). A bad list throws `{context}: {why}`.
pub(super) fn files_from_js(
    files: &JsValue,
    context: &str,
) -> Result<Vec<(String, Vec<u8>)>, JsError> {
    let bad = |why: String| JsError::new(&format!("{context}: {why}"));
    if !js_sys::Array::is_array(files) {
        return Err(bad("not an array".into()));
    }
    js_sys::Array::from(files)
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let get = |k: &str| js_sys::Reflect::get(&f, &JsValue::from_str(k)).ok();
            let name = get("name")
                .and_then(|n| n.as_string())
                .ok_or_else(|| bad(format!("file {}: no `name` string", i + 1)))?;
            let bytes = get("bytes")
                .filter(|b| b.is_object())
                .map(|b| js_sys::Uint8Array::new(&b).to_vec())
                .ok_or_else(|| bad(format!("file {} ({name}): no `bytes` array", i + 1)))?;
            Ok((name, bytes))
        })
        .collect()
}

/// Identifies one machine from several CMM files on `prepared` (the settings of `options`, as
/// for `analyse`). `files`: `[{name, bytes: Uint8Array}]` (at least 2); `options`: the settings
/// of `analyse` plus `setup_per_part` (bool). Returns the
/// [`crate::pool::PooledIdentification`]: `{version, settings, parts: [{name, index, points,
/// excluded_rows, residual_rms, residual_mean}], shared, per_part, identification}` (mm, rad).
#[wasm_bindgen(js_name = analysePooled)]
pub fn analyse_pooled(
    prepared: &PreparedSettings,
    files: JsValue,
    options: JsValue,
) -> Result<JsValue, JsError> {
    let files = files_from_js(&files, "pooled files: expected [{name, bytes}]")?;
    let opts: PoolOptions = super::settings_from_js(options, "bad pooling settings")?;
    let list: Vec<(&[u8], &str)> = files
        .iter()
        .map(|(name, bytes)| (bytes.as_slice(), name.as_str()))
        .collect();
    let r = identify_pooled(prepared.session().prepared(), &list, &opts)
        .map_err(|e| JsError::new(&e.to_string()))?;
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
        super::from_js(
            v,
            &format!("parameters of {side}: expected [{{name, value, std, unit}}]"),
        )
    };
    let c = compare(a_name, &parse(a, a_name)?, b_name, &parse(b, b_name)?)
        .map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&c)
}
