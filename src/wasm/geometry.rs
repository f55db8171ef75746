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
