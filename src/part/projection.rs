//! Closest-point projection of a 3-D point onto the nominal S-shape surfaces (or the surfaces of
//! any [`RuledPart`]; on a closed part such as a cone frustum `u` wraps around instead of being
//! clamped).
//!
//! For one surface, minimise `f(u,v) = ½|S(u,v) - p|²` (eq. 1 surface) with `u ∈ [0, 1]` and `v`
//! free (the ruled surface extends linearly past Z 0..30, so a point measured slightly above or
//! below the part still projects orthogonally):
//!
//! 1. start: the best of 401 rulings, each with its own closest `v = (p - C0)·D/|D|²`
//!    (searched coarse to fine, [`super::start_rulings`]);
//! 2. Newton on `∇f = [(S-p)·S_u, (S-p)·S_v]` with the Hessian
//!    `[[S_u·S_u + (S-p)·S_uu, S_u·S_v + (S-p)·D'], [·, S_v·S_v]]` (`S_vv = 0`, `S_uv = D'`),
//!    falling back to the Gauss–Newton matrix when that is not positive definite, with step
//!    halving on `f`; when `u` reaches 0 or 1 it is clamped there and only `v` is solved.
//!
//! Over the part's surfaces the one with the smaller `|p - foot|` wins. The result is the foot point,
//! its `(u, v)`, the outward normal `N(u,v)` there and the signed distance `(p - foot)·N` (mm):
//! **positive = outside the material** (same sign as a deviation, s-shape.md). At an interior
//! foot `p - foot ∥ N`; at a clamped end it is not, and `clamped` says so.

use nalgebra::{Matrix2, Vector2, Vector3};
use serde::Serialize;

use super::start_rulings::StartRulings;
use crate::geometry::GeometryError;
use crate::numerics::order::{argsort, sort_by_index};
use crate::part::frame::frame_derivs_from;
#[cfg(all(test, not(target_arch = "wasm32")))]
use crate::part::SShape;
use crate::part::{RuledPart, Section, Surface};

/// Result of a closest-point projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    pub surface: Surface,
    /// surface parameters of the foot point (`u ∈ [0,1]`, `v = z/30` for the nominal part)
    pub u: f64,
    pub v: f64,
    /// closest point on the surface (mm)
    pub foot: Vector3<f64>,
    /// outward unit normal `N(u,v)` at the foot
    pub normal: Vector3<f64>,
    /// `(p - foot)·N` (mm): + outside the material, - inside
    pub distance: f64,
    /// true when the foot is on the end `u = 0` or `u = 1` (then `p - foot` need not be ∥ `N`)
    pub clamped: bool,
}

/// Flat serde form: `{surface, u, v, x, y, z, nx, ny, nz, distance, clamped}`.
impl Serialize for Projection {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("Projection", 11)?;
        st.serialize_field("surface", &self.surface)?;
        st.serialize_field("u", &self.u)?;
        st.serialize_field("v", &self.v)?;
        st.serialize_field("x", &self.foot.x)?;
        st.serialize_field("y", &self.foot.y)?;
        st.serialize_field("z", &self.foot.z)?;
        st.serialize_field("nx", &self.normal.x)?;
        st.serialize_field("ny", &self.normal.y)?;
        st.serialize_field("nz", &self.normal.z)?;
        st.serialize_field("distance", &self.distance)?;
        st.serialize_field("clamped", &self.clamped)?;
        st.end()
    }
}

const MAX_ITER: usize = 100;

/// The start rulings of every surface of a part ([`StartRulings`]: `C0` and `D = C1 - C0` at
/// `u = i/400`, `i = 0..=400`), computed once: a file's points all start from the same 401
/// rulings, which are most of the cost of a projection. [`project`] and [`project_on`] build one
/// per call.
#[derive(Debug)]
pub struct Projector<'a, P: RuledPart + ?Sized> {
    part: &'a P,
    rulings: Vec<(Surface, StartRulings)>,
    /// Per surface, how much nearer than its nearest start ruling's line a foot can be (mm,
    /// [`StartRulings::margin`]).
    margins: Vec<f64>,
}

/// The `|v|` up to which [`StartRulings::margin`] holds (three times the part's height).
pub const MARGIN_V: f64 = 3.0;

impl<'a, P: RuledPart + ?Sized> Projector<'a, P> {
    /// Samples the start rulings of every surface of `part`.
    pub fn new(part: &'a P) -> Self {
        let rulings: Vec<(Surface, StartRulings)> = part
            .surfaces()
            .iter()
            .map(|&s| (s, StartRulings::new(part, s)))
            .collect();
        let margins = rulings.iter().map(|(_, r)| r.margin()).collect();
        Self {
            part,
            rulings,
            margins,
        }
    }

    /// Projects `p` (mm) onto the nearest surface of the part (S-shape: A or B); of equally near
    /// feet the first surface's. A surface whose nearest start ruling is farther, less its
    /// [`StartRulings::margin`], than a foot already found cannot hold the nearest foot and is not
    /// projected on (the surfaces tried nearest start first): a scan's point on A is not
    /// projected onto B (half the projections of a file, issue 31).
    pub fn project(&self, p: &Vector3<f64>) -> Result<Projection, GeometryError> {
        check_finite(p)?;
        let starts: Vec<(f64, f64, f64)> = self.rulings.iter().map(|(_, r)| r.nearest(p)).collect();
        // the shared sorts of numerics::order (a sort of its own here costs the wasm ~5 KB)
        let order = argsort(&starts.iter().map(|s| s.2).collect::<Vec<f64>>());
        let mut found: Vec<(usize, Projection)> = Vec::new();
        for k in order {
            let (u, v, d2) = starts[k];
            let nearest = found
                .iter()
                .map(|(_, f)| (p - f.foot).norm())
                .fold(f64::INFINITY, f64::min);
            if v.abs() <= MARGIN_V
                && (d2.sqrt() - self.margins[k] > nearest || self.rulings[k].1.beyond(p, nearest))
            {
                continue;
            }
            found.push((k, newton_from(self.part, self.rulings[k].0, u, v, p)?));
        }
        // in the surfaces' order, the first of the nearest
        sort_by_index(&mut found, |(k, _)| *k);
        let mut best: Option<Projection> = None;
        for (_, pr) in found {
            if best.is_none_or(|b| (p - pr.foot).norm() < (p - b.foot).norm()) {
                best = Some(pr);
            }
        }
        best.ok_or(GeometryError::NonFinitePoint {
            x: p.x,
            y: p.y,
            z: p.z,
        })
    }

    /// Projects `p` (mm) onto surface `s` (one of the part's surfaces).
    pub fn project_on(&self, s: Surface, p: &Vector3<f64>) -> Result<Projection, GeometryError> {
        match self.rulings.iter().find(|(t, _)| *t == s) {
            Some((_, rulings)) => project_from(self.part, s, rulings, p),
            None => project_from(self.part, s, &StartRulings::new(self.part, s), p),
        }
    }
}

/// Projects `p` (mm) onto the nearest surface of the part (S-shape: A or B).
pub fn project<P: RuledPart + ?Sized>(
    part: &P,
    p: &Vector3<f64>,
) -> Result<Projection, GeometryError> {
    Projector::new(part).project(p)
}

/// Projects `p` (mm) onto surface `s`.
pub fn project_on<P: RuledPart + ?Sized>(
    part: &P,
    s: Surface,
    p: &Vector3<f64>,
) -> Result<Projection, GeometryError> {
    project_from(part, s, &StartRulings::new(part, s), p)
}

/// Projects `p` onto surface `s`, starting from the nearest of `rulings` (surface `s`'s).
fn project_from<P: RuledPart + ?Sized>(
    part: &P,
    s: Surface,
    rulings: &StartRulings,
    p: &Vector3<f64>,
) -> Result<Projection, GeometryError> {
    check_finite(p)?;
    let (u, v, _) = rulings.nearest(p);
    newton_from(part, s, u, v, p)
}

fn check_finite(p: &Vector3<f64>) -> Result<(), GeometryError> {
    if p.x.is_finite() && p.y.is_finite() && p.z.is_finite() {
        Ok(())
    } else {
        Err(GeometryError::NonFinitePoint {
            x: p.x,
            y: p.y,
            z: p.z,
        })
    }
}

/// The safeguarded Newton iteration of a projection of `p` onto `s` from `(u, v)`.
fn newton_from<P: RuledPart + ?Sized>(
    part: &P,
    s: Surface,
    mut u: f64,
    mut v: f64,
    p: &Vector3<f64>,
) -> Result<Projection, GeometryError> {
    // 2. safeguarded Newton
    // `f(u, v)` from the section at `u` (the arithmetic of `point_at`)
    let objective = |sec: &Section, v: f64| {
        0.5 * (sec.c0.point * (1.0 - v) + sec.c1.point * v - p).norm_squared()
    };
    let mut converged = false;
    // the section the step halving evaluated last, at the `u` the next step starts from
    let mut last: Option<(f64, Section)> = None;
    for _ in 0..MAX_ITER {
        // one section a step: the frame's derivatives, `D'` and `f(u, v)` all come from it (the
        // arithmetic of `frame_derivs_at` and `point_at`)
        let sec = match last.take() {
            Some((at, sec)) if at.to_bits() == u.to_bits() => sec,
            _ => part.section_at(s, u),
        };
        let f = frame_derivs_from(&sec, v, part.normal_sign(s));
        let r = f.frame.point - p;
        let d1 = sec.d.d1;
        let g = Vector2::new(r.dot(&f.s_u), r.dot(&f.s_v));
        let closed = part.closed();
        let at_lo = !closed && u <= 0.0 && g[0] > 0.0;
        let at_hi = !closed && u >= 1.0 && g[0] < 0.0;
        let gn = Matrix2::new(
            f.s_u.dot(&f.s_u),
            f.s_u.dot(&f.s_v),
            f.s_u.dot(&f.s_v),
            f.s_v.dot(&f.s_v),
        );
        let full = gn + Matrix2::new(r.dot(&f.s_uu), r.dot(&d1), r.dot(&d1), 0.0);
        let step = if at_lo || at_hi {
            // u held on the end: minimise in v only
            Vector2::new(0.0, -g[1] / gn[(1, 1)])
        } else {
            let pd = full[(0, 0)] > 0.0 && full.determinant() > 0.0;
            let h = if pd { full } else { gn };
            match h.lu().solve(&(-g)) {
                Some(st) => st,
                None => Vector2::new(-g[0] / gn[(0, 0)], -g[1] / gn[(1, 1)]),
            }
        };
        // Step halving on f for large steps only: near the foot f changes by less than its
        // rounding, and the full Newton step is what converges there.
        let size = (step[0] * f.s_u.norm()).abs() + (step[1] * f.s_v.norm()).abs();
        let f0 = 0.5 * r.norm_squared();
        let mut lambda = 1.0;
        let (mut un, mut vn) = (u, v);
        for _ in 0..40 {
            un = if closed {
                (u + lambda * step[0]).rem_euclid(1.0)
            } else {
                (u + lambda * step[0]).clamp(0.0, 1.0)
            };
            vn = v + lambda * step[1];
            if size < 1e-4 {
                break;
            }
            let next = part.section_at(s, un);
            let f_next = objective(&next, vn);
            last = Some((un, next));
            if f_next <= f0 {
                break;
            }
            lambda *= 0.5;
        }
        let du = if closed {
            (un - u + 0.5).rem_euclid(1.0) - 0.5
        } else {
            un - u
        };
        let moved = (du * f.s_u.norm()).abs() + ((vn - v) * f.s_v.norm()).abs();
        (u, v) = (un, vn);
        // converged when the Newton step is below 1e-11 mm (at the foot, rounding makes the
        // iterate hop by an ulp of u, i.e. ~1e-13 mm, forever)
        if moved < 1e-13 || size < 1e-11 {
            converged = true;
            break;
        }
    }
    if !converged {
        return Err(GeometryError::ProjectionDidNotConverge {
            x: p.x,
            y: p.y,
            z: p.z,
            surface: s.name(),
        });
    }
    let fr = part.frame_at(s, u, v);
    Ok(Projection {
        surface: s,
        u,
        v,
        foot: fr.point,
        normal: fr.n,
        distance: (p - fr.point).dot(&fr.n),
        clamped: !part.closed() && (u <= 0.0 || u >= 1.0),
    })
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;
    use crate::assert_near;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// The projection that skips a surface by its start rulings' margin is, bit for bit,
        /// the nearer of the projections onto each surface (the first on a tie): points anywhere
        /// in and around the part's box, near A, near B, between them and far off.
        #[test]
        fn skipping_a_far_surface_changes_no_projection(
            x in -60.0f64..160.0, y in -60.0f64..160.0, z in -20.0f64..50.0
        ) {
            let part = SShape::iso();
            let pr = Projector::new(&part);
            let p = Vector3::new(x, y, z);
            let a = pr.project_on(Surface::A, &p);
            let b = pr.project_on(Surface::B, &p);
            let got = pr.project(&p);
            match (a, b) {
                (Ok(a), Ok(b)) => {
                    let want = if (p - b.foot).norm() < (p - a.foot).norm() { b } else { a };
                    prop_assert_eq!(got.unwrap(), want);
                }
                // a failure on a surface the margin skips becomes the other's foot
                (Ok(q), Err(_)) | (Err(_), Ok(q)) => {
                    if let Ok(g) = got {
                        prop_assert_eq!(g, q);
                    }
                }
                (Err(_), Err(_)) => prop_assert!(got.is_err()),
            }
        }
    }

    /// A scan's points, on either side within 0.1 mm of the surface (u every 0.01, v every 0.1,
    /// the ends and the vertical zone included), project as the nearer of the projections onto
    /// each surface, bit for bit, and the other side is skipped by the blocks' bound
    /// ([`StartRulings::beyond`]) for most of them (the surface-wide margin skips none: 12-16
    /// mm against the 9-10 mm between the sides).
    #[test]
    fn a_scan_point_is_not_projected_onto_the_other_side() {
        let part = SShape::iso();
        let pr = Projector::new(&part);
        let (mut points, mut skipped) = (0, 0);
        for s in Surface::BOTH {
            for i in 0..=100 {
                for j in 0..=10 {
                    let (u, v) = (i as f64 / 100.0, j as f64 / 10.0);
                    let fr = part.frame_at(s, u, v);
                    let p = fr.point + fr.n * (0.1 * ((i + j) as f64).sin());
                    let a = pr.project_on(Surface::A, &p).unwrap();
                    let b = pr.project_on(Surface::B, &p).unwrap();
                    let want = if (p - b.foot).norm() < (p - a.foot).norm() {
                        b
                    } else {
                        a
                    };
                    assert_eq!(pr.project(&p).unwrap(), want, "{s:?} u {u} v {v}");
                    let (other, own) = if s == Surface::A { (1, a) } else { (0, b) };
                    points += 1;
                    if pr.rulings[other].1.beyond(&p, (p - own.foot).norm()) {
                        skipped += 1;
                    }
                }
            }
        }
        assert!(skipped * 10 >= points * 9, "{skipped} of {points} skipped");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        /// A point offset by d along N from S(u,v) projects back to (u,v) with distance d,
        /// and p - foot is parallel to N.
        #[test]
        fn offset_points_project_back(
            on_a in any::<bool>(), u in 0.002f64..0.998, v in -0.1f64..1.1, d in -2.5f64..2.5
        ) {
            let part = SShape::iso();
            let s = if on_a { Surface::A } else { Surface::B };
            let f = part.frame_at(s, u, v);
            let p = f.point + f.n * d;
            let pr = project(&part, &p).unwrap();
            prop_assert_eq!(pr.surface, s);
            prop_assert!((pr.foot - f.point).norm() < 1e-8, "foot off by {}", (pr.foot - f.point).norm());
            prop_assert!((pr.distance - d).abs() < 1e-9);
            prop_assert!((p - pr.foot).cross(&pr.normal).norm() < 1e-9, "cross {} foot {} dist {} {}", (p - pr.foot).cross(&pr.normal).norm(), (pr.foot - f.point).norm(), pr.distance, d);
            prop_assert!((pr.foot - part.point_at(s, pr.u, pr.v)).norm() < 1e-12);
        }
    }

    /// The Newton step takes `f(u, v)` and `D'` from the section its frame is made of: the same
    /// numbers, bit for bit, as `point_at` and a second `section_at` (tolerance: none), on the
    /// S-shape's surfaces and a cone frustum.
    #[test]
    fn one_section_a_step_gives_the_point_of_point_at() {
        let part = SShape::iso();
        let cone = crate::part::ConeFrustum::m3_45(true);
        let parts: [(&dyn RuledPart, Surface); 3] = [
            (&part, Surface::A),
            (&part, Surface::B),
            (&cone, Surface::A),
        ];
        for (part, s) in parts {
            for k in 0..=500 {
                let u = k as f64 / 500.0;
                for v in [-0.2, 0.0, 0.37, 1.0, 1.4] {
                    let sec = part.section_at(s, u);
                    let f = frame_derivs_from(&sec, v, part.normal_sign(s));
                    assert_eq!(f, part.frame_derivs_at(s, u, v), "u = {u}, v = {v}");
                    assert_eq!(f.frame.point, part.point_at(s, u, v), "u = {u}, v = {v}");
                }
            }
        }
    }

    #[test]
    fn vertical_zone_and_ends() {
        let part = SShape::iso();
        // On the vertical zone the surface is a plane strip; N is horizontal.
        let f = part.frame_at(Surface::B, 0.5, 0.4);
        assert_near!(f.n.z, 0.0, 1e-15);
        let pr = project(&part, &(f.point + f.n * 0.3)).unwrap();
        assert_near!(pr.u, 0.5, 1e-10);
        assert_near!(pr.distance, 0.3, 1e-12);
        // Beyond the end u = 1 (along the tangent): clamped to the end ruling.
        let e = part.frame_at(Surface::A, 1.0, 0.5);
        let p = e.point + e.t * 2.0 + e.n * 0.1;
        let pr = project_on(&part, Surface::A, &p).unwrap();
        assert_eq!(pr.u, 1.0);
        assert!(pr.clamped);
        assert_near!(pr.v, 0.5, 0.1);
    }

    #[test]
    fn bad_input_is_an_error() {
        let e = project(&SShape::iso(), &Vector3::new(f64::NAN, 0.0, 0.0)).unwrap_err();
        assert!(e.to_string().contains("NaN"), "{e}");
    }
}
