//! wasm exports for the page's curves on any of the three machines: the Figure-19 matrix for the
//! analysis settings, and paper 002's surface-frame coefficients (eq. 11-14) along the S-shape
//! flank path and along the M3 cone-frustum path.

use wasm_bindgen::prelude::*;

use super::to_js;
use crate::analysis::{sensitivity_options, AnalysisOptions};
use crate::machine::{Branch, Chain, ErrorParam};
use crate::part::{builtin_points, SShape, Surface};
use crate::sensitivity::cone_frustum::ConeFrustum;
use crate::sensitivity::frenet::{coefficients, cone_frames, flank_frames, Cutting};
use crate::sensitivity::sensitivity_matrix;

fn options(options: JsValue) -> Result<AnalysisOptions, JsError> {
    if options.is_undefined() || options.is_null() {
        return Ok(AnalysisOptions::default());
    }
    super::from_js(options).map_err(|e| JsError::new(&format!("bad analysis settings: {e}")))
}

/// Figure-19 matrix at the 100 built-in points for the analysis settings `options`
/// (`{machine, l0, mode, branch}`): same result as `sensitivity` (`{ids, curves, params, rows,
/// cols, values}`, column-major, mm per unit error) but for the chosen chain.
#[wasm_bindgen(js_name = sensitivityFor)]
pub fn sensitivity_for(options_js: JsValue) -> Result<JsValue, JsError> {
    let opts = options(options_js)?;
    if !(opts.l0.is_finite() && opts.l0 > 0.0) {
        return Err(JsError::new(&format!(
            "L0 = {} mm is not a positive finite length",
            opts.l0
        )));
    }
    let part = SShape::iso();
    let m = sensitivity_matrix(&part, &builtin_points(&part), &sensitivity_options(&opts))
        .map_err(|e| JsError::new(&e.to_string()))?;
    super::machine::matrix_to_js(&m)
}

#[derive(serde::Serialize)]
struct PathCoefficients {
    /// What the path is.
    path: String,
    /// Tool-tip path length from the first sample (mm).
    s: Vec<f64>,
    /// The path parameter of each sample (`u` of the S-shape, or `φ` in degrees on the cone).
    x: Vec<f64>,
    x_label: String,
    coefficients: Vec<crate::sensitivity::frenet::Coefficients>,
}

/// Paper 002's coefficients `k, k_n, k_t, k_b` (mm per unit error) of each location error of the
/// chosen chain along the S-shape flank path of `surface` (`"A"` or `"B"`), at `samples + 1`
/// equally spaced `u`. A is machined down-cutting, B up-cutting (so `n` is the outward normal).
#[wasm_bindgen(js_name = pathCoefficients)]
pub fn path_coefficients(
    options_js: JsValue,
    surface: &str,
    samples: usize,
) -> Result<JsValue, JsError> {
    let opts = options(options_js)?;
    let (s, cutting) = match surface.trim() {
        "A" | "a" => (Surface::A, Cutting::Down),
        "B" | "b" => (Surface::B, Cutting::Up),
        other => return Err(JsError::new(&format!("surface `{other}`: expected A or B"))),
    };
    let sopts = sensitivity_options(&opts);
    let samples = samples.clamp(2, 2000);
    let frames = flank_frames(&SShape::iso(), s, &sopts, samples, cutting)
        .map_err(|e| JsError::new(&e.to_string()))?;
    let coefficients = sopts
        .params()
        .map_err(|e| JsError::new(&e.to_string()))?
        .into_iter()
        .map(|p| coefficients(&sopts.chain, &frames, p))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| JsError::new(&e.to_string()))?;
    to_js(&PathCoefficients {
        path: format!("S-shape surface {surface}, {}", sopts.chain.code()),
        s: frames.iter().map(|f| f.s).collect(),
        x: (0..=samples).map(|k| k as f64 / samples as f64).collect(),
        x_label: "u".into(),
        coefficients,
    })
}

/// The same coefficients along the M3 cone-frustum flank path of paper 002 §4 (`kind` `"M3_15"`
/// or `"M3_45"`, `offsets`: d = 62.5 mm, p = 30 mm) on paper 002's B-C tilting table, up-cutting
/// counter-clockwise, at `samples` angles φ over one turn; for each location error of that chain,
/// `k_n` is the normal defect per unit error (the cone's Figure-19 curve).
#[wasm_bindgen(js_name = coneCoefficients)]
pub fn cone_coefficients(kind: &str, offsets: bool, samples: usize) -> Result<JsValue, JsError> {
    let mut cone = match kind.trim().to_ascii_uppercase().as_str() {
        "M3_15" => ConeFrustum::m3_15(),
        "M3_45" => ConeFrustum::m3_45(),
        other => {
            return Err(JsError::new(&format!(
                "unknown cone frustum `{other}` (expected M3_15 or M3_45)"
            )))
        }
    };
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
    let coefficients = params
        .into_iter()
        .map(|p| coefficients(&chain, &frames, p))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| JsError::new(&e.to_string()))?;
    to_js(&PathCoefficients {
        path: format!(
            "cone frustum {kind}{}, {}",
            if offsets { " with offsets" } else { "" },
            chain.code()
        ),
        s: frames.iter().map(|f| f.s).collect(),
        x: phis.iter().map(|p| p.to_degrees()).collect(),
        x_label: "φ (degrees)".into(),
        coefficients,
    })
}
