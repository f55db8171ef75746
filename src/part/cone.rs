//! The ISO 10791-7 M3 cone-frustum test pieces M3_15 and M3_45 (paper 002 §4.1, Table 3), as a
//! second part kind for the same flank-milling pipeline.
//!
//! Table 3: bottom diameter `D` = 80 mm for both; thickness `t` = 20 / 15 mm; inclination `β` =
//! 10° / 30°; half apex angle `θ` = 15° / 45°; centre offset `d` = 62.5 mm and height offset
//! `p` = 30 mm when the offsets are used (25 % of the rotary-table diameter and > 10 % of it).
//!
//! **Model (our reading of Table 3 and Fig. 12, whose drawing is not in the text).** The flank is
//! the cone of half apex angle `θ` narrowing upward; the thickness `t` is the frustum's height
//! along its axis. The cone axis `a = (sin β, 0, cos β)` is inclined by `β` from the machine Z
//! axis, about Y, toward +X. The bottom circle (radius `D/2`) is centred at `O = (d, 0, p)`
//! (`d = p = 0` without offsets). With `e1 = (cos β, 0, -sin β)`, `e2 = (0, 1, 0)`,
//! `e(φ) = cos φ·e1 + sin φ·e2` and `φ = 2πu`:
//!
//! `C0(u) = O + (D/2)·e(φ)`, `C1(u) = O + t·a + r1·e(φ)`, `r1 = D/2 - t·tan θ`,
//! `S(u,v) = (1-v)·C0 + v·C1` (the ruled form of eq. 1, paper 000).
//!
//! So the radius at height `z` above the bottom (along `a`) is `D/2 - z·tan θ`, the rulings make the
//! angle `θ` with the axis, and the outward normal is `N = cos θ·e(φ) + sin θ·a`. `u` runs
//! counter-clockwise about `a` and is periodic. Since `R × T` points toward the axis, the outward
//! normal sign is `-1`.
//!
//! **Flank path.** As eq. 2: `T_tool = C1 + 10·N(u,1) - L_tool·R`, with the tip
//! `L_tool = t/cos θ + 5 mm` below the top circle, i.e. 5 mm below the bottom edge along the
//! ruling (the S-shape's tip is 4-5 mm below its bottom edge too). A cone is developable and
//! convex, so the cylinder touches it along the whole ruling: the exact envelope leaves no
//! overcut (a closed-form check of the envelope code). Units: mm, rad.

use std::f64::consts::PI;

use nalgebra::Vector3;
use serde::ser::SerializeStruct;
use serde::Serialize;

use super::flat::Flat;
use super::frame::Section;
use super::ruled::RuledPart;
use super::s_shape::Surface;
use crate::geometry::{CurveDerivs, GeometryError};

/// Distance of the flank tool's tip below the bottom edge of the cone, along the ruling (mm).
pub const TIP_BELOW_BOTTOM: f64 = 5.0;
/// Centre offset `d` used with offsets in paper 002 (mm).
pub const PAPER_002_CENTER_OFFSET: f64 = 62.5;
/// Height offset `p` used with offsets in paper 002 (mm).
pub const PAPER_002_HEIGHT_OFFSET: f64 = 30.0;

/// A cone-frustum test piece (paper 002 Table 3).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConeFrustum {
    /// `M3_15` or `M3_45` (or a custom name)
    pub name: String,
    /// `D`, diameter of the bottom circle (mm)
    pub bottom_diameter: f64,
    /// `t`, height of the frustum along its axis (mm)
    pub thickness: f64,
    /// `β`, inclination of the cone axis from machine Z (rad)
    pub inclination: f64,
    /// `θ`, half apex angle (rad)
    pub half_apex: f64,
    /// `d`, offset of the bottom centre along X (mm)
    pub center_offset: f64,
    /// `p`, offset of the bottom centre along Z (mm)
    pub height_offset: f64,
}

impl ConeFrustum {
    /// Validates: `D, t > 0`, `0 < θ < π/2`, `|β| < π/2`, a positive top radius, finite offsets.
    pub fn try_new(
        name: &str,
        bottom_diameter: f64,
        thickness: f64,
        inclination: f64,
        half_apex: f64,
        center_offset: f64,
        height_offset: f64,
    ) -> Result<Self, GeometryError> {
        let top = 0.5 * bottom_diameter - thickness * half_apex.tan();
        let ok = bottom_diameter.is_finite()
            && bottom_diameter > 0.0
            && thickness.is_finite()
            && thickness > 0.0
            && half_apex > 0.0
            && half_apex < 0.5 * PI
            && inclination.abs() < 0.5 * PI
            && top > 0.0
            && center_offset.is_finite()
            && height_offset.is_finite();
        if !ok {
            return Err(GeometryError::BadCone {
                bottom_diameter,
                thickness,
                inclination,
                half_apex,
                top_radius: top,
            });
        }
        Ok(Self {
            name: name.to_string(),
            bottom_diameter,
            thickness,
            inclination,
            half_apex,
            center_offset,
            height_offset,
        })
    }

    fn table_3(name: &str, thickness: f64, beta_deg: f64, theta_deg: f64, offsets: bool) -> Self {
        let (d, p) = if offsets {
            (PAPER_002_CENTER_OFFSET, PAPER_002_HEIGHT_OFFSET)
        } else {
            (0.0, 0.0)
        };
        Self {
            name: name.to_string(),
            bottom_diameter: 80.0,
            thickness,
            inclination: beta_deg.to_radians(),
            half_apex: theta_deg.to_radians(),
            center_offset: d,
            height_offset: p,
        }
    }

    /// ISO 10791-7 M3_15: D 80, t 20, β 10°, θ 15°; with `offsets`, d = 62.5 and p = 30 mm.
    pub fn m3_15(offsets: bool) -> Self {
        Self::table_3("M3_15", 20.0, 10.0, 15.0, offsets)
    }

    /// ISO 10791-7 M3_45: D 80, t 15, β 30°, θ 45°; with `offsets`, d = 62.5 and p = 30 mm.
    pub fn m3_45(offsets: bool) -> Self {
        Self::table_3("M3_45", 15.0, 30.0, 45.0, offsets)
    }

    /// Unit cone axis `a`.
    pub fn axis(&self) -> Vector3<f64> {
        let b = self.inclination;
        Vector3::new(b.sin(), 0.0, b.cos())
    }

    /// Centre `O` of the bottom circle (mm).
    pub fn base_center(&self) -> Vector3<f64> {
        Vector3::new(self.center_offset, 0.0, self.height_offset)
    }

    /// Radius of the cone at height `z` above the bottom along the axis: `D/2 - z·tan θ` (mm).
    pub fn radius_at_height(&self, z: f64) -> f64 {
        0.5 * self.bottom_diameter - z * self.half_apex.tan()
    }

    /// Length of a ruling from the bottom to the top circle: `t / cos θ` (mm).
    pub fn slant_height(&self) -> f64 {
        self.thickness / self.half_apex.cos()
    }

    /// `e(φ)` and `de/dφ`.
    fn radial(&self, phi: f64) -> (Vector3<f64>, Vector3<f64>) {
        let b = self.inclination;
        let e1 = Vector3::new(b.cos(), 0.0, -b.sin());
        let e2 = Vector3::y();
        (
            e1 * phi.cos() + e2 * phi.sin(),
            -e1 * phi.sin() + e2 * phi.cos(),
        )
    }
}

impl RuledPart for ConeFrustum {
    fn surfaces(&self) -> &'static [Surface] {
        &[Surface::A]
    }

    /// Closed form: with `φ = 2πu`, `C = c + r·e(φ)`, `C' = 2πr·e'(φ)`, `C'' = -(2π)²r·e(φ)`.
    fn section_at(&self, _s: Surface, u: f64) -> Section {
        let w = 2.0 * PI;
        let (e, de) = self.radial(w * u);
        let r0 = self.radius_at_height(0.0);
        let r1 = self.radius_at_height(self.thickness);
        let o = self.base_center();
        let top = o + self.axis() * self.thickness;
        let curve = |c: Vector3<f64>, r: f64| CurveDerivs {
            point: c + e * r,
            d1: de * (w * r),
            d2: -e * (w * w * r),
        };
        Section {
            c0: curve(o, r0),
            c1: curve(top, r1),
            d: curve(top - o, r1 - r0),
        }
    }

    fn normal_sign(&self, _s: Surface) -> f64 {
        -1.0
    }

    fn tip_offset(&self) -> f64 {
        self.slant_height() + TIP_BELOW_BOTTOM
    }

    fn closed(&self) -> bool {
        true
    }
}

/// A measurement point on a cone frustum.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConePoint {
    /// 1-based, level by level, counter-clockwise from `φ = 0`
    pub id: usize,
    /// height of the measurement circle above the bottom along the axis (mm)
    pub level: f64,
    /// `u = φ/2π` and `v = level/t`
    pub u: f64,
    pub v: f64,
    /// the point (mm) and its outward unit normal
    pub point: Vector3<f64>,
    pub normal: Vector3<f64>,
    /// contact height above the flank tool's tip (mm)
    pub h: f64,
}

impl ConePoint {
    /// The geometry columns shared with every part's points.
    pub fn flat(&self) -> Flat<'_> {
        Flat {
            u: self.u,
            v: self.v,
            point: &self.point,
            normal: &self.normal,
            h: self.h,
        }
    }
}

/// Flat serde form: `{id, level, u, v, x, y, z, nx, ny, nz, h}`.
impl Serialize for ConePoint {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("ConePoint", 11)?;
        st.serialize_field("id", &self.id)?;
        st.serialize_field("level", &self.level)?;
        self.flat().write_fields(&mut st)?;
        st.end()
    }
}

/// Levels of the built-in cone points, as fractions of the thickness.
pub const CONE_LEVELS: [f64; 2] = [0.25, 0.75];
/// Built-in points per level (every 15°).
pub const CONE_POINTS_PER_LEVEL: usize = 24;

impl ConeFrustum {
    /// `per_level` equally spaced points (from `φ = 0`, counter-clockwise) on each circle at the
    /// heights `levels` (mm above the bottom, along the axis).
    pub fn points(&self, levels: &[f64], per_level: usize) -> Vec<ConePoint> {
        let mut out = Vec::with_capacity(levels.len() * per_level);
        for &level in levels {
            let v = level / self.thickness;
            for k in 0..per_level {
                let u = k as f64 / per_level as f64;
                let f = self.frame_at(Surface::A, u, v);
                out.push(ConePoint {
                    id: out.len() + 1,
                    level,
                    u,
                    v,
                    point: f.point,
                    normal: f.n,
                    h: crate::part::ruled::contact_height(self, Surface::A, u, v),
                });
            }
        }
        out
    }

    /// The built-in points: 24 per circle at 25 % and 75 % of the thickness.
    pub fn builtin_points(&self) -> Vec<ConePoint> {
        let levels: Vec<f64> = CONE_LEVELS.iter().map(|f| f * self.thickness).collect();
        self.points(&levels, CONE_POINTS_PER_LEVEL)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::toolpath::{tool_pose, FlankPath, TOOL_RADIUS};

    fn both() -> Vec<ConeFrustum> {
        vec![
            ConeFrustum::m3_15(false),
            ConeFrustum::m3_15(true),
            ConeFrustum::m3_45(false),
            ConeFrustum::m3_45(true),
        ]
    }

    /// Distance of `x` from the cone axis and its height along it.
    fn cyl(c: &ConeFrustum, x: &Vector3<f64>) -> (f64, f64) {
        let rel = x - c.base_center();
        let z = rel.dot(&c.axis());
        ((rel - c.axis() * z).norm(), z)
    }

    #[test]
    fn table_3_top_radii() {
        // closed form: 40 - 20 tan 15° and 40 - 15 tan 45°
        assert_near!(
            ConeFrustum::m3_15(false).radius_at_height(20.0),
            34.641_016_151_377_55,
            1e-12
        );
        assert_near!(
            ConeFrustum::m3_45(false).radius_at_height(15.0),
            25.0,
            1e-12
        );
    }

    #[test]
    fn radius_at_height_and_half_apex_angle() {
        for c in both() {
            for i in 0..40 {
                let u = i as f64 / 40.0 + 0.003;
                for v in [0.0, 0.3, 1.0] {
                    let f = c.frame_at(Surface::A, u, v);
                    let (r, z) = cyl(&c, &f.point);
                    assert_near!(z, v * c.thickness, 1e-12);
                    assert_near!(r, c.radius_at_height(z), 1e-12);
                    // the ruling makes the half apex angle with the axis
                    assert_near!(f.r.dot(&c.axis()).acos(), c.half_apex, 1e-12);
                    // outward normal: cos θ radially out, sin θ up the axis, ⊥ ruling
                    let radial = (f.point - c.base_center() - c.axis() * z) / r;
                    assert_near!(f.n.dot(&radial), c.half_apex.cos(), 1e-12);
                    assert_near!(f.n.dot(&c.axis()), c.half_apex.sin(), 1e-12);
                    assert_near!(f.n.dot(&f.r), 0.0, 1e-12);
                }
            }
        }
    }

    #[test]
    fn flank_path_geometry() {
        for c in both() {
            let beta = c.inclination;
            let theta = c.half_apex;
            let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
            for i in 0..=720 {
                let u = i as f64 / 720.0;
                let pose = tool_pose(&c, Surface::A, u);
                // axis along the ruling, 10 mm off the cone along N, tip 5 mm below the bottom
                let f0 = c.frame_at(Surface::A, u, 0.0);
                let rel = f0.point - pose.tip;
                assert_near!(pose.axis.dot(&f0.r), 1.0, 1e-12);
                assert_near!(
                    (rel - pose.axis * rel.dot(&pose.axis)).norm(),
                    TOOL_RADIUS,
                    1e-9
                );
                assert_near!(rel.dot(&pose.axis), TIP_BELOW_BOTTOM, 1e-9);
                let tilt = pose.axis.z.acos();
                lo = lo.min(tilt);
                hi = hi.max(tilt);
            }
            // the tool tilts from machine Z between |β - θ| and β + θ around the cone
            assert_near!(lo, (beta - theta).abs(), 1e-5);
            assert_near!(hi, beta + theta, 1e-5);
        }
    }

    #[test]
    fn developable_cone_has_no_overcut() {
        for c in both() {
            let path = FlankPath::new(&c, Surface::A);
            for p in c.builtin_points() {
                let hit = path
                    .deviation_at(&p.point, &p.normal, p.u, TOOL_RADIUS)
                    .unwrap();
                assert_near!(hit.deviation, 0.0, 1e-9);
                assert_near!(p.h, c.tip_offset() - (1.0 - p.v) * c.slant_height(), 1e-12);
            }
            assert_eq!(c.builtin_points().len(), 48);
        }
    }

    #[test]
    fn projection_wraps_around_the_closed_cone() {
        let c = ConeFrustum::m3_45(true);
        for (u, d) in [(0.0, 0.4), (0.999, -0.3), (0.5, 1.2)] {
            let f = c.frame_at(Surface::A, u, 0.6);
            let pr = crate::part::project(&c, &(f.point + f.n * d)).unwrap();
            assert_near!(pr.distance, d, 1e-10);
            assert_near!((pr.foot - f.point).norm(), 0.0, 1e-8);
            assert!(!pr.clamped);
        }
    }

    #[test]
    fn closed_form_derivatives_match_central_differences() {
        use crate::tolerance::FD_REL;
        let c = ConeFrustum::m3_15(true);
        let h = 1e-6;
        for i in 0..50 {
            let u = i as f64 / 50.0 + 0.01;
            let s = c.section_at(Surface::A, u);
            let (sp, sm) = (
                c.section_at(Surface::A, u + h),
                c.section_at(Surface::A, u - h),
            );
            for (d, p, m) in [
                (s.c0, sp.c0, sm.c0),
                (s.c1, sp.c1, sm.c1),
                (s.d, sp.d, sm.d),
            ] {
                let fd1 = (p.point - m.point) / (2.0 * h);
                let fd2 = (p.d1 - m.d1) / (2.0 * h);
                assert!((d.d1 - fd1).norm() <= FD_REL * (1.0 + d.d1.norm()));
                assert!((d.d2 - fd2).norm() <= FD_REL * (1.0 + d.d2.norm()));
            }
            assert_near!((s.d.point - (s.c1.point - s.c0.point)).norm(), 0.0, 1e-12);
        }
    }

    #[test]
    fn rejects_impossible_cones() {
        // the top radius would be 40 - 50 tan 45° < 0
        let e = ConeFrustum::try_new("x", 80.0, 50.0, 0.1, PI / 4.0, 0.0, 0.0).unwrap_err();
        assert!(e.to_string().contains("top radius"), "{e}");
        assert!(ConeFrustum::try_new("ok", 80.0, 20.0, 0.1, 0.2, 0.0, 0.0).is_ok());
    }
}
