//! wasm exports of the `machine` and `sensitivity` stages: thin, stateless converters.

use js_sys::{Float64Array, Object, Reflect};
use wasm_bindgen::prelude::*;

use super::to_js;
use crate::machine::Branch;
use crate::part::{builtin_points, SShape};
use crate::sensitivity::{sensitivity_matrix, Mode, SensitivityMatrix, SensitivityOptions};

fn set(o: &Object, k: &str, v: &JsValue) -> Result<(), JsError> {
    Reflect::set(o, &JsValue::from_str(k), v)
        .map(|_| ())
        .map_err(|_| JsError::new(&format!("could not set `{k}` on the result")))
}

/// Figure-19 sensitivity matrix at the 100 built-in points.
/// `mode`: `"physical"` (default when empty) or `"paper"`; `branch`: `"signed"` (default) or
/// `"positive"`. Returns `{ids: number[], curves: string[], params: string[], rows, cols,
/// values: Float64Array}` with `values` **column-major**: `values[k * rows + i]` is the defect
/// (mm) at point `ids[i]` per unit of error `params[k]` (mm/rad; mm/mm for EX0B).
#[wasm_bindgen]
pub fn sensitivity(mode: &str, branch: &str) -> Result<JsValue, JsError> {
    let mode = if mode.is_empty() {
        Mode::Physical
    } else {
        Mode::parse(mode).map_err(|e| JsError::new(&e.to_string()))?
    };
    let branch = if branch.is_empty() {
        Branch::Signed
    } else {
        Branch::parse(branch).ok_or_else(|| {
            JsError::new(&format!(
                "`{branch}` is not a branch (expected `signed` or `positive`)"
            ))
        })?
    };
    let part = SShape::iso();
    let points = builtin_points(&part);
    let opts = SensitivityOptions::default()
        .with_mode(mode)
        .with_branch(branch);
    let m = sensitivity_matrix(&part, &points, &opts).map_err(|e| JsError::new(&e.to_string()))?;
    matrix_to_js(&m)
}

/// A sensitivity matrix as `{ids, curves, params, rows, cols, values}`, `values` a
/// Float64Array in column-major order (nalgebra's storage).
pub(crate) fn matrix_to_js(m: &SensitivityMatrix) -> Result<JsValue, JsError> {
    let o = Object::new();
    set(&o, "ids", &to_js(&m.ids)?)?;
    set(&o, "curves", &to_js(&m.curves)?)?;
    set(&o, "params", &to_js(&m.params)?)?;
    set(&o, "rows", &JsValue::from(m.values.nrows() as u32))?;
    set(&o, "cols", &JsValue::from(m.values.ncols() as u32))?;
    set(
        &o,
        "values",
        &Float64Array::from(m.values.as_slice()).into(),
    )?;
    Ok(o.into())
}
