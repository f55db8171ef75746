//! The page's main call: one measured part through the whole pipeline.

use wasm_bindgen::prelude::*;

use crate::analysis::{analyse as run, AnalysisOptions};

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
