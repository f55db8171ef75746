//! wasm exports of the `geometry` stage: part points and frames.

use wasm_bindgen::prelude::*;

use super::to_js;
use crate::part::{builtin_points, SShape};

/// The 100 built-in measurement points of the S-shape (s-shape.md): an array of
/// `{id, curve, surface, u, v, x, y, z, nx, ny, nz, h}` (mm; `n` = outward unit normal,
/// `h` = contact height above the flank tool tip).
#[wasm_bindgen(js_name = builtinPoints)]
pub fn builtin_points_js() -> Result<JsValue, JsError> {
    to_js(&builtin_points(&SShape::iso()))
}

/// Deviation left by the flank path (paper 000 eq. 2, exact tool envelope) at the 100 built-in
/// points for a tool of radius `10 + d_r` mm: an array of `{id, curve, deviation}` (mm; + = material
/// left, - = overcut).
#[wasm_bindgen(js_name = envelopeDeviation)]
pub fn envelope_deviation_js(d_r: f64) -> Result<JsValue, JsError> {
    if !d_r.is_finite() {
        return Err(JsError::new(&format!(
            "tool radius error {d_r} mm is not a finite number"
        )));
    }
    let part = SShape::iso();
    let dev = crate::toolpath::points_deviation(&part, &builtin_points(&part), d_r)
        .map_err(|e| JsError::new(&e.to_string()))?;
    to_js(&dev)
}

/// Largest overcut of the flank path over each whole surface (Z 0..30) and where:
/// `[{surface, max_overcut, u, z}]` (mm; `max_overcut` > 0).
#[wasm_bindgen(js_name = surfaceMaxOvercut)]
pub fn surface_max_overcut_js() -> Result<JsValue, JsError> {
    let part = SShape::iso();
    let maxima = crate::part::Surface::BOTH
        .iter()
        .map(|s| crate::toolpath::surface_max_overcut(&part, *s))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| JsError::new(&e.to_string()))?;
    to_js(&maxima)
}

/// Most layers [`multilayer_deviation_js`] computes (the work grows with the count).
pub const MAX_LAYERS: usize = 1000;

/// Multi-layer flank milling with a tool rotation-profile error (paper 001 §2-3) at the 100
/// built-in points. `heights`/`radii`: the measured profile (mm above the tip, mm; same length,
/// heights increasing); `rho` (mm), `phi` (rad): tool setup error; `layers`, `pitch` (mm),
/// `cutting_length` (mm): the layer plan (last layer = nominal path, each earlier one `pitch`
/// higher). Returns `[{id, curve, deviation, layer, height, own_layer, own_deviation}]` (mm).
#[wasm_bindgen(js_name = multilayerDeviation)]
#[allow(clippy::too_many_arguments)]
pub fn multilayer_deviation_js(
    heights: Vec<f64>,
    radii: Vec<f64>,
    rho: f64,
    phi: f64,
    layers: usize,
    pitch: f64,
    cutting_length: f64,
) -> Result<JsValue, JsError> {
    use crate::toolpath::{multilayer_deviation, LayerPlan, ToolProfile};
    let err = |e: crate::toolpath::ToolpathError| JsError::new(&e.to_string());
    if heights.len() != radii.len() {
        return Err(JsError::new(&format!(
            "{} profile heights but {} radii",
            heights.len(),
            radii.len()
        )));
    }
    if layers > MAX_LAYERS {
        return Err(JsError::new(&format!(
            "{layers} layers: at most {MAX_LAYERS} are computed (a test piece is cut in a few)"
        )));
    }
    let table: Vec<(f64, f64)> = heights.into_iter().zip(radii).collect();
    let profile = ToolProfile::try_new(&table)
        .and_then(|p| p.with_setup_error(rho, phi))
        .map_err(err)?;
    let plan = LayerPlan::try_new(layers, pitch, cutting_length).map_err(err)?;
    let part = SShape::iso();
    let res = multilayer_deviation(&part, &builtin_points(&part), &profile, &plan).map_err(err)?;
    to_js(&res)
}

/// The built-in points of a cone-frustum test piece (paper 002 Table 3): `kind` is `"M3_15"` or
/// `"M3_45"`, `offsets` places it with the paper's centre and height offsets (62.5 and 30 mm).
/// Returns `{cone: {name, bottom_diameter, thickness, inclination, half_apex, center_offset,
/// height_offset}, points: [{id, level, u, v, x, y, z, nx, ny, nz, h}]}` (mm, rad).
#[wasm_bindgen(js_name = conePoints)]
pub fn cone_points_js(kind: &str, offsets: bool) -> Result<JsValue, JsError> {
    use crate::part::ConeFrustum;
    let cone = match kind.trim().to_ascii_uppercase().as_str() {
        "M3_15" => ConeFrustum::m3_15(offsets),
        "M3_45" => ConeFrustum::m3_45(offsets),
        other => {
            return Err(JsError::new(&format!(
                "unknown cone frustum `{other}` (expected M3_15 or M3_45)"
            )))
        }
    };
    #[derive(serde::Serialize)]
    struct Out<'a> {
        cone: &'a ConeFrustum,
        points: Vec<crate::part::ConePoint>,
    }
    to_js(&Out {
        cone: &cone,
        points: cone.builtin_points(),
    })
}
