//! wasm exports of the `gap` stage.

use wasm_bindgen::prelude::*;

use crate::effects::builtin::builtin_model;
use crate::effects::GapInput;
use crate::gap::diagnose;
use crate::part::SShape;

/// Diagnoses the sim-to-real gap of a part measured at the 100 built-in points.
///
/// `deviations`: `Float64Array` of 100 normal deviations (mm, `(measured − nominal)·N`, + =
/// material left), in built-in id order (1-25 `A_Z11`, 26-50 `A_Z25`, 51-75 `B_Z11`,
/// 76-100 `B_Z25`). `sigma`: CMM repeatability (mm, 1σ) or `undefined` to estimate it.
/// Returns the report of `testpiece diagnose --json` (`baseline`, `where`, `candidates`,
/// `verdict`, `summary`, …).
#[wasm_bindgen(js_name = diagnoseBuiltin)]
pub fn diagnose_builtin(deviations: Vec<f64>, sigma: Option<f64>) -> Result<JsValue, JsError> {
    let model = builtin_model(&SShape::iso()).map_err(|e| JsError::new(&e.to_string()))?;
    let report = diagnose(&GapInput {
        deviations,
        points: model.points,
        baseline: model.baseline,
        candidates: model.candidates,
        noise_sigma: sigma,
        reversals: model.reversals,
    })
    .map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&report)
}
