//! Paper 002's surface frame along a tool path and its sensitivity coefficients (eq. 3-14).
//!
//! At tool centre point `P0(n)` (the tool tip of a square-end mill, workpiece frame):
//! - `t(n) = (P0(n+1) − P0(n)) / |…|` (eq. 3; the last point uses the previous step),
//! - `b(n) = (i, j, k)`, the tool axis (eq. 4),
//! - `n(n) = t × b` for up-cutting (eq. 5), `−t × b` for down-cutting (eq. 6).
//!
//! For an error motion `E**` (or any error parameter) the tool-position error is
//! `E(n) = P(n) − P0(n)` (eq. 7), here to first order `E = (∂P/∂E**)·E**` from the analytic
//! Jacobian of [`crate::machine::direct`]; the coefficients per unit error are
//! `k = |E|/E**` (eq. 11), `k_n = E·n/E**`, `k_t = E·t/E**`, `k_b = E·b/E**` (eq. 12-14).
//! Sign: `k_n > 0` leaves material (positive normal error, paper 002 Fig. 7). Units: mm per mm or
//! mm per rad.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::machine::direct::point_jacobian;
use crate::machine::inverse::inverse_path;
use crate::machine::{AxisValues, Branch, Chain, ErrorParam, MachineErrors};
use crate::part::{SShape, Surface};
use crate::toolpath::flank::tool_pose;

use super::cone_frustum::ConeFrustum;
use super::defect::SensitivityOptions;
use super::path::machine_path;
use super::SensitivityError;

/// Which side of the tool cuts (paper 002 Fig. 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Cutting {
    /// `n = t × b` (eq. 5)
    #[default]
    Up,
    /// `n = −t × b` (eq. 6)
    Down,
}

/// The surface frame at one tool position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceFrame {
    /// Tool-tip path length from the first point (mm).
    pub s: f64,
    pub tip: Vector3<f64>,
    pub t: Vector3<f64>,
    pub n: Vector3<f64>,
    pub b: Vector3<f64>,
    /// Axis values of the pose.
    pub q: AxisValues,
}

/// Surface frames (eq. 3-6) of a path given as tool tips, tool axes and axis values.
pub fn surface_frames(
    tips: &[Vector3<f64>],
    axes: &[Vector3<f64>],
    q: &[AxisValues],
    cutting: Cutting,
) -> Vec<SurfaceFrame> {
    let n = tips.len().min(axes.len()).min(q.len());
    let mut s = 0.0;
    (0..n)
        .map(|i| {
            if i > 0 {
                s += (tips[i] - tips[i - 1]).norm();
            }
            let step = if i + 1 < n {
                tips[i + 1] - tips[i]
            } else if i > 0 {
                tips[i] - tips[i - 1]
            } else {
                Vector3::zeros()
            };
            let t = step.try_normalize(0.0).unwrap_or_else(Vector3::zeros);
            let b = axes[i];
            let tb = t.cross(&b);
            let nn = match cutting {
                Cutting::Up => tb,
                Cutting::Down => -tb,
            };
            SurfaceFrame {
                s,
                tip: tips[i],
                t,
                n: nn,
                b,
                q: q[i],
            }
        })
        .collect()
}

/// Sensitivity coefficients of one error along the path (eq. 11-14), per unit error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Coefficients {
    pub param: String,
    pub k: Vec<f64>,
    pub k_n: Vec<f64>,
    pub k_t: Vec<f64>,
    pub k_b: Vec<f64>,
}

/// The coefficients of `param` (e.g. `EXX`, `EBB`, or a location error) at every frame, for the
/// tool tip of `chain`.
pub fn coefficients(
    chain: &Chain,
    frames: &[SurfaceFrame],
    param: ErrorParam,
) -> Result<Coefficients, SensitivityError> {
    let mut c = Coefficients {
        param: param.name(),
        k: Vec::with_capacity(frames.len()),
        k_n: Vec::with_capacity(frames.len()),
        k_t: Vec::with_capacity(frames.len()),
        k_b: Vec::with_capacity(frames.len()),
    };
    for f in frames {
        let j = point_jacobian(chain, &f.q, 0.0, &MachineErrors::none(), &[param])?;
        let e: Vector3<f64> = j.column(0).into_owned();
        c.k.push(e.norm());
        c.k_n.push(e.dot(&f.n));
        c.k_t.push(e.dot(&f.t));
        c.k_b.push(e.dot(&f.b));
    }
    Ok(c)
}

/// Surface frames along the S-shape flank path of surface `s` (eq. 2) at `samples + 1` equally
/// spaced `u` in [0, 1], with the axis values of `opts.chain` / `opts.branch`. Machined in
/// increasing `u`, the outward normal `N` of the spec is `n` of down-cutting on A and of
/// up-cutting on B.
pub fn flank_frames(
    part: &SShape,
    s: Surface,
    opts: &SensitivityOptions,
    samples: usize,
    cutting: Cutting,
) -> Result<Vec<SurfaceFrame>, SensitivityError> {
    let us: Vec<f64> = (0..=samples.max(1))
        .map(|k| k as f64 / samples.max(1) as f64)
        .collect();
    let path = machine_path(part, &opts.chain, s, opts.branch, &us)?;
    let poses: Vec<_> = us.iter().map(|&u| tool_pose(part, s, u)).collect();
    let tips: Vec<Vector3<f64>> = poses.iter().map(|p| p.tip).collect();
    let axes: Vec<Vector3<f64>> = poses.iter().map(|p| p.axis).collect();
    let q: Vec<AxisValues> = path.iter().map(|p| p.values).collect();
    Ok(surface_frames(&tips, &axes, &q, cutting))
}

/// Surface frames around the cone frustum `cone` (paper 002 §4.2) at `samples` equally spaced
/// `φ` in [0, 2π), machined by `chain` on `branch`, up-cutting; returns the angles (rad) with
/// the frames.
pub fn cone_frames(
    cone: &ConeFrustum,
    chain: &Chain,
    branch: Branch,
    samples: usize,
) -> Result<(Vec<f64>, Vec<SurfaceFrame>), SensitivityError> {
    let n = samples.max(2);
    let phis: Vec<f64> = (0..n)
        .map(|k| 2.0 * std::f64::consts::PI * k as f64 / n as f64)
        .collect();
    let path = inverse_path(
        chain,
        branch,
        |p| cone.tool_pose(p),
        (0.0, phis[n - 1]),
        2000,
        &phis,
    )?;
    let poses: Vec<_> = phis.iter().map(|&p| cone.tool_pose(p)).collect();
    let tips: Vec<Vector3<f64>> = poses.iter().map(|p| p.0).collect();
    let axes: Vec<Vector3<f64>> = poses.iter().map(|p| p.1).collect();
    let q: Vec<AxisValues> = path.iter().map(|p| p.values).collect();
    let frames = surface_frames(&tips, &axes, &q, Cutting::Up);
    Ok((phis, frames))
}
