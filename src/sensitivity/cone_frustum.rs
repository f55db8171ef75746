//! The ISO 10791-7 M3 cone-frustum flank path used by paper 002 §4 (Table 3), as a tool path for
//! the surface-frame coefficients ([`super::frenet`]).
//!
//! Cone: bottom diameter `D`, half apex angle `θ`, axis inclined by `β` about +y,
//! `a = (sin β, 0, cos β)`; bottom centre `c` (the offsets: `d` along +x of the table and `p` up).
//! At angle `φ` (counter-clockwise seen from +z), with `e_r(φ)` the unit radial vector
//! perpendicular to `a`, the contact line is the generatrix from `B(φ) = c + (D/2)·e_r` along
//! `g = cos θ·a − sin θ·e_r`; the outward normal is `m = cos θ·e_r + sin θ·a`. A square-end mill
//! of radius `r` flank-mills it with its axis along `g` and its tip at `B + r·m`. Units: mm, rad.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Cone-frustum test piece and set-up (paper 002 Table 3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ConeFrustum {
    /// Bottom diameter `D` (mm)
    pub diameter: f64,
    /// Half apex angle `θ` (rad)
    pub half_apex: f64,
    /// Inclination `β` of the cone axis (rad)
    pub inclination: f64,
    /// Centre offset `d` along +x of the table (mm)
    pub centre_offset: f64,
    /// Height offset `p` (mm)
    pub height_offset: f64,
    /// Tool radius `r` (mm)
    pub tool_radius: f64,
}

impl ConeFrustum {
    /// M3_15: D = 80 mm, θ = 15°, β = 10°; without offsets; a 10 mm tool radius.
    pub fn m3_15() -> Self {
        Self {
            diameter: 80.0,
            half_apex: 15f64.to_radians(),
            inclination: 10f64.to_radians(),
            centre_offset: 0.0,
            height_offset: 0.0,
            tool_radius: 10.0,
        }
    }
    /// M3_45: D = 80 mm, θ = 45°, β = 30°.
    pub fn m3_45() -> Self {
        Self {
            half_apex: 45f64.to_radians(),
            inclination: 30f64.to_radians(),
            ..Self::m3_15()
        }
    }
    /// With paper 002's offsets: d = 62.5 mm, p = 30 mm.
    pub fn with_offsets(self) -> Self {
        Self {
            centre_offset: 62.5,
            height_offset: 30.0,
            ..self
        }
    }
    /// Tool tip and unit tool axis at angle `φ` (rad).
    pub fn tool_pose(&self, phi: f64) -> (Vector3<f64>, Vector3<f64>) {
        let (sb, cb) = self.inclination.sin_cos();
        let a = Vector3::new(sb, 0.0, cb);
        // Orthonormal basis perpendicular to a: e1 = y × a normalised (= (cb, 0, -sb)), e2 = a × e1.
        let e1 = Vector3::new(cb, 0.0, -sb);
        let e2 = a.cross(&e1);
        let er = e1 * phi.cos() + e2 * phi.sin();
        let (st, ct) = self.half_apex.sin_cos();
        let g = a * ct - er * st;
        let m = er * ct + a * st;
        let c = Vector3::new(self.centre_offset, 0.0, self.height_offset);
        let base = c + er * (0.5 * self.diameter);
        (base + m * self.tool_radius, g)
    }
}
