//! The local frame of a ruled surface of the S-shape and its derivatives (paper 000 §3.1,
//! Fig. 7; conventions of `shared/spec/s-shape.md`).
//!
//! With `S(u,v) = (1-v)·C0(u) + v·C1(u)` (eq. 1) and `D(u) = C1(u) - C0(u)`:
//!
//! - `R(u) = D/|D|`: the ruling, pointing up; it is the flank tool axis. `D` is evaluated as a
//!   B-spline of its own (control points `P1_i - P0_i`, same basis), so it is **exactly** vertical on
//!   `u ∈ [6/13, 8/13]` where the two curves share control points 7-11.
//! - `T(u,v) = S_u/|S_u|` with `S_u = (1-v)·C0' + v·C1'`. The paper states `T ⊥ R`; that is false
//!   (|R·T| reaches 0.28), so `T` is *not* used to build an orthonormal frame.
//! - `N(u,v) = s·(R × T)/|R × T|`, `s = +1` on A and `-1` on B: the unit outward normal (it is the
//!   surface normal, since `R ∥ S_v = D`).
//!
//! Derivatives (for the envelope condition eq. 5 and the closest-point projection), with
//! `W = R × S_u`:
//! `R_u = (D' - R (R·D'))/|D|`, `W_u = R_u × S_u + R × S_uu`, `W_v = R × D'` (since `S_uv = D'`),
//! `N_• = s·(W_• - n (n·W_•))/|W|` with `n = W/|W|`. All are checked against central differences
//! in the tests. Units: mm for points, unit vectors dimensionless, derivatives per unit `u`/`v`.

use nalgebra::Vector3;

use super::s_shape::{SShape, Surface};
use crate::geometry::bspline::MAX_STACK_DEGREE;
use crate::geometry::{BSplineCurve, CurveDerivs};

/// The frame at `S(u, v)`: point (mm) and three unit vectors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// `S(u,v)` (mm)
    pub point: Vector3<f64>,
    /// `R(u)`, unit ruling pointing from `C0` up to `C1` (the tool axis)
    pub r: Vector3<f64>,
    /// `T(u,v)`, unit tangent of the curve `v = const` in increasing `u` (not ⊥ `R` in general)
    pub t: Vector3<f64>,
    /// `N(u,v)`, unit outward normal
    pub n: Vector3<f64>,
}

/// Value and derivatives of `C0`, `C1` and `D = C1 - C0` at one `u` (mm per unit `u`ⁿ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    pub c0: CurveDerivs,
    pub c1: CurveDerivs,
    /// `D = C1 - C0` evaluated as the difference spline
    pub d: CurveDerivs,
}

/// The frame with the partial derivatives the envelope and projection need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameDerivs {
    pub frame: Frame,
    /// `∂S/∂u` (mm)
    pub s_u: Vector3<f64>,
    /// `∂S/∂v = D(u)` (mm)
    pub s_v: Vector3<f64>,
    /// `∂²S/∂u²` (mm)
    pub s_uu: Vector3<f64>,
    /// `dR/du`
    pub r_u: Vector3<f64>,
    /// `∂N/∂u`
    pub n_u: Vector3<f64>,
    /// `∂N/∂v`
    pub n_v: Vector3<f64>,
}

/// Whether curves `[C0, C1]` share one non-rational basis (the same degree, at most
/// [`MAX_STACK_DEGREE`], and knots, every weight 1): then [`SShape::section_at`] evaluates the
/// basis once for both curves and their difference.
pub(crate) fn share_one_basis([c0, c1]: &[BSplineCurve; 2]) -> bool {
    let rational = c0.weights().iter().chain(c1.weights()).any(|w| *w != 1.0);
    !rational
        && c0.knots() == c1.knots()
        && c0.degree() == c1.degree()
        && c0.degree() <= MAX_STACK_DEGREE
}

/// Derivative of `x/|x|` given `x` and `x'`.
pub(crate) fn unit_derivative(x: &Vector3<f64>, dx: &Vector3<f64>) -> Vector3<f64> {
    let len = x.norm();
    let e = x / len;
    (dx - e * e.dot(dx)) / len
}

impl SShape {
    /// `C0`, `C1` and `D = C1 - C0` with first and second derivatives at `u` (clamped to [0, 1]).
    ///
    /// `D` uses one basis evaluation applied to the control-point differences `P1_i - P0_i`, so its
    /// x and y components are exactly 0 where those differences are (the vertical zone).
    pub fn section_at(&self, s: Surface, u: f64) -> Section {
        self.section_upto(s, u, 2)
    }

    /// [`Self::section_at`] without the second derivatives (`d2` = 0): the same arithmetic for
    /// the points and first derivatives, which is all a frame needs.
    pub fn section1_at(&self, s: Surface, u: f64) -> Section {
        self.section_upto(s, u, 1)
    }

    /// The section with derivatives up to order `nd` (1 or 2; higher-order fields 0 on the
    /// shared-basis path).
    #[inline]
    fn section_upto(&self, s: Surface, u: f64, nd: usize) -> Section {
        let [c0, c1] = self.curves(s);
        if !self.one_basis(s) {
            let d0 = c0.derivs_at(u);
            let d1 = c1.derivs_at(u);
            return Section {
                c0: d0,
                c1: d1,
                d: CurveDerivs {
                    point: d1.point - d0.point,
                    d1: d1.d1 - d0.d1,
                    d2: d1.d2 - d0.d2,
                },
            };
        }
        // one basis evaluation for C0, C1 and D (non-rational, shared knots)
        let (lo, hi) = c0.domain();
        let uc = u.clamp(lo, hi);
        let p = c0.degree();
        let (span, ders) = if nd >= 2 {
            c0.basis_derivs2(uc)
        } else {
            c0.basis_derivs1(uc)
        };
        let mut out = [[Vector3::zeros(); 3]; 3];
        for (k, row) in ders.iter().enumerate().take(nd.min(2).min(p) + 1) {
            for (j, nb) in row[..=p].iter().enumerate() {
                let i = span - p + j;
                let (p0, p1) = (c0.control_points()[i], c1.control_points()[i]);
                out[0][k] += p0 * *nb;
                out[1][k] += p1 * *nb;
                out[2][k] += (p1 - p0) * *nb;
            }
        }
        let cd = |o: [Vector3<f64>; 3]| CurveDerivs {
            point: o[0],
            d1: o[1],
            d2: o[2],
        };
        Section {
            c0: cd(out[0]),
            c1: cd(out[1]),
            d: cd(out[2]),
        }
    }

    /// The ruling `R(u)` (unit, pointing up) and `dR/du`.
    pub fn ruling_at(&self, s: Surface, u: f64) -> (Vector3<f64>, Vector3<f64>) {
        let d = self.section_at(s, u).d;
        (d.point.normalize(), unit_derivative(&d.point, &d.d1))
    }

    /// The frame `{S, R, T, N}` at `(u, v)` (s-shape.md). `u` is clamped to [0, 1]; `v` is not
    /// (the ruled surface extends linearly beyond Z 0..30).
    pub fn frame_at(&self, s: Surface, u: f64, v: f64) -> Frame {
        frame_from(&self.section1_at(s, u), v, s.normal_sign())
    }

    /// The frame with its first derivatives in `u` and `v` (see the module doc for the formulas).
    pub fn frame_derivs_at(&self, s: Surface, u: f64, v: f64) -> FrameDerivs {
        frame_derivs_from(&self.section_at(s, u), v, s.normal_sign())
    }
}

/// The frame alone (no derivatives) of any ruled surface from its section at one `u`: only the
/// points and first derivatives of the section are used.
pub fn frame_from(sec: &Section, v: f64, sign: f64) -> Frame {
    let s_u = sec.c0.d1 * (1.0 - v) + sec.c1.d1 * v;
    let r = sec.d.point.normalize();
    Frame {
        point: sec.c0.point * (1.0 - v) + sec.c1.point * v,
        r,
        t: s_u.normalize(),
        n: r.cross(&s_u).normalize() * sign,
    }
}

/// The frame of any ruled surface `(1-v)·C0 + v·C1` from its section at one `u`, with the normal
/// sign `sign` (`N = sign·unit(R × S_u)`); the formulas of the module doc.
pub fn frame_derivs_from(sec: &Section, v: f64, sign: f64) -> FrameDerivs {
    let dd = sec.d;
    let frame = frame_from(sec, v, sign);
    let s_u = sec.c0.d1 * (1.0 - v) + sec.c1.d1 * v;
    let s_uu = sec.c0.d2 * (1.0 - v) + sec.c1.d2 * v;
    let r = frame.r;
    let r_u = unit_derivative(&dd.point, &dd.d1);
    let w = r.cross(&s_u);
    let w_u = r_u.cross(&s_u) + r.cross(&s_uu);
    let w_v = r.cross(&dd.d1);
    FrameDerivs {
        frame,
        s_u,
        s_v: dd.point,
        s_uu,
        r_u,
        n_u: unit_derivative(&w, &w_u) * sign,
        n_v: unit_derivative(&w, &w_v) * sign,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::FD_REL;

    fn fd_ok(a: &Vector3<f64>, fd: &Vector3<f64>) -> bool {
        (a - fd).norm() <= FD_REL * (1.0 + a.norm())
    }

    /// One basis for both curves is decided with the curves: the built-in surfaces share one; a
    /// curve written as rational (every weight 2: the same curve, the weights cancel) does not,
    /// and its sections, each curve evaluated on its own, are the shared basis's to 1e-9 mm
    /// (rounding of the two evaluations; the points are ~100 mm, the derivatives ~1000 mm).
    #[test]
    fn one_basis_is_decided_with_the_curves() {
        let p = SShape::iso();
        assert!(Surface::BOTH.iter().all(|&s| p.one_basis(s)));
        let [c0, c1] = p.curves(Surface::A).clone();
        let n = c1.control_points().len();
        let weighted = BSplineCurve::try_new_rational(
            c1.degree(),
            c1.knots().to_vec(),
            c1.control_points().to_vec(),
            vec![2.0; n],
        )
        .unwrap();
        let pair = [c0, weighted];
        assert!(!share_one_basis(&pair));
        let q = SShape::new(pair, p.curves(Surface::B).clone());
        assert!(!q.one_basis(Surface::A) && q.one_basis(Surface::B));
        for i in 0..=40 {
            let u = i as f64 / 40.0;
            let (x, y) = (p.section_at(Surface::A, u), q.section_at(Surface::A, u));
            for (a, b) in [(x.c0, y.c0), (x.c1, y.c1), (x.d, y.d)] {
                for (va, vb) in [(a.point, b.point), (a.d1, b.d1), (a.d2, b.d2)] {
                    assert!((va - vb).norm() < 1e-9, "u = {u}: {va:?} vs {vb:?}");
                }
            }
        }
    }

    #[test]
    fn frame_is_unit_and_normal_is_orthogonal_to_the_surface() {
        let p = SShape::iso();
        for s in Surface::BOTH {
            for i in 0..=100 {
                let u = i as f64 / 100.0;
                for v in [0.0, 11.0 / 30.0, 1.0] {
                    let f = p.frame_derivs_at(s, u, v);
                    assert_near!(f.frame.r.norm(), 1.0, 1e-14);
                    assert_near!(f.frame.t.norm(), 1.0, 1e-14);
                    assert_near!(f.frame.n.norm(), 1.0, 1e-14);
                    // N ⊥ S_u and N ⊥ S_v: it is the surface normal.
                    assert_near!(f.frame.n.dot(&f.s_u), 0.0, 1e-10);
                    assert_near!(f.frame.n.dot(&f.s_v), 0.0, 1e-10);
                    assert!(f.frame.r.z > 0.9, "R points up");
                }
            }
        }
    }

    #[test]
    fn ruling_is_exactly_vertical_on_the_shared_zone() {
        // s-shape.md: control points 7-11 are shared, so on u ∈ [6/13, 8/13] C1 - C0 = (0,0,30).
        let p = SShape::iso();
        for s in Surface::BOTH {
            for i in 0..=50 {
                let u = 6.0 / 13.0 + i as f64 * (2.0 / 13.0) / 50.0;
                let (r, r_u) = p.ruling_at(s, u);
                assert_eq!((r.x, r.y, r.z), (0.0, 0.0, 1.0), "u = {u}");
                assert_eq!(r_u.norm(), 0.0);
            }
        }
    }

    #[test]
    fn paper_claim_t_perpendicular_to_r_is_false() {
        // s-shape.md: |R·T| reaches about 0.28.
        let p = SShape::iso();
        let mut worst: f64 = 0.0;
        for s in Surface::BOTH {
            for i in 0..=2000 {
                let f = p.frame_at(s, i as f64 / 2000.0, 1.0);
                worst = worst.max(f.r.dot(&f.t).abs());
            }
        }
        assert!(worst > 0.2 && worst < 0.35, "max |R·T| = {worst}");
    }

    #[test]
    fn outward_normals_point_away_from_the_other_surface() {
        // Surface A lies on one side of B: at the same u, the other surface's point is behind N.
        let p = SShape::iso();
        for i in 1..20 {
            let u = i as f64 / 20.0;
            let fa = p.frame_at(Surface::A, u, 0.5);
            let fb = p.frame_at(Surface::B, u, 0.5);
            assert!((fb.point - fa.point).dot(&fa.n) < 0.0, "u = {u}");
            assert!((fa.point - fb.point).dot(&fb.n) < 0.0, "u = {u}");
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        let p = SShape::iso();
        let h = 1e-6;
        for s in Surface::BOTH {
            for i in 1..200 {
                let u = i as f64 / 200.0 + 1.3e-4;
                let v = 0.1 + 0.8 * (i % 7) as f64 / 7.0;
                let f = p.frame_derivs_at(s, u, v);
                let up = p.frame_derivs_at(s, u + h, v);
                let um = p.frame_derivs_at(s, u - h, v);
                let vp = p.frame_at(s, u, v + h);
                let vm = p.frame_at(s, u, v - h);
                let fd = |a: Vector3<f64>, b: Vector3<f64>| (a - b) / (2.0 * h);
                assert!(fd_ok(&f.s_u, &fd(up.frame.point, um.frame.point)));
                assert!(fd_ok(&f.s_uu, &fd(up.s_u, um.s_u)));
                assert!(fd_ok(&f.s_v, &fd(vp.point, vm.point)));
                assert!(fd_ok(&f.r_u, &fd(up.frame.r, um.frame.r)), "R_u at u = {u}");
                assert!(fd_ok(&f.n_u, &fd(up.frame.n, um.frame.n)), "N_u at u = {u}");
                assert!(fd_ok(&f.n_v, &fd(vp.n, vm.n)), "N_v at u = {u}");
            }
        }
    }
}
