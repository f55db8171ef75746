//! wasm exports of the `cmm` stage: one stateless call per uploaded file.

use wasm_bindgen::prelude::*;

use crate::cmm::{read_cmm_with, ReadOptions};

/// Options from the page: `undefined`/`null` = defaults; otherwise an object with any of the
/// fields of [`ReadOptions`] (snake_case: `exclude_bad_rows`, `min_points`, `max_bytes`,
/// `max_rows`, `length_unit` ("mm" | "um" | "inch" | "cm" | "m"), `max_distance_mm`,
/// `normal_warn_deg`, `deviation_warn_mm`); missing fields take their defaults.
pub(crate) fn options_from_js(options: JsValue) -> Result<ReadOptions, JsError> {
    if options.is_undefined() || options.is_null() {
        return Ok(ReadOptions::default());
    }
    super::from_js(options).map_err(|e| JsError::new(&format!("invalid CMM reading options: {e}")))
}

/// Reads a CMM export (`shared/spec/cmm-csv.md`). `bytes`: the file as uploaded; `name`: its
/// name (for messages). Returns the [`crate::cmm::CmmFile`] as a plain object:
/// `{name, format: {kind, description, encoding, separator, decimal_comma, header_line,
/// columns}, extra_columns, points: [{line, id, curve, nominal: [x,y,z] | null,
/// normal: [i,j,k] | null, measured: [x,y,z] | null, deviation | null, extra: [..]}],
/// excluded: [{line, column, kind, found, expected}], warnings: [{line, message}],
/// comment_lines, blank_lines}`; lengths in mm, deviation + = material left.
/// A rejected file throws a `JsError` whose message is the reader's, listing every bad row.
#[wasm_bindgen(js_name = readCmm)]
pub fn read_cmm(bytes: &[u8], name: &str, options: JsValue) -> Result<JsValue, JsError> {
    let opts = options_from_js(options)?;
    let file = read_cmm_with(bytes, name, &opts).map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&file)
}

/// Reads a CMM export and matches every point to the nominal S-shape by closest-point
/// projection (cmm-csv.md rules 1-4). Returns the [`crate::cmm::MatchedPart`] as a plain object:
/// `{name, format, extra_columns, points: [{file: <row as in readCmm>, surface: "A"|"B", u, v,
/// foot: [x,y,z], normal: [i,j,k], deviation, rule: "file_deviation"|"measured_minus_nominal"|
/// "projection", distance, clamped, normal_angle_deg | null, position_deviation | null}],
/// excluded, warnings}`; mm, + = material left. Options as for [`read_cmm`]. A rejected file
/// (including points more than `max_distance_mm` from the surfaces) throws a `JsError` with
/// the reader's message.
#[wasm_bindgen(js_name = matchCmm)]
pub fn match_cmm(bytes: &[u8], name: &str, options: JsValue) -> Result<JsValue, JsError> {
    let opts = options_from_js(options)?;
    let part =
        crate::cmm::read_and_match(bytes, name, &opts).map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&part)
}
