//! Inverse kinematics of a chain with X, Y, Z and two rotary axes (paper 000 eq. 9-10).
//!
//! **Orientation.** The tool direction in the workpiece frame is
//! `w = R_o(s_o·α) · R_i(s_i·β) · ẑ`, where the *inner* rotary axis `i` is the one applied first
//! to the tool axis and the *outer* one `o` last (for `w C Y' b X Z B t`: `w = Rz(-C)·Ry(B)·ẑ`,
//! i.e. `(sinB cosC, -sinB sinC, cosB)`); `s = ±1` folds the prime and the side (a workpiece-side
//! axis enters inverted). `w·o` fixes the inner angle: `a cos θ + b sin θ = w·o` with
//! `(a, b) = (ẑ·o, (i × ẑ)·o)`, two roots `θ = φ ± acos(w·o)` (computed as `atan2(|w⊥|, w·o)`); the outer angle turns `R_i(θ)ẑ`
//! onto `w` about `o`. The two solutions differ by π in the outer angle.
//!
//! **Branch** ([`Branch`]): `Signed` (default; paper 000 eq. 9 read literally, `C = atan(-j/i)`
//! modulo π) picks the solution whose outer angle is nearest the previous one (0 at the start),
//! so the inner angle may be negative; `Positive` keeps the inner angle ≥ 0 and unwraps the outer
//! angle modulo 2π. Where `w` is exactly parallel to the outer axis, the outer angle is undefined:
//! along a path it is interpolated linearly in `u` between its limits at the ends of the zone
//! (spec s-shape.md: the S-shape's vertical zone `u ∈ [6/13, 8/13]`).
//!
//! **Position.** With the rotary angles fixed the tool tip is affine in (X, Y, Z); the 3 × 3
//! system is solved directly. Units: mm, rad.

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use super::chain::{AxisKind, AxisName, AxisValues, Chain};
use super::direct::{nominal_from_sides, side_motion, RotaryMotions};
use super::transform::rotation3;
use super::MachineError;
use crate::numerics::order::argsort;

/// Which of the two inverse solutions to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Branch {
    /// Outer angle continuous modulo π; inner (tilt) angle signed (paper 000 eq. 9).
    #[default]
    Signed,
    /// Inner (tilt) angle ≥ 0; outer angle continuous modulo 2π.
    Positive,
}

impl Branch {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "signed" => Some(Branch::Signed),
            "positive" => Some(Branch::Positive),
            _ => None,
        }
    }
}

/// The rotary structure of a chain: `w = R_o(s_o α) R_i(s_i β) ẑ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotaryPair {
    pub outer: AxisName,
    pub inner: AxisName,
    s_outer: f64,
    s_inner: f64,
}

impl RotaryPair {
    /// Finds the inner and outer rotary axes of the chain.
    pub fn of(chain: &Chain) -> Result<Self, MachineError> {
        // Rotations applied to the tool axis, innermost first: tool side from the tool back to
        // the frame, then the workpiece side (inverted) from the frame to the workpiece.
        let mut seq: Vec<(AxisName, f64)> = Vec::new();
        for a in chain.tool_axes().iter().rev() {
            if a.name.kind() == AxisKind::Rotary {
                seq.push((a.name, a.sign));
            }
        }
        for a in chain.workpiece_axes() {
            if a.name.kind() == AxisKind::Rotary {
                seq.push((a.name, -a.sign));
            }
        }
        if seq.len() != 2 {
            return Err(MachineError::RotaryCount {
                code: chain.code().to_string(),
                found: seq.len(),
            });
        }
        let (inner, s_inner) = seq[0];
        let (outer, s_outer) = seq[1];
        if inner.direction() == 2 || inner.direction() == outer.direction() {
            return Err(MachineError::DegenerateRotaries {
                outer: outer.to_string(),
                inner: inner.to_string(),
            });
        }
        Ok(Self {
            outer,
            inner,
            s_outer,
            s_inner,
        })
    }

    fn unit(k: usize) -> Vector3<f64> {
        let mut v = Vector3::zeros();
        v[k] = 1.0;
        v
    }

    /// The two (outer, inner) solutions for unit direction `w`, and the norm of `w`'s component
    /// perpendicular to the outer axis (0: singular, outer angle undefined and returned as 0).
    pub fn solutions(&self, w: &Vector3<f64>) -> ([(f64, f64); 2], f64) {
        let o = Self::unit(self.outer.direction());
        let i = Self::unit(self.inner.direction());
        let z = Vector3::z();
        let a = z.dot(&o);
        let b = i.cross(&z).dot(&o);
        let phi = b.atan2(a);
        let c = w.dot(&o);
        let w_perp = w - o * c;
        let perp = w_perp.norm();
        // acos(c), accurate near the singularity where c rounds to ±1 but w⊥ does not vanish.
        let d = perp.atan2(c);
        let mut out = [(0.0, 0.0); 2];
        for (n, theta_i) in [phi + d, phi - d].into_iter().enumerate() {
            let theta_i = wrap_pi(theta_i);
            let v = rotation3(self.inner.direction(), theta_i) * z;
            let v_perp = v - o * v.dot(&o);
            let theta_o = if perp == 0.0 {
                0.0
            } else {
                o.dot(&v_perp.cross(&w_perp)).atan2(v_perp.dot(&w_perp))
            };
            out[n] = (theta_o / self.s_outer, theta_i / self.s_inner);
        }
        (out, perp)
    }

    /// Picks a solution by branch, unwrapping the outer angle towards `previous`.
    pub fn select(&self, sols: &[(f64, f64); 2], branch: Branch, previous: f64) -> (f64, f64) {
        match branch {
            Branch::Signed => sols
                .iter()
                .map(|&(o, i)| (unwrap_near(o, previous), i))
                .min_by(|x, y| (x.0 - previous).abs().total_cmp(&(y.0 - previous).abs()))
                .unwrap_or((previous, 0.0)),
            Branch::Positive => {
                // Outer axis ∥ z (C): the roots are ±β, exactly one ≥ 0. Outer ⊥ z (a head
                // tilting about two horizontal axes): the roots are θ and π − θ; take the
                // non-negative one if only one is, else the smaller tilt.
                let (a, b) = (sols[0], sols[1]);
                let (o, i) = match (a.1 >= 0.0, b.1 >= 0.0) {
                    (true, false) => a,
                    (false, true) => b,
                    _ if a.1.abs() <= b.1.abs() => a,
                    _ => b,
                };
                (unwrap_near(o, previous), i)
            }
        }
    }

    /// The inner angle when the outer angle is fixed at `outer` on a singular pose.
    fn inner_at(&self, w: &Vector3<f64>, outer: f64) -> f64 {
        // w ∥ o: undo the outer rotation, then the inner angle turns ẑ onto the result.
        let ro = rotation3(self.outer.direction(), self.s_outer * outer);
        let v: Vector3<f64> = ro.transpose() * w;
        let i = Self::unit(self.inner.direction());
        let z = Vector3::z();
        let v_perp = v - i * v.dot(&i);
        i.dot(&z.cross(&v_perp)).atan2(z.dot(&v_perp)) / self.s_inner
    }
}

/// `x + 2πk` nearest to `target`.
fn unwrap_near(x: f64, target: f64) -> f64 {
    x + 2.0 * PI * ((target - x) / (2.0 * PI)).round()
}

fn wrap_pi(x: f64) -> f64 {
    if x > -PI && x <= PI {
        // Leave in-range values untouched: tiny angles near a singularity must keep their value.
        return x;
    }
    let y = x.rem_euclid(2.0 * PI);
    if y > PI {
        y - 2.0 * PI
    } else {
        y
    }
}

/// Solves the three linear axes for a tool tip with the rotary axes set in `q`.
pub fn solve_linear(
    chain: &Chain,
    q: &AxisValues,
    tip: &Vector3<f64>,
) -> Result<AxisValues, MachineError> {
    let lin = [AxisName::X, AxisName::Y, AxisName::Z];
    let found = chain
        .axes()
        .filter(|a| a.name.kind() == AxisKind::Linear)
        .count();
    if found != 3 || lin.iter().any(|&n| chain.axis(n).is_none()) {
        return Err(MachineError::LinearCount {
            code: chain.code().to_string(),
            found,
        });
    }
    let mut base = *q;
    for n in lin {
        base.set(n, 0.0);
    }
    // The tip at the linear axes 0 and at each one set to 1 (the nominal chain, `nominal`'s
    // arithmetic): the rotary axes' motions once, and the motion of a side that does not carry
    // the axis set to 1 is the one at 0 (the same numbers).
    let rotary = RotaryMotions::of(chain, &base);
    let (wp, tool) = (chain.workpiece_axes(), chain.tool_axes());
    let w0 = side_motion(wp, &base, &rotary).inverse();
    let t0 = side_motion(tool, &base, &rotary);
    let p0 = nominal_from_sides(chain, &w0, &t0, 0.0).point;
    let mut j = Matrix3::zeros();
    for (k, n) in lin.into_iter().enumerate() {
        let mut e = base;
        e.set(n, 1.0);
        let p = if wp.iter().any(|a| a.name == n) {
            let w = side_motion(wp, &e, &rotary).inverse();
            nominal_from_sides(chain, &w, &t0, 0.0)
        } else {
            let t = side_motion(tool, &e, &rotary);
            nominal_from_sides(chain, &w0, &t, 0.0)
        };
        j.set_column(k, &(p.point - p0));
    }
    let det = j.determinant();
    let x = j
        .lu()
        .solve(&(tip - p0))
        .ok_or(MachineError::SingularLinear { det })?;
    let mut out = *q;
    for (k, n) in lin.into_iter().enumerate() {
        out.set(n, x[k]);
    }
    Ok(out)
}

fn check_direction(w: &Vector3<f64>) -> Result<(), MachineError> {
    let n = w.norm();
    if !n.is_finite() || (n - 1.0).abs() > 1e-9 {
        return Err(MachineError::BadDirection {
            x: w.x,
            y: w.y,
            z: w.z,
            norm: n,
        });
    }
    Ok(())
}

/// Inverse kinematics of one pose: tool tip `tip` (mm) and unit tool direction `w` in the
/// workpiece frame. `previous_outer` (rad) is the outer angle to stay near (0 at a path start).
/// On a singular pose (w ∥ outer axis) the outer angle is kept at `previous_outer`.
pub fn inverse(
    chain: &Chain,
    tip: &Vector3<f64>,
    w: &Vector3<f64>,
    branch: Branch,
    previous_outer: f64,
) -> Result<AxisValues, MachineError> {
    check_direction(w)?;
    let pair = RotaryPair::of(chain)?;
    let (sols, perp) = pair.solutions(w);
    let (outer, inner) = if perp == 0.0 {
        (previous_outer, pair.inner_at(w, previous_outer))
    } else {
        pair.select(&sols, branch, previous_outer)
    };
    let mut q = AxisValues::default();
    q.set(pair.outer, outer);
    q.set(pair.inner, inner);
    solve_linear(chain, &q, tip)
}

/// Axis values at one path parameter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PathSample {
    pub u: f64,
    pub values: AxisValues,
    /// True on a singular zone (outer angle interpolated).
    pub singular: bool,
}

/// Inverse kinematics along a path `u ↦ (tip, w)` over `domain`, returned at `us` (each inside
/// the domain). The outer angle is unwrapped from the domain start on a grid of `grid` steps
/// (plus the `us`), and interpolated linearly in `u` across singular zones between its limits at
/// the zone ends (located by bisection to machine precision).
pub fn inverse_path<F>(
    chain: &Chain,
    branch: Branch,
    pose_at: F,
    domain: (f64, f64),
    grid: usize,
    us: &[f64],
) -> Result<Vec<PathSample>, MachineError>
where
    F: Fn(f64) -> (Vector3<f64>, Vector3<f64>),
{
    let pair = RotaryPair::of(chain)?;
    let (u0, u1) = domain;
    if u0.partial_cmp(&u1) != Some(std::cmp::Ordering::Less) || grid == 0 {
        return Err(MachineError::EmptyDomain { u0, u1, grid });
    }
    if let Some(u) = us.iter().find(|u| !(**u >= u0 && **u <= u1)) {
        return Err(MachineError::OutsideDomain { u: *u, u0, u1 });
    }
    // The grid and the `us`, sorted and without repeats (`g`): `order` lists the `us` in `g`'s
    // order and `at` where each one's value sits in `g`, so that the samples are read in `g`'s
    // order (not by a search each, and in memory order). `argsort` is stable: the order of a
    // sort of the values, the grid's before the `us`' among equal ones.
    let values: Vec<f64> = (0..=grid)
        .map(|k| u0 + (u1 - u0) * k as f64 / grid as f64)
        .chain(us.iter().copied())
        .collect();
    let mut g: Vec<f64> = Vec::with_capacity(values.len());
    let mut order: Vec<usize> = Vec::with_capacity(us.len());
    let mut at = vec![0; us.len()];
    for k in argsort(&values) {
        let u = values[k];
        if g.last() != Some(&u) {
            g.push(u);
        }
        if let Some(i) = k.checked_sub(grid + 1) {
            order.push(i);
            at[i] = g.len() - 1;
        }
    }
    let sing = |u: f64| pair.solutions(&pose_at(u).1).1 == 0.0;
    let poses: Vec<(Vector3<f64>, Vector3<f64>)> = g.iter().map(|&u| pose_at(u)).collect();
    let solved: Vec<([(f64, f64); 2], bool)> = poses
        .iter()
        .map(|(_, w)| {
            check_direction(w)?;
            let (s, perp) = pair.solutions(w);
            Ok((s, perp == 0.0))
        })
        .collect::<Result<_, MachineError>>()?;
    let mut outer = vec![0.0; g.len()];
    let mut prev = 0.0;
    let mut k = 0;
    while k < g.len() {
        if !solved[k].1 {
            outer[k] = pair.select(&solved[k].0, branch, prev).0;
            prev = outer[k];
            k += 1;
            continue;
        }
        // A singular run g[k..m].
        let mut m = k;
        while m < g.len() && solved[m].1 {
            m += 1;
        }
        let bisect = |mut lo: f64, mut hi: f64, lo_singular: bool| {
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if sing(mid) == lo_singular {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            (lo, hi)
        };
        let start = if k > 0 {
            let (lo, hi) = bisect(g[k - 1], g[k], false);
            let (s, _) = pair.solutions(&pose_at(lo).1);
            Some((hi, pair.select(&s, branch, prev).0))
        } else {
            None
        };
        let end = if m < g.len() {
            let (lo, hi) = bisect(g[m - 1], g[m], true);
            let target = start.map(|s| s.1).unwrap_or(prev);
            let (s, _) = pair.solutions(&pose_at(hi).1);
            Some((lo, pair.select(&s, branch, target).0))
        } else {
            None
        };
        for j in k..m {
            outer[j] = match (start, end) {
                (Some((ua, ca)), Some((ub, cb))) if ub > ua => {
                    ca + (cb - ca) * ((g[j] - ua) / (ub - ua)).clamp(0.0, 1.0)
                }
                (Some((_, ca)), _) => ca,
                (None, Some((_, cb))) => cb,
                (None, None) => prev,
            };
        }
        prev = end.map(|e| e.1).unwrap_or(outer[m - 1]);
        k = m;
    }
    let sample = |k: usize| {
        let (u, j) = (us[k], at[k]);
        // a value kept once for an equal one of other bits (-0.0 beside 0.0) is not found, as
        // by a search of `g`
        if g[j].total_cmp(&u) != std::cmp::Ordering::Equal {
            return Err(MachineError::LostFromGrid { u });
        }
        let (tip, w) = poses[j];
        let (o, i) = if solved[j].1 {
            (outer[j], pair.inner_at(&w, outer[j]))
        } else {
            let sols = &solved[j].0;
            // The solution whose outer angle matches the unwrapped one.
            let best = sols
                .iter()
                .map(|&(o, i)| (unwrap_near(o, outer[j]), i))
                .min_by(|x, y| (x.0 - outer[j]).abs().total_cmp(&(y.0 - outer[j]).abs()))
                .unwrap_or((outer[j], 0.0));
            best
        };
        let mut q = AxisValues::default();
        q.set(pair.outer, o);
        q.set(pair.inner, i);
        let values = solve_linear(chain, &q, &tip)?;
        Ok(PathSample {
            u,
            values,
            singular: solved[j].1,
        })
    };
    let blank = PathSample {
        u: 0.0,
        values: AxisValues::default(),
        singular: false,
    };
    let mut samples = vec![blank; us.len()];
    // the error of the first of the `us` that has one, as a pass in their order would give
    let mut failed: Option<(usize, MachineError)> = None;
    for i in order {
        match sample(i) {
            Ok(p) => samples[i] = p,
            Err(e) => {
                if failed.as_ref().is_none_or(|(j, _)| i < *j) {
                    failed = Some((i, e));
                }
            }
        }
    }
    match failed {
        Some((_, e)) => Err(e),
        None => Ok(samples),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::chain::PAPER000_L0;
    use crate::machine::direct::tests::spread_poses;
    use crate::part::{SShape, Surface};
    use crate::toolpath::flank::tool_pose;

    /// The linear axes solved with the sides' motions shared are those solved with a whole
    /// nominal chain per evaluation (the direct method), bit for bit (tolerance: none).
    #[test]
    fn linear_axes_as_with_a_nominal_chain_each() {
        use crate::machine::direct::nominal;
        let direct = |chain: &Chain, q: &AxisValues, tip: &Vector3<f64>| {
            let lin = [AxisName::X, AxisName::Y, AxisName::Z];
            let mut base = *q;
            for n in lin {
                base.set(n, 0.0);
            }
            let p0 = nominal(chain, &base, 0.0).point;
            let mut j = Matrix3::zeros();
            for (k, n) in lin.into_iter().enumerate() {
                let mut e = base;
                e.set(n, 1.0);
                j.set_column(k, &(nominal(chain, &e, 0.0).point - p0));
            }
            let x = j.lu().solve(&(tip - p0)).unwrap();
            let mut out = *q;
            for (k, n) in lin.into_iter().enumerate() {
                out.set(n, x[k]);
            }
            out
        };
        for (k, (chain, q)) in spread_poses(false).into_iter().enumerate() {
            let t = k as f64;
            let tip = Vector3::new(60.0 * (0.11 * t).cos(), 40.0 * (0.07 * t).sin(), 0.1 * t);
            let got = solve_linear(&chain, &q, &tip).unwrap();
            assert_eq!(got, direct(&chain, &q, &tip), "{} k = {k}", chain.code());
        }
    }

    /// The samples read in the grid's order are put back in the `us`' order: a batch of
    /// parameters in no order, with repeats, the ends and the vertical zone, gives at each one
    /// the sample a call with that parameter alone gives (bit for bit, tolerance: none), on the
    /// three chains.
    #[test]
    fn samples_come_back_in_the_order_asked() {
        let part = SShape::iso();
        let mut us: Vec<f64> = (0..400)
            .map(|k| ((k * 7919) % 400) as f64 / 399.0)
            .collect();
        us.extend([
            0.0,
            1.0,
            0.5,
            0.5,
            6.0 / 13.0,
            8.0 / 13.0,
            0.123_456_789,
            0.0,
        ]);
        for chain in [
            Chain::paper000(PAPER000_L0),
            Chain::paper002(),
            Chain::paper001(120.0, 80.0),
        ] {
            for s in Surface::BOTH {
                let pose = |u: f64| {
                    let p = tool_pose(&part, s, u);
                    (p.tip, p.axis)
                };
                let batch = inverse_path(&chain, Branch::Signed, pose, (0.0, 1.0), 260, &us);
                let batch = batch.unwrap();
                for (k, &u) in us.iter().enumerate() {
                    let one = inverse_path(&chain, Branch::Signed, pose, (0.0, 1.0), 260, &[u]);
                    assert_eq!(batch[k], one.unwrap()[0], "{} {s:?} u = {u}", chain.code());
                }
            }
        }
    }
}
