//! wasm exports of the `machine` and `sensitivity` stages: thin, stateless converters.

use js_sys::{Array, Float64Array, Object, Reflect};
use wasm_bindgen::prelude::*;

use super::to_js;
use crate::machine::description::MachineDescription;
use crate::machine::direct::tool_point;
use crate::machine::location_errors::minimal_set;
use crate::machine::{AxisName, AxisValues, Branch, Chain};
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

/// The ISO 230-1 location errors of a structural code (e.g. `"w C Y' b X Z B t"`) with their
/// status: `{code, free: string[], rows: [{error: {component, axis}, status, reason}]}`.
#[wasm_bindgen(js_name = minimalErrorSet)]
pub fn minimal_error_set(code: &str) -> Result<JsValue, JsError> {
    let chain = Chain::from_code(code).map_err(|e| JsError::new(&e.to_string()))?;
    let set_ = minimal_set(&chain);
    let o = Object::new();
    set(&o, "code", &JsValue::from_str(chain.code()))?;
    let free = Array::new();
    for n in set_.names() {
        free.push(&JsValue::from_str(&n));
    }
    set(&o, "free", &free.into())?;
    set(&o, "rows", &to_js(&set_.rows)?)?;
    Ok(o.into())
}

/// Forward kinematics of a machine description (JSON, see `src/machine/description.rs`) for
/// `values`, a row-major Float64Array of rows `X, Y, Z, A, B, C` (mm; rotary axes in the
/// description's `angle_unit`, degrees by default; axes the machine lacks are ignored).
/// Returns a Float64Array of rows `tip_x, tip_y, tip_z, i, j, k` (mm; unit tool axis).
#[wasm_bindgen(js_name = forwardKinematics)]
pub fn forward_kinematics(description: &str, values: &[f64]) -> Result<Float64Array, JsError> {
    let err = |e: crate::machine::MachineError| JsError::new(&e.to_string());
    let desc = MachineDescription::from_json(description).map_err(err)?;
    let chain = desc.chain().map_err(err)?;
    let errors = desc.machine_errors().map_err(err)?;
    if values.len() % 6 != 0 {
        return Err(JsError::new(&format!(
            "{} values is not a whole number of rows of 6 (X, Y, Z, A, B, C)",
            values.len()
        )));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(JsError::new(&format!(
            "row {}, axis {}: value {} is not a finite number",
            i / 6 + 1,
            ["X", "Y", "Z", "A", "B", "C"][i % 6],
            values[i]
        )));
    }
    let k = desc.angle_unit.to_rad();
    let mut out = Vec::with_capacity(values.len());
    for row in values.chunks(6) {
        let mut q = AxisValues::default();
        for (n, v) in AxisName::ALL.iter().zip(row) {
            q.set_in_units(*n, *v, k);
        }
        let t = tool_point(&chain, &q, 0.0, &errors).map_err(err)?;
        out.extend_from_slice(&t.to_array());
    }
    Ok(Float64Array::from(&out[..]))
}
