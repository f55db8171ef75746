//! wasm exports for the page's curves on any of the three machines: the Figure-19 matrix for the
//! analysis settings with paper 002's surface-frame coefficients (eq. 11-14) along the S-shape
//! flank path (one call per change of the settings), and the same coefficients along the M3
//! cone-frustum path (one call per choice of cone).
//!
//! Every parameter crosses with its unit and the typical size the page draws it at (1e-4 rad for
//! an angle, 0.01 mm for a length: [`crate::machine::location_errors::TYPICAL_ANGLE_RAD`],
//! [`crate::machine::location_errors::TYPICAL_LENGTH_MM`]), both from the kind of the
//! parameter's component (X, Y, Z a length; A, B, C an angle), never from its name.

use js_sys::{Float64Array, Object, Reflect};
use serde::Serialize;
use wasm_bindgen::prelude::*;

use super::prepared::PreparedSettings;
use super::to_js;
use crate::machine::{Branch, Chain, ErrorParam, Unit};
use crate::parameter::ParamId;
use crate::part::{builtin_points, Surface};
use crate::sensitivity::cone_frustum::ConeFrustum;
use crate::sensitivity::frenet::{coefficients, cone_frames, flank_frames, Coefficients, Cutting};
use crate::sensitivity::SensitivityMatrix;

/// A cone frustum of paper 002 §4 by name.
type NamedCone = (&'static str, fn() -> ConeFrustum);

/// The cone frusta of paper 002 §4 the page offers, by the name `coneCoefficients` takes.
pub(crate) const CONES: [NamedCone; 2] =
    [("M3_15", ConeFrustum::m3_15), ("M3_45", ConeFrustum::m3_45)];

/// The S-shape surfaces by the name `curvesFor` takes, with the way each is cut (A down-cutting,
/// B up-cutting, so that `n` is the outward normal).
pub(crate) const SURFACES: [(&str, Surface, Cutting); 2] = [
    ("A", Surface::A, Cutting::Down),
    ("B", Surface::B, Cutting::Up),
];

/// The unit of an error parameter and its typical size in that unit, both from the kind of its
/// component ([`ErrorParam::unit`], [`ErrorParam::typical`]): a position error (X, Y, Z) is a
/// length in mm, an orientation error (A, B, C) an angle in rad.
fn unit_of(p: &ErrorParam) -> (Unit, f64) {
    (p.unit(), p.typical())
}

fn set(o: &Object, k: &str, v: &JsValue) -> Result<(), JsError> {
    Reflect::set(o, &JsValue::from_str(k), v)
        .map(|_| ())
        .map_err(|_| JsError::new(&format!("could not set `{k}` on the result")))
}

/// A sensitivity matrix as `{ids, curves, params, parameters, units, scales, rows, cols,
/// values}`, `values` a Float64Array in column-major order (nalgebra's storage):
/// `values[k * rows + i]` is the defect (mm) at point `ids[i]` per unit of `params[k]`
/// (`parameters[k]` its `{kind, name, unit}`, `units[k]` the same unit, drawn per `scales[k]`).
fn matrix_to_js(m: &SensitivityMatrix, params: &[ErrorParam]) -> Result<JsValue, JsError> {
    let o = Object::new();
    let (units, scales): (Vec<Unit>, Vec<f64>) = params.iter().map(unit_of).unzip();
    let ids: Vec<ParamId> = m.errors.iter().map(|e| ParamId::Machine(*e)).collect();
    set(&o, "ids", &to_js(&m.ids)?)?;
    set(&o, "curves", &to_js(&m.curves)?)?;
    set(&o, "params", &to_js(&m.names())?)?;
    set(&o, "parameters", &to_js(&ids)?)?;
    set(&o, "units", &to_js(&units)?)?;
    set(&o, "scales", &to_js(&scales)?)?;
    set(&o, "rows", &JsValue::from(m.values.nrows() as u32))?;
    set(&o, "cols", &JsValue::from(m.values.ncols() as u32))?;
    set(
        &o,
        "values",
        &Float64Array::from(m.values.as_slice()).into(),
    )?;
    Ok(o.into())
}

/// The coefficients of one parameter with its unit and typical size.
#[derive(Serialize)]
struct ParamCoefficients {
    #[serde(flatten)]
    coefficients: Coefficients,
    unit: Unit,
    /// The typical size the page draws it at (in `unit`).
    scale: f64,
}

#[derive(Serialize)]
struct PathCoefficients {
    /// What the path is.
    path: String,
    /// Tool-tip path length from the first sample (mm).
    s: Vec<f64>,
    /// The path parameter of each sample (`u` of the S-shape, or `φ` in degrees on the cone).
    x: Vec<f64>,
    x_label: String,
    coefficients: Vec<ParamCoefficients>,
}

fn coefficients_of(
    chain: &Chain,
    frames: &[crate::sensitivity::frenet::SurfaceFrame],
    params: Vec<ErrorParam>,
) -> Result<Vec<ParamCoefficients>, JsError> {
    params
        .into_iter()
        .map(|p| {
            let (unit, scale) = unit_of(&p);
            coefficients(chain, frames, p)
                .map(|coefficients| ParamCoefficients {
                    coefficients,
                    unit,
                    scale,
                })
                .map_err(|e| JsError::new(&e.to_string()))
        })
        .collect()
}

/// The curves of the prepared settings `prepared` (held by the worker for the page's `{machine,
/// l0, mode, branch}`), one call per change of them: `{sensitivity, path}`.
/// - `sensitivity`: the Figure-19 matrix at the 100 built-in points (`matrix_to_js`: `{ids,
///   curves, params, units, scales, rows, cols, values}`, column-major, mm per unit error);
/// - `path`: paper 002's coefficients `k, k_n, k_t, k_b` (mm per unit error) of each location
///   error along the S-shape flank path of `surface` (`"A"` or `"B"`) at `samples + 1` equally
///   spaced `u`: `{path, s, x, x_label, coefficients: [{param, unit, scale, k, k_n, k_t, k_b}]}`.
///   A is machined down-cutting, B up-cutting (so `n` is the outward normal).
#[wasm_bindgen(js_name = curvesFor)]
pub fn curves_for(
    prepared: &PreparedSettings,
    surface: &str,
    samples: usize,
) -> Result<JsValue, JsError> {
    let prepared = prepared.session().prepared();
    let wanted = surface.trim();
    let Some(&(_, s, cutting)) = SURFACES
        .iter()
        .find(|(name, _, _)| name.eq_ignore_ascii_case(wanted))
    else {
        return Err(JsError::new(&format!(
            "surface `{wanted}`: expected A or B"
        )));
    };
    let sopts = prepared.options();
    let params = prepared.errors();
    let part = prepared.part();
    let points = builtin_points(part);
    let m = prepared
        .axis_values(&points)
        .and_then(|q| prepared.sensitivity_matrix(&points, &q))
        .map_err(|e| JsError::new(&e.to_string()))?;
    let samples = samples.clamp(2, 2000);
    let frames =
        flank_frames(part, s, sopts, samples, cutting).map_err(|e| JsError::new(&e.to_string()))?;
    let path = PathCoefficients {
        path: format!("S-shape surface {surface}, {}", sopts.chain.code()),
        s: frames.iter().map(|f| f.s).collect(),
        x: (0..=samples).map(|k| k as f64 / samples as f64).collect(),
        x_label: "u".into(),
        coefficients: coefficients_of(&sopts.chain, &frames, params.clone())?,
    };
    let o = Object::new();
    set(&o, "sensitivity", &matrix_to_js(&m, &params)?)?;
    set(&o, "path", &to_js(&path)?)?;
    Ok(o.into())
}

/// The same coefficients along the M3 cone-frustum flank path of paper 002 §4 (`kind` `"M3_15"`
/// or `"M3_45"`, `offsets`: d = 62.5 mm, p = 30 mm) on paper 002's B-C tilting table, up-cutting
/// counter-clockwise, at `samples` angles φ over one turn; for each location error of that chain,
/// `k_n` is the normal defect per unit error (the cone's Figure-19 curve).
#[wasm_bindgen(js_name = coneCoefficients)]
pub fn cone_coefficients(kind: &str, offsets: bool, samples: usize) -> Result<JsValue, JsError> {
    let wanted = kind.trim().to_ascii_uppercase();
    let Some(&(_, make)) = CONES.iter().find(|(name, _)| *name == wanted) else {
        return Err(JsError::new(&format!(
            "unknown cone frustum `{wanted}` (expected M3_15 or M3_45)"
        )));
    };
    let mut cone = make();
    if offsets {
        cone = cone.with_offsets();
    }
    let chain = Chain::paper002();
    let (phis, frames) = cone_frames(&cone, &chain, Branch::Positive, samples.clamp(8, 4000))
        .map_err(|e| JsError::new(&e.to_string()))?;
    let params: Vec<ErrorParam> = crate::machine::location_errors::minimal_set(&chain)
        .free()
        .into_iter()
        .map(ErrorParam::Location)
        .collect();
    to_js(&PathCoefficients {
        path: format!(
            "cone frustum {kind}{}, {}",
            if offsets { " with offsets" } else { "" },
            chain.code()
        ),
        s: frames.iter().map(|f| f.s).collect(),
        x: phis.iter().map(|p| p.to_degrees()).collect(),
        x_label: "φ (degrees)".into(),
        coefficients: coefficients_of(&chain, &frames, params)?,
    })
}
