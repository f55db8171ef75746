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
