//! Where the finishing pass places its positions: along the exact flank path of eq. 2
//! (`T_tool(u)`, axis `R(u)`, [`crate::toolpath::tool_pose`]), close enough that neither way of
//! going from one position to the next leaves the tolerance `t` (mm):
//!
//! 1. **the scallop between two tool positions**, the CAM term the error budget measures on the
//!    part ([`crate::budget`]): on a flat wall paper 000 eq. 7 in its exact form
//!    [`crate::budget::discrete::chord_error`], `R − √(R² − s²/4) ≤ t` for steps
//!    `s ≤ 2√(t(2R − t))` of the tool axis (R = 10 mm: `s ≤ 0.283 mm` at `t` = 1 µm); where the
//!    wall is concave towards the tool (radius `ρ` in the section, centre on the tool's side) the
//!    circles' centres lie on a circle of radius `ρ − R` and the cusp is deeper,
//!    `h = ρ − √((ρ − R)² − s²/4) − √(R² − s²/4)` ([`scallop`], → eq. 7 as `ρ → ∞`; a convex
//!    wall gives less than eq. 7, which is kept as the bound). Checked at the bottom (`v = 0`)
//!    and top (`v = 1`) curves with the step of the tool-axis point at their contact heights;
//! 2. **the chord of the tip path**: the exact tip at the middle parameter stays within `t` of
//!    the straight segment between the two tips (a CL consumer interpolating linearly);
//! 3. **the controller's interpolation** in machine axes (G01 moves every axis linearly): the
//!    tool point at the tip and at the top of the flank (`h` = 35 mm) of the axis values halfway
//!    between two blocks, through the nominal direct kinematics, stays within `t` of the exact
//!    path's point at the middle parameter.
//!
//! Start with equal tip steps meeting (1) ([`crate::budget::synthetic::equal_steps`]), then
//! bisect every interval that fails (2) or (3) until none does. The axis values come from the
//! inverse kinematics of the analysis ([`crate::sensitivity::path::machine_path`]: the outer
//! rotary angle unwrapped from `u = 0`, interpolated linearly in `u` across the vertical zone,
//! the chosen B branch), so the program passes the singular zone exactly as the sensitivity and
//! the identification assume. Units: mm, rad.

use nalgebra::Vector3;

use super::ProgramError;
use crate::machine::direct::nominal;
use crate::machine::{AxisName, AxisValues, Branch, Chain, PathSample};
use crate::part::ruled::{contact_height, TIP_OFFSET};
use crate::part::{SShape, Surface};
use crate::sensitivity::path::machine_path;
use crate::toolpath::{tool_pose, TOOL_RADIUS};

/// Bisection rounds at most (each halves the failing intervals).
const MAX_ROUNDS: usize = 30;

/// The largest tip step whose scallop `R − √(R² − s²/4)` is `t` (mm): `2√(t(2R − t))`.
pub fn max_step(tolerance: f64, radius: f64) -> f64 {
    2.0 * (tolerance * (2.0 * radius - tolerance)).max(0.0).sqrt()
}

/// The scallop depth (mm) between two circles of radius `radius` whose centres are `step` mm
/// apart, on a wall whose section curves towards the tool with curvature `kappa` (1/mm; ≤ 0:
/// flat or convex, eq. 7's exact form): module docs, rule 1. A step the circles cannot close
/// (or `R κ ≥ 1`, the tool larger than the hollow) gives `radius`.
pub fn scallop(step: f64, radius: f64, kappa: f64) -> f64 {
    let flat = crate::budget::discrete::chord_error(step, radius);
    if kappa <= 0.0 {
        return flat;
    }
    if kappa * radius >= 1.0 {
        return radius;
    }
    let rho = 1.0 / kappa;
    let q = 0.25 * step * step;
    let (a, b) = ((rho - radius).powi(2) - q, radius * radius - q);
    if a < 0.0 || b < 0.0 {
        return radius;
    }
    // ρ − √a − √b written as the flat term plus the curvature's share, without cancellation:
    // (ρ − R) − √a = q / ((ρ − R) + √a), R − √b = flat.
    flat + q / ((rho - radius) + a.sqrt())
}

/// Curvature (1/mm) of the curve `S(·, v)` of surface `s` at `u` towards the tool side (the
/// outward normal `N`): `(S_uu · N) / (|S_u|² |N_xy|)`, > 0 where the wall is concave as the
/// tool sees it.
pub fn curvature_towards_tool(part: &SShape, s: Surface, u: f64, v: f64) -> f64 {
    let [c0, c1] = part.curves(s);
    let (d0, d1) = (c0.derivs_at(u), c1.derivs_at(u));
    let su = d0.d1 * (1.0 - v) + d1.d1 * v;
    let suu = d0.d2 * (1.0 - v) + d1.d2 * v;
    let n = part.frame_at(s, u, v).n;
    let nxy = (n.x * n.x + n.y * n.y).sqrt().max(1e-12);
    suu.dot(&n) / (su.norm_squared().max(1e-300) * nxy)
}

/// Distance (mm) from `p` to the segment `[a, b]`.
pub fn distance_to_segment(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let d = b - a;
    let l2 = d.norm_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(&d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * t)).norm()
}

/// Axis values halfway between `a` and `b` (every axis linearly, as G01 moves them).
pub fn halfway(a: &AxisValues, b: &AxisValues) -> AxisValues {
    let mut q = AxisValues::default();
    for n in AxisName::ALL {
        q.set(n, 0.5 * (a.get(n) + b.get(n)));
    }
    q
}

/// The error (mm) between two positions at `u0`, `u1` with axis values `q0`, `q1`: the
/// largest of the scallop (1), the tip chord (2) and the controller's interpolation (3) of the
/// module docs, against the exact path at `um`. Returns (largest, scallop).
pub fn interval_error(
    part: &SShape,
    chain: &Chain,
    s: Surface,
    (u0, q0): (f64, &AxisValues),
    (u1, q1): (f64, &AxisValues),
    um: f64,
) -> (f64, f64) {
    let (a, b, m) = (
        tool_pose(part, s, u0),
        tool_pose(part, s, u1),
        tool_pose(part, s, um),
    );
    let scallop = [0.0, 1.0]
        .into_iter()
        .map(|v| {
            let h = contact_height(part, s, um, v);
            let step = ((b.tip + b.axis * h) - (a.tip + a.axis * h)).norm();
            let kappa = [u0, um, u1]
                .into_iter()
                .map(|u| curvature_towards_tool(part, s, u, v))
                .fold(f64::NEG_INFINITY, f64::max);
            scallop(step, TOOL_RADIUS, kappa)
        })
        .fold(0.0, f64::max);
    let chord = distance_to_segment(&m.tip, &a.tip, &b.tip);
    let q = halfway(q0, q1);
    let nc = [0.0, TIP_OFFSET]
        .into_iter()
        .map(|h| (nominal(chain, &q, h).point - (m.tip + m.axis * h)).norm())
        .fold(0.0, f64::max);
    (chord.max(nc).max(scallop), scallop)
}

/// The positions of the finishing pass of surface `s`: `(u, axis values)` in increasing `u`,
/// every interval within `tolerance` (mm) by the three rules of the module docs, the largest
/// interval error and the largest scallop found.
pub fn sample_surface(
    part: &SShape,
    chain: &Chain,
    branch: Branch,
    s: Surface,
    tolerance: f64,
) -> Result<(Vec<PathSample>, f64, f64), ProgramError> {
    let letter = if s == Surface::A { 'A' } else { 'B' };
    let kin = |source: crate::sensitivity::SensitivityError| ProgramError::Kinematics {
        surface: letter,
        source,
    };
    let mut us = crate::budget::synthetic::equal_steps(part, s, max_step(tolerance, TOOL_RADIUS));
    let mut last = (f64::NAN, 0.0, 1.0);
    for _ in 0..MAX_ROUNDS {
        let mids: Vec<f64> = us.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
        let path = machine_path(part, chain, s, branch, &us).map_err(kin)?;
        let mut worst = (0.0, 0);
        let mut worst_scallop = 0.0f64;
        let mut split = Vec::new();
        for k in 0..mids.len() {
            let (e, sc) = interval_error(
                part,
                chain,
                s,
                (us[k], &path[k].values),
                (us[k + 1], &path[k + 1].values),
                mids[k],
            );
            worst_scallop = worst_scallop.max(sc);
            if e > worst.0 {
                worst = (e, k);
            }
            if e > tolerance {
                split.push(mids[k]);
            }
        }
        if split.is_empty() {
            return Ok((path, worst.0, worst_scallop));
        }
        last = (worst.0, us[worst.1], us[worst.1 + 1]);
        if us.len() + split.len() > crate::budget::MAX_POSITIONS / 2 {
            return Err(ProgramError::NotConverged {
                surface: letter,
                positions: us.len(),
                error: worst.0,
                tolerance,
                u0: us[worst.1],
                u1: us[worst.1 + 1],
            });
        }
        us.extend(split);
        us.sort_by(f64::total_cmp);
    }
    Err(ProgramError::NotConverged {
        surface: letter,
        positions: us.len(),
        error: last.0,
        tolerance,
        u0: last.1,
        u1: last.2,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::budget::discrete::chord_error;

    /// The step of the tolerance gives back the tolerance through the budget's chord error
    /// (closed form, 1e-15 mm).
    #[test]
    fn max_step_inverts_the_chord_error() {
        for t in [1e-4, 1e-3, 0.01] {
            assert_near!(chord_error(max_step(t, 10.0), 10.0), t, 1e-15);
        }
        // A hollow of radius 30 mm: centres on the circle of radius 20 mm; direct evaluation
        // of ρ − √((ρ−R)² − s²/4) − √(R² − s²/4) (1e-12 mm); flat and convex give eq. 7.
        let (s, r, rho) = (0.5f64, 10.0f64, 30.0f64);
        let direct = rho - ((rho - r).powi(2) - s * s / 4.0).sqrt() - (r * r - s * s / 4.0).sqrt();
        assert_near!(scallop(s, r, 1.0 / rho), direct, 1e-12);
        assert!(scallop(s, r, 1.0 / rho) > chord_error(s, r));
        assert_eq!(scallop(s, r, -0.1), chord_error(s, r));
        assert_eq!(scallop(s, r, 0.2), r);
        let (a, b) = (Vector3::zeros(), Vector3::new(2.0, 0.0, 0.0));
        assert_near!(
            distance_to_segment(&Vector3::new(1.0, 0.5, 0.0), &a, &b),
            0.5,
            1e-15
        );
        assert_near!(
            distance_to_segment(&Vector3::new(3.0, 0.0, 0.0), &a, &b),
            1.0,
            1e-15
        );
    }
}
