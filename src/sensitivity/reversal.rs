//! Reversal (backlash) errors along the flank path with a first-order servo lag (paper 002 §4.3,
//! Fig. 16; `shared/spec/effects.md`, candidates `backlash_x` … `backlash_c`).
//!
//! Each surface is machined in one pass in increasing `u`. An axis with lost motion `b` (mm, or
//! rad for B and C) trails its command by `b/2` against its direction of motion: the offset
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
use super::path::machine_path;
use super::SensitivityError;

/// Time constant of the servo lag, in mm of tool-tip path (effects.md).
pub const LAG_LENGTH: f64 = 2.0;
/// Steps of the `u` grid on which the lag is integrated (20001 samples).
pub const REVERSAL_GRID: usize = 20000;
/// Axis increments at most this large between grid samples count as rest (mm or rad): they are
/// rounding noise of the inverse kinematics on stretches where an axis stands still.
pub const REST_TOLERANCE: f64 = 1e-9;

/// One pass (one surface): grid, cumulative tool-tip path length and axis values.
#[derive(Debug, Clone)]
pub struct Pass {
    pub u: Vec<f64>,
    /// Tool-tip path length from the start of the pass (mm, sum of grid chords).
    pub s: Vec<f64>,
    pub q: Vec<AxisValues>,
    pub tips: Vec<Vector3<f64>>,
}

/// The pass of surface `surface` on the reversal grid.
pub fn pass(
    part: &SShape,
    surface: Surface,
    opts: &SensitivityOptions,
) -> Result<Pass, SensitivityError> {
    let u: Vec<f64> = (0..=REVERSAL_GRID)
        .map(|k| k as f64 / REVERSAL_GRID as f64)
        .collect();
    let path = machine_path(part, &opts.chain, surface, opts.branch, &u)?;
    let tips: Vec<Vector3<f64>> = u.iter().map(|&x| tool_pose(part, surface, x).tip).collect();
    let mut s = vec![0.0; u.len()];
    for k in 1..u.len() {
        s[k] = s[k - 1] + (tips[k] - tips[k - 1]).norm();
    }
    Ok(Pass {
        u,
        s,
        q: path.into_iter().map(|p| p.values).collect(),
        tips,
    })
}

/// Direction of motion of `axis` on each grid step `k-1 → k` (index k; index 0 = the first
/// motion), held through rest.
pub fn directions(p: &Pass, axis: AxisName) -> Vec<f64> {
    let n = p.q.len();
    let mut d = vec![0.0; n];
    for k in 1..n {
        let dq = p.q[k].get(axis) - p.q[k - 1].get(axis);
        d[k] = if dq.abs() > REST_TOLERANCE {
            dq.signum()
        } else {
            d[k - 1]
        };
    }
    // Settled for the first motion: back-fill the leading rest with the first direction.
    let first = d.iter().copied().find(|x| *x != 0.0).unwrap_or(1.0);
    for x in d.iter_mut() {
        if *x != 0.0 {
            break;
        }
        *x = first;
    }
    d
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
    let d = directions(p, axis);
    let mut e = vec![-0.5 * d[0]; p.u.len()];
    for k in 1..p.u.len() {
        let target = -0.5 * d[k];
        e[k] = target + (e[k - 1] - target) * (-(p.s[k] - p.s[k - 1]) / LAG_LENGTH).exp();
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

/// [`backlash_signatures`] on passes already computed by [`passes`] with the same `opts`.
pub fn backlash_signatures_on(
    passes: &[Pass; 2],
    part: &SShape,
    points: &[MeasurementPoint],
    axes: &[AxisName],
    opts: &SensitivityOptions,
) -> Result<Vec<Vec<f64>>, SensitivityError> {
    let mut out = vec![vec![0.0; points.len()]; axes.len()];
    for (surface, p) in Surface::BOTH.into_iter().zip(passes) {
        let idx: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].surface == surface)
            .collect();
        if idx.is_empty() {
            continue;
        }
        let us: Vec<f64> = idx.iter().map(|&i| points[i].u).collect();
        let poses = machine_path(part, &opts.chain, surface, opts.branch, &us)?;
        for (a, &axis) in axes.iter().enumerate() {
            let e = lagged_offset(p, axis);
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
