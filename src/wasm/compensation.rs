//! Compensation in the controller's terms (issue 19, step 3) for the page: one call when the
//! Correction view is opened for a file (stateless: the file is analysed again with the same
//! settings, as `testpiece identify FILE --compensation` does).

use wasm_bindgen::prelude::*;

use super::prepared::PreparedSettings;
use crate::analysis::{analyse, AnalysisOptions};
use crate::compensation::compensation;

/// The compensation of one CMM file's final answer: `prepared` and `options` as for `analyse`.
/// Returns the [`crate::compensation::Compensation`] (`{machine, before, after, after_std (the
/// std of every number of `after`, same shape), covariance, changes, tool_tip_shift, entered,
/// not_entered: [{name, value, unit, std, status, reason, why}], controller: {controller,
/// kinematic_type, toolholder, parameters: [{name, meaning, value, std, unit, group, place}],
/// homes: [{name, groups, parameters, sentence}]} | null, controller_unavailable, part: {points:
/// [{id, curve, measured, machine, left_model, residual, after, used}], before, after, machine,
/// left_in}, withheld: {curves: [{curve, points, entered, values, measured, after}], points,
/// measured, after, skipped}, effects_left, notes}`, mm, rad).
#[wasm_bindgen]
pub fn compensate(
    prepared: &PreparedSettings,
    bytes: &[u8],
    name: &str,
    options: JsValue,
) -> Result<JsValue, JsError> {
    let opts: AnalysisOptions = super::settings_from_js(options, "bad analysis settings")?;
    let a = analyse(prepared.session(), bytes, name, &opts)
        .map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&compensation(&a))
}
