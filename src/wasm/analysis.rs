//! The page's main call: one measured part through the whole pipeline.

use wasm_bindgen::prelude::*;

use crate::analysis::{analyse as run, analyse_repeats, AnalysisOptions};

/// Reads, matches and identifies one CMM file. `options` is `{mode, branch, l0, tool_radius,
/// exclude_bad_rows, noise_sigma, noise_mpe: {a_um, k_mm, r0_um}, keep_outliers, ...}` (any may
/// be absent: defaults of `AnalysisOptions`; `noise_sigma` and `noise_mpe` not both).
/// Returns the [`crate::analysis::Analysis`] as a plain object; a bad file throws the reader's
/// message (line, column, text found, what was expected).
#[wasm_bindgen]
pub fn analyse(bytes: &[u8], name: &str, options: JsValue) -> Result<JsValue, JsError> {
    let opts: AnalysisOptions = if options.is_undefined() || options.is_null() {
        AnalysisOptions::default()
    } else {
        super::from_js(options).map_err(|e| JsError::new(&format!("bad analysis settings: {e}")))?
    };
    let a = run(bytes, name, &opts).map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&a)
}

/// Repeat measurements of one part: `files` = `[{name, bytes: Uint8Array}]`, the first file then
/// its repeats (the same point ids measured again, at least 2 files); `options` as for
/// `analyse`, without `noise_sigma` or `noise_mpe` (σ comes from the repeats). Returns the
/// [`crate::analysis::Analysis`] of their mean, with `repeat` = {pure_error {sigma, dof,
/// sigma_mean, largest}, lack_of_fit {f, dof_fit, dof_pure, p_value}, summary}.
#[wasm_bindgen(js_name = analyseRepeats)]
pub fn analyse_repeats_js(files: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let files = super::pool::files_from_js(&files)
        .map_err(|e| JsError::new(&format!("repeat files: expected [{{name, bytes}}]: {e}")))?;
    let opts: AnalysisOptions = if options.is_undefined() || options.is_null() {
        AnalysisOptions::default()
    } else {
        super::from_js(options).map_err(|e| JsError::new(&format!("bad analysis settings: {e}")))?
    };
    let list: Vec<(&[u8], &str)> = files
        .iter()
        .map(|(name, bytes)| (bytes.as_slice(), name.as_str()))
        .collect();
    let a = analyse_repeats(&list, &opts).map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&a)
}
