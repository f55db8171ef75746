//! Tool-radius and tool-taper signatures (effects.md; paper 001 Table 2 for the rotation profile).
//!
//! A tool of radius `10 + dR` cuts `dR` deeper along the normal: deviation `−dR` (s-shape.md).
//! A taper makes the radius at height `h` above the tip `10 + dR0 + g·h`: deviation
//! `−(dR0 + g·h)`, so the Z11 (h ≈ 15.5) and Z25 (h ≈ 30) curves differ by `−g·14.5`.

use super::EffectPoint;

/// `tool_radius.dR` column: −1 per mm.
pub fn tool_radius(points: &[EffectPoint]) -> Vec<Vec<f64>> {
    vec![vec![-1.0; points.len()]]
}

/// `tool_taper.dR0` (−1 per mm) and `tool_taper.g` (−h per mm/mm) columns.
pub fn tool_taper(points: &[EffectPoint]) -> Vec<Vec<f64>> {
    vec![
        vec![-1.0; points.len()],
        points.iter().map(|p| -p.h).collect(),
    ]
}
