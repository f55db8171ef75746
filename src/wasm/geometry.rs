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
