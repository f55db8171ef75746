//! Tool-tip path length along the flank path (eq. 2): `s(u) = ∫₀ᵘ |dT_tool/du| du` on each
//! surface, A machined first then B (effects.md), so a point of B has `s = s_A,total + s_B(u)`.
//! The tables are [`crate::toolpath::tip_length::TipLength`]'s (agreement with the reference `s`
//! column is checked in tests); a part model takes them from its kept path model.

use crate::part::{SShape, Surface};
use crate::toolpath::tip_length::TipLength;

/// Tip path length from `u = 0` to `u` on one surface (mm).
pub fn surface_path_length(part: &SShape, s: Surface, u: f64) -> f64 {
    TipLength::new(part, s).at(part, u)
}

/// Tool-tip path length from the start of A (A then B) to parameter `u` on surface `s` (mm).
pub fn path_length(part: &SShape, s: Surface, u: f64) -> f64 {
    match s {
        Surface::A => surface_path_length(part, Surface::A, u),
        Surface::B => {
            TipLength::new(part, Surface::A).total() + surface_path_length(part, Surface::B, u)
        }
    }
}

/// Total path length, A then B (mm).
pub fn total_path_length(part: &SShape) -> f64 {
    Surface::BOTH
        .into_iter()
        .map(|s| TipLength::new(part, s).total())
        .sum()
}
