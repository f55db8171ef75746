//! What the tool path, envelope and projection need of a test piece: ruled surfaces
//! `S(u,v) = (1-v)·C0(u) + v·C1(u)` given by their boundary curves (paper 000 eq. 1), each with an
//! outward normal sign, and where the flank tool's tip sits (eq. 2). Implemented by the S-shape
//! ([`super::SShape`]) and the cone frustums ([`super::ConeFrustum`]), so the same flank path,
//! envelope and projection code runs on both.

use nalgebra::Vector3;

use super::frame::{frame_derivs_from, Frame, FrameDerivs, Section};
use super::s_shape::{SShape, Surface};

/// Distance `L_tool` from the top curve down to the tool tip along the axis (mm), eq. 2.
pub const TIP_OFFSET: f64 = 35.0;

/// A part made of ruled flank surfaces.
pub trait RuledPart: std::fmt::Debug {
    /// The surfaces of the part (the S-shape: A and B; a cone frustum: its flank, as `A`).
    fn surfaces(&self) -> &'static [Surface];
    /// `C0`, `C1`, `D = C1 - C0` and their first two derivatives at `u ∈ [0, 1]` (mm).
    fn section_at(&self, s: Surface, u: f64) -> Section;
    /// Sign `s` of the outward normal `N = s·unit(R × S_u)`.
    fn normal_sign(&self, s: Surface) -> f64;
    /// Distance `L_tool` from the top curve `C1` down to the flank tool's tip along `R` (mm):
    /// `T_tool = C1 + R_tool·N(u,1) - L_tool·R` (eq. 2).
    fn tip_offset(&self) -> f64;
    /// True when `u` is periodic (a closed surface: `u = 0` and `u = 1` are the same ruling).
    fn closed(&self) -> bool {
        false
    }

    /// The frame `{S, R, T, N}` with its derivatives (see [`super::frame`]).
    fn frame_derivs_at(&self, s: Surface, u: f64, v: f64) -> FrameDerivs {
        frame_derivs_from(&self.section_at(s, u), v, self.normal_sign(s))
    }
    /// The frame `{S, R, T, N}` at `(u, v)`.
    fn frame_at(&self, s: Surface, u: f64, v: f64) -> Frame {
        self.frame_derivs_at(s, u, v).frame
    }
    /// `S(u, v)` (mm).
    fn point_at(&self, s: Surface, u: f64, v: f64) -> Vector3<f64> {
        let sec = self.section_at(s, u);
        sec.c0.point * (1.0 - v) + sec.c1.point * v
    }
}

impl RuledPart for SShape {
    fn surfaces(&self) -> &'static [Surface] {
        &Surface::BOTH
    }
    fn section_at(&self, s: Surface, u: f64) -> Section {
        SShape::section_at(self, s, u)
    }
    fn frame_at(&self, s: Surface, u: f64, v: f64) -> Frame {
        SShape::frame_at(self, s, u, v)
    }
    fn normal_sign(&self, s: Surface) -> f64 {
        s.normal_sign()
    }
    fn tip_offset(&self) -> f64 {
        TIP_OFFSET
    }
}

/// Contact height `h` of the surface point `S(u,v)` above the tool tip along the axis (mm):
/// `h = L_tool - (1-v)·|C1(u) - C0(u)|`, since `S(u,v) = C1 - (1-v)·D` lies on the ruling
/// that the tool touches from `C1` down.
pub fn contact_height<P: RuledPart + ?Sized>(part: &P, s: Surface, u: f64, v: f64) -> f64 {
    part.tip_offset() - (1.0 - v) * part.section_at(s, u).d.point.norm()
}
