//! Tool-tip path length along the flank path (eq. 2): `s(u) = ∫₀ᵘ |dT_tool/du| du` on each
//! surface, A machined first then B (effects.md), so a point of B has `s = s_A,total + s_B(u)`.
//! The tables are [`crate::toolpath::tip_length::TipLength`]'s (agreement with the reference `s`
//! column is checked in tests); a part model takes them from its kept path model
//! ([`crate::effects::path_model::PathModel::lengths`]), its points' `s` from
//! [`crate::effects::builtin::effect_points`].

use crate::part::{SShape, Surface};
use crate::toolpath::tip_length::TipLength;

/// Total path length, A then B (mm).
pub fn total_path_length(part: &SShape) -> f64 {
    Surface::BOTH
        .into_iter()
        .map(|s| TipLength::new(part, s).total())
        .sum()
}
