//! Reversal (backlash) errors along the flank path with a first-order servo lag (paper 002 §4.3,
//! Fig. 16; `shared/spec/effects.md`, candidates `backlash_x` … `backlash_c`, and `backlash_a` of
//! paper 001's A-B head).
//!
//! Each surface is machined in one pass in increasing `u`. An axis with lost motion `b` (mm, or
//! rad for A, B and C) trails its command by `b/2` against its direction of motion: the offset
//! target is `e* = −(b/2)·sgn(dq/du)`, held while the axis is at rest. At a reversal the offset
//! moves to the new target through a first-order lag whose "time" constant is
//! [`LAG_LENGTH`] = 2 mm of tool-tip path: `e(s) = e* + (e(s₀) − e*)·exp(−(s − s₀)/2)`, updated
//! exactly between the samples of a [`REVERSAL_GRID`]-step grid in `u`, and interpolated linearly
//! in `u` at the points. Each pass starts settled for its first direction of motion.
//! The defect at a point is `e(s)·(∂x/∂q)·N`, `x` the tool-body point at the contact point (the
//! rigid tool motion evaluated where the tool touches the wall), `N` the normal of the mode
//! ([`super`]), `s` the tool-tip path length (chords of the grid). Units: mm, rad.

use nalgebra::Vector3;

use crate::machine::direct::jacobian_body_point;
use crate::machine::{AxisName, AxisValues, ErrorParam, MachineErrors};
use crate::part::{MeasurementPoint, SShape, Surface};
use crate::toolpath::flank::tool_pose;

use super::defect::{Mode, SensitivityOptions};
use super::path::{machine_path, PATH_GRID};
use super::SensitivityError;
use crate::machine::inverse::inverse_path;

/// Time constant of the servo lag, in mm of tool-tip path (effects.md).
pub const LAG_LENGTH: f64 = 2.0;
/// Steps of the `u` grid on which the lag is integrated (20001 samples).
pub const REVERSAL_GRID: usize = 20000;
/// Axis increments at most this large between grid samples count as rest (mm or rad): they are
/// rounding noise of the inverse kinematics on stretches where an axis stands still.
pub const REST_TOLERANCE: f64 = 1e-9;

/// The axis values are solved on every [`REFINE_STRIDE`]-th grid sample, and on every sample of
/// the coarse steps where an axis may reverse or rest (see [`pass`]).
pub const REFINE_STRIDE: usize = 10;
/// A coarse step over which some axis moves by at most this (mm or rad) is solved on every fine
/// sample: within it an axis may stand still, so that fine increments can fall under
/// [`REST_TOLERANCE`] (a coarse step that moves more than 1000× the rest tolerance over
/// [`REFINE_STRIDE`] samples of a smooth path cannot contain such increments unless it turns).
pub const REFINE_BELOW: f64 = 1e-6;

/// A coarse step over which an axis moves by at most this (mm or rad) is rest: the axis stands
/// still there up to the rounding of the inverse kinematics (~1e-13), and every fine increment is
/// under [`REST_TOLERANCE`], so its direction is held without solving the fine samples.
pub const REST_BELOW: f64 = 1e-11;

/// What a coarse step of one axis is.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Step {
    Rest,
    Moving(f64),
    Unsure,
}

/// One pass (one surface): grid, cumulative tool-tip path length and each axis's direction of
/// motion on every grid step.
#[derive(Debug, Clone)]
pub struct Pass {
    pub u: Vec<f64>,
    /// Tool-tip path length from the start of the pass (mm, sum of grid chords).
    pub s: Vec<f64>,
    pub tips: Vec<Vector3<f64>>,
    /// The chain's axes and, per axis, [`directions`] on the grid.
    pub axes: Vec<AxisName>,
    pub directions: Vec<Vec<f64>>,
    /// Grid samples at which the inverse kinematics was solved (of `u.len()`).
    pub solved: usize,
}

/// The pass of surface `surface` on the reversal grid.
///
/// The direction of motion of an axis on a grid step is the sign of its increment, held through
/// rest (increments ≤ [`REST_TOLERANCE`]). Solving the inverse kinematics at all 20,001 samples
/// is not needed for that: the axes are solved on every [`REFINE_STRIDE`]-th sample, and each
/// coarse step of each axis is *rest* (it moves by at most [`REST_BELOW`]: direction held),
/// *moving* (by more than [`REFINE_BELOW`], 1000× the rest tolerance over
/// [`REFINE_STRIDE`] samples: monotone, its fine directions are the coarse step's sign) or
/// *unsure*. A coarse step is solved on all its fine samples when it is unsure for some axis, or
/// when some axis changes class or direction between it and a neighbour (a turn, a start or a
/// stop lies in one of the two). The inverse kinematics
/// at a given `u` does not depend on the other samples requested ([`machine_path`]), so the
/// directions are those of the full fine solution (checked against it in
/// tests/it/sensitivity_reversal.rs for the three chains and both branches).
pub fn pass(
    part: &SShape,
    surface: Surface,
    opts: &SensitivityOptions,
) -> Result<Pass, SensitivityError> {
    let n = REVERSAL_GRID;
    let u: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
    let poses: Vec<(Vector3<f64>, Vector3<f64>)> = u
        .iter()
        .map(|&x| {
            let p = tool_pose(part, surface, x);
            (p.tip, p.axis)
        })
        .collect();
    // The inverse kinematics of `machine_path`, reusing the poses of the grid samples.
    let solve = |us: &[f64]| {
        let pose = |x: f64| {
            let k = (x * n as f64).round();
            if (0.0..=n as f64).contains(&k) && u[k as usize] == x {
                poses[k as usize]
            } else {
                let p = tool_pose(part, surface, x);
                (p.tip, p.axis)
            }
        };
        inverse_path(&opts.chain, opts.branch, pose, (0.0, 1.0), PATH_GRID, us)
    };
    let tips: Vec<Vector3<f64>> = poses.iter().map(|p| p.0).collect();
    let mut s = vec![0.0; u.len()];
    for k in 1..u.len() {
        s[k] = s[k - 1] + (tips[k] - tips[k - 1]).norm();
    }
    let axes: Vec<AxisName> = opts.chain.axes().map(|a| a.name).collect();
    let stride = REFINE_STRIDE;
    let coarse_idx: Vec<usize> = (0..=n / stride).map(|m| m * stride).chain([n]).collect();
    let mut coarse_idx = coarse_idx;
    coarse_idx.dedup();
    let coarse_u: Vec<f64> = coarse_idx.iter().map(|&k| u[k]).collect();
    let coarse = solve(&coarse_u)?;
    let steps = coarse_idx.len() - 1;
    // Coarse increments per axis, and the coarse steps to solve finely.
    let dc: Vec<Vec<f64>> = axes
        .iter()
        .map(|&a| {
            (1..=steps)
                .map(|m| coarse[m].values.get(a) - coarse[m - 1].values.get(a))
                .collect()
        })
        .collect();
    let class = |x: f64| {
        if x.abs() <= REST_BELOW {
            Step::Rest
        } else if x.abs() > REFINE_BELOW {
            Step::Moving(x.signum())
        } else {
            Step::Unsure
        }
    };
    let mut refine = vec![false; steps];
    for d in &dc {
        for m in 0..steps {
            let c = class(d[m]);
            if c == Step::Unsure {
                refine[m] = true;
            }
            // A turn, or a start or stop between rest and motion, lies in one of the two.
            if m > 0 && c != class(d[m - 1]) {
                refine[m] = true;
                refine[m - 1] = true;
            }
        }
    }
    let mut fine_idx: Vec<usize> = Vec::new();
    for m in (0..steps).filter(|&m| refine[m]) {
        fine_idx.extend(coarse_idx[m]..=coarse_idx[m + 1]);
    }
    fine_idx.dedup();
    let fine_u: Vec<f64> = fine_idx.iter().map(|&k| u[k]).collect();
    let fine = if fine_u.is_empty() {
        Vec::new()
    } else {
        solve(&fine_u)?
    };
    // Fine sample k -> its solution, where solved.
    let mut at = vec![usize::MAX; u.len()];
    for (j, &k) in fine_idx.iter().enumerate() {
        at[k] = j;
    }
    let directions = axes
        .iter()
        .enumerate()
        .map(|(ai, &axis)| {
            let mut d = vec![0.0; u.len()];
            for m in 0..steps {
                for k in coarse_idx[m] + 1..=coarse_idx[m + 1] {
                    let step = if refine[m] {
                        fine[at[k]].values.get(axis) - fine[at[k - 1]].values.get(axis)
                    } else if class(dc[ai][m]) == Step::Rest {
                        0.0
                    } else {
                        dc[ai][m]
                    };
                    d[k] = if step.abs() > REST_TOLERANCE {
                        step.signum()
                    } else {
                        d[k - 1]
                    };
                }
            }
            settle_start(&mut d);
            d
        })
        .collect();
    Ok(Pass {
        u,
        s,
        tips,
        axes,
        directions,
        solved: coarse_idx.len() + fine_idx.len(),
    })
}

/// Direction of motion of `axis` on each grid step `k-1 → k` (index k; index 0 = the first
/// motion), held through rest; an axis the chain does not have never moves (settled at +1, as
/// [`directions_of`] gives for constant values).
pub fn directions(p: &Pass, axis: AxisName) -> Vec<f64> {
    p.axes
        .iter()
        .position(|&a| a == axis)
        .map_or_else(|| vec![1.0; p.u.len()], |i| p.directions[i].clone())
}

/// Directions from the axis values at every grid sample (the definition [`pass`] reproduces
/// with fewer inverse kinematics; tests compare the two).
pub fn directions_of(q: &[AxisValues], axis: AxisName) -> Vec<f64> {
    let mut d = vec![0.0; q.len()];
    for k in 1..q.len() {
        let dq = q[k].get(axis) - q[k - 1].get(axis);
        d[k] = if dq.abs() > REST_TOLERANCE {
            dq.signum()
        } else {
            d[k - 1]
        };
    }
    settle_start(&mut d);
    d
}

/// Settled for the first motion: back-fills the leading rest with the first direction.
fn settle_start(d: &mut [f64]) {
    let first = d.iter().copied().find(|x| *x != 0.0).unwrap_or(1.0);
    for x in d.iter_mut() {
        if *x != 0.0 {
            break;
        }
        *x = first;
    }
}

/// Number of reversals of `axis` along the pass.
pub fn reversal_count(p: &Pass, axis: AxisName) -> usize {
    directions(p, axis)
        .windows(2)
        .filter(|w| w[0] != w[1])
        .count()
}

/// Lagged offset `e` per unit lost motion (`b = 1`) at every grid sample.
pub fn lagged_offset(p: &Pass, axis: AxisName) -> Vec<f64> {
    lag_on(&decays(p), &directions(p, axis))
}

/// The lag's decay over each grid step, `exp(−Δs/`[`LAG_LENGTH`]`)` (step `k − 1 → k` at index
/// `k − 1`): the same for every axis.
fn decays(p: &Pass) -> Vec<f64> {
    (1..p.u.len())
        .map(|k| (-(p.s[k] - p.s[k - 1]) / LAG_LENGTH).exp())
        .collect()
}

/// `e_k = e* + (e_{k−1} − e*)·decay_k` from `e_0 = e*_0`, `e* = −d/2`. Once `e` has reached its
/// target exactly (the difference rounds to 0 after ~75 mm of path), the step is `e* + 0·decay =
/// e*`: it is written so, without the multiplication (the same bits).
fn lag_on(decay: &[f64], d: &[f64]) -> Vec<f64> {
    let mut e = vec![-0.5 * d[0]; d.len()];
    for k in 1..d.len() {
        let target = -0.5 * d[k];
        let prev = e[k - 1];
        e[k] = if prev == target {
            target
        } else {
            target + (prev - target) * decay[k - 1]
        };
    }
    e
}

/// The signature of `backlash_<axis>` at the points per unit `b`: `e(s)·(∂p/∂q)·N`.
pub fn backlash_signature(
    part: &SShape,
    points: &[MeasurementPoint],
    axis: AxisName,
    opts: &SensitivityOptions,
) -> Result<Vec<f64>, SensitivityError> {
    Ok(backlash_signatures(part, points, &[axis], opts)?.remove(0))
}

/// [`backlash_signature`] for several axes at once (the passes are computed once): one vector
/// per axis, in the order of `axes`.
pub fn backlash_signatures(
    part: &SShape,
    points: &[MeasurementPoint],
    axes: &[AxisName],
    opts: &SensitivityOptions,
) -> Result<Vec<Vec<f64>>, SensitivityError> {
    backlash_signatures_on(&passes(part, opts)?, part, points, axes, opts)
}

/// The passes of surfaces A and B ([`Surface::BOTH`] order), for callers that need them for
/// several things (signatures and reversal positions): each costs 20,001 inverse kinematics.
pub fn passes(part: &SShape, opts: &SensitivityOptions) -> Result<[Pass; 2], SensitivityError> {
    Ok([
        pass(part, Surface::BOTH[0], opts)?,
        pass(part, Surface::BOTH[1], opts)?,
    ])
}

/// The lagged offsets of a pass per unit lost motion ([`lagged_offset`]) for some axes, with the
/// pass's `u` grid: all that [`backlash_signatures_lagged`] needs of a pass (it depends on the
/// part, the chain and the branch, not on the points, so it can be kept for other points).
#[derive(Debug, Clone, PartialEq)]
pub struct Lag {
    pub u: Vec<f64>,
    pub axes: Vec<AxisName>,
    /// One [`lagged_offset`] per axis of `axes`.
    pub e: Vec<Vec<f64>>,
}

impl Lag {
    /// The lag of `axes` on pass `p` (the lags of A and B given together must have the same axes).
    pub fn of(p: &Pass, axes: &[AxisName]) -> Self {
        let decay = decays(p);
        Self {
            u: p.u.clone(),
            axes: axes.to_vec(),
            e: axes
                .iter()
                .map(|&a| lag_on(&decay, &directions(p, a)))
                .collect(),
        }
    }
}

/// [`backlash_signatures`] on passes already computed by [`passes`] with the same `opts`.
pub fn backlash_signatures_on(
    passes: &[Pass; 2],
    part: &SShape,
    points: &[MeasurementPoint],
    axes: &[AxisName],
    opts: &SensitivityOptions,
) -> Result<Vec<Vec<f64>>, SensitivityError> {
    let lags = [Lag::of(&passes[0], axes), Lag::of(&passes[1], axes)];
    backlash_signatures_lagged(&lags, part, points, opts)
}

/// [`backlash_signatures`] on the lags of the passes of A and B ([`Lag::of`] with the axes wanted
/// and the same `opts`): one vector per axis of the lags.
pub fn backlash_signatures_lagged(
    lags: &[Lag; 2],
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &SensitivityOptions,
) -> Result<Vec<Vec<f64>>, SensitivityError> {
    let mut out = vec![vec![0.0; points.len()]; lags[0].axes.len()];
    for (surface, p) in Surface::BOTH.into_iter().zip(lags) {
        let idx: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].surface == surface)
            .collect();
        if idx.is_empty() {
            continue;
        }
        let us: Vec<f64> = idx.iter().map(|&i| points[i].u).collect();
        let poses = machine_path(part, &opts.chain, surface, opts.branch, &us)?;
        for (a, (&axis, e)) in p.axes.iter().zip(&p.e).enumerate() {
            for (&i, pose) in idx.iter().zip(&poses) {
                let pt = &points[i];
                // Linear interpolation in u between the grid samples around the point (the
                // reference's convention; the exact lag from sample k-1 differs by < 1e-4
                // relative).
                let k = p.u.partition_point(|x| *x < pt.u).clamp(1, p.u.len() - 1);
                let t = (pt.u - p.u[k - 1]) / (p.u[k] - p.u[k - 1]);
                let e_pt = e[k - 1] * (1.0 - t) + e[k] * t;
                let n = match opts.mode {
                    Mode::Physical => pt.normal,
                    Mode::Paper => part.frame_at(surface, pt.u, 1.0).n,
                };
                let dpdq = axis_derivative(opts, &pose.values, &pt.point, axis)?;
                out[a][i] = e_pt * dpdq.dot(&n);
            }
        }
    }
    Ok(out)
}

/// `∂x/∂q` of the tool-body point at the contact point `x` for one axis (mm per mm or per rad):
/// the axis's positioning error motion `E{axis}{axis}` is exactly a change of its value. (On the
/// flank, the contact point and the tool-axis point at the same height differ by `10·N(u,1)`;
/// for C, whose axis is not perpendicular to the tool, their normal displacements differ.)
fn axis_derivative(
    opts: &SensitivityOptions,
    q: &AxisValues,
    x: &Vector3<f64>,
    axis: AxisName,
) -> Result<Vector3<f64>, SensitivityError> {
    let param = ErrorParam::Motion {
        component: axis,
        axis,
        power: 0,
    };
    let (j, _) = jacobian_body_point(&opts.chain, q, x, &MachineErrors::none(), &[param])?;
    Ok(j.column(0).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lag_is_the_recursion_of_its_definition_bit_for_bit() {
        // The module's recursion written out (one exp per step and axis, no shortcut once
        // settled): Lag::of shares the decay between axes and skips settled steps, same bits.
        let part = SShape::iso();
        let opts = SensitivityOptions::default();
        let axes = [
            AxisName::X,
            AxisName::Y,
            AxisName::Z,
            AxisName::B,
            AxisName::C,
        ];
        for p in passes(&part, &opts).unwrap() {
            let lag = Lag::of(&p, &axes);
            for (a, &axis) in axes.iter().enumerate() {
                let d = directions(&p, axis);
                let mut e = vec![-0.5 * d[0]; p.u.len()];
                for k in 1..p.u.len() {
                    let target = -0.5 * d[k];
                    e[k] =
                        target + (e[k - 1] - target) * (-(p.s[k] - p.s[k - 1]) / LAG_LENGTH).exp();
                }
                let same = e
                    .iter()
                    .zip(&lag.e[a])
                    .all(|(x, y)| x.to_bits() == y.to_bits());
                assert!(same, "{axis:?}");
                assert_eq!(lagged_offset(&p, axis), e, "{axis:?}");
            }
        }
    }
}
