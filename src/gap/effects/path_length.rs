//! Tool-tip path length along the flank path (eq. 2): `s(u) = ∫₀ᵘ |dT_tool/du| du` on each
//! surface, A machined first then B (effects.md), so a point of B has `s = s_A,total + s_B(u)`.
//! Composite Simpson rule on [`PATH_STEPS`] intervals per surface (the tip speed is smooth;
//! agreement with the reference `s` column is checked in tests).

use crate::part::{SShape, Surface};
use crate::toolpath::flank::tool_pose_derivs;

/// Simpson intervals per surface.
pub const PATH_STEPS: usize = 4000;

/// `|dT_tool/du|` (mm per unit u).
fn speed(part: &SShape, s: Surface, u: f64) -> f64 {
    tool_pose_derivs(part, s, u).tip_u.norm()
}

/// Simpson integral of the tip speed over `[a, b]` on a grid proportional to `b − a`.
fn segment(part: &SShape, s: Surface, a: f64, b: f64) -> f64 {
    let m = (((PATH_STEPS as f64) * (b - a)).ceil() as usize).max(2);
    let m = m + m % 2;
    let h = (b - a) / m as f64;
    let mut acc = speed(part, s, a) + speed(part, s, b);
    for k in 1..m {
        let w = if k % 2 == 1 { 4.0 } else { 2.0 };
        acc += w * speed(part, s, a + k as f64 * h);
    }
    acc * h / 3.0
}

/// Tip path length from `u = 0` to `u` on one surface (mm).
pub fn surface_path_length(part: &SShape, s: Surface, u: f64) -> f64 {
    segment(part, s, 0.0, u.clamp(0.0, 1.0))
}

/// Tip path lengths at several `u` of one surface (mm), integrating once over the sorted `u`.
pub fn surface_path_lengths(part: &SShape, s: Surface, us: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..us.len()).collect();
    idx.sort_by(|&a, &b| us[a].total_cmp(&us[b]));
    let mut out = vec![0.0; us.len()];
    let (mut prev, mut acc) = (0.0, 0.0);
    for i in idx {
        let u = us[i].clamp(0.0, 1.0);
        if u > prev {
            acc += segment(part, s, prev, u);
            prev = u;
        }
        out[i] = acc;
    }
    out
}

/// Tool-tip path length from the start of A (A then B) to parameter `u` on surface `s` (mm).
pub fn path_length(part: &SShape, s: Surface, u: f64) -> f64 {
    match s {
        Surface::A => surface_path_length(part, Surface::A, u),
        Surface::B => {
            surface_path_length(part, Surface::A, 1.0) + surface_path_length(part, Surface::B, u)
        }
    }
}

/// Total path length, A then B (mm).
pub fn total_path_length(part: &SShape) -> f64 {
    surface_path_length(part, Surface::A, 1.0) + surface_path_length(part, Surface::B, 1.0)
}
