//! Rigid-body signatures: datum alignment (`setup_error`) and C-axis zero offset (`c_index`).
//!
//! The measured part rotated by `θz` about Z and shifted by `t`: a point moves by
//! `θz ẑ × p + t`, its deviation is `(θz ẑ × p + t)·N` with `ẑ × p = (−y, x, 0)`.
//! A C-axis offset `dC` (`C_real = C_cmd + dC`) turns the table, and the part, by `dC` about
//! the C axis; with `p = Rz(C)ᵀ(…)` (s-shape.md eq. 8-10) the tool's path in the part frame turns by
//! `−dC`: `∂p/∂C·N = −(ẑ × p)·N`, the negative of `setup_error.thetaz` (reference README).

use super::EffectPoint;

/// `(ẑ × p)·N` per rad.
fn rotation_z(p: &EffectPoint) -> f64 {
    -p.p.y * p.n.x + p.p.x * p.n.y
}

/// `setup_error.thetaz` (mm/rad), `.tx`, `.ty` (mm/mm) columns.
pub fn setup_error(points: &[EffectPoint]) -> Vec<Vec<f64>> {
    vec![
        points.iter().map(rotation_z).collect(),
        points.iter().map(|p| p.n.x).collect(),
        points.iter().map(|p| p.n.y).collect(),
    ]
}

/// `c_index.dC` column (mm/rad).
pub fn c_index(points: &[EffectPoint]) -> Vec<Vec<f64>> {
    vec![points.iter().map(|p| -rotation_z(p)).collect()]
}
