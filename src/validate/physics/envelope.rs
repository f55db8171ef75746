//! The surface a moving tool leaves, at the measurement points: the envelope of the tool bodies
//! at the actual poses of a pass (paper 000 §4.1, Fig. 13, with the actual motion in place of the
//! programmed one).
//!
//! At a point `P` with outward normal `N`, the machined surface along the line `P + t·N` is where
//! the first tool body enters it: `deviation(P) = min_k t_enter(pose_k)` (mm; + material left,
//! − overcut). The tool is a body of revolution standing on its tip, radius `r(h)` at height `h`
//! above the tip (a cylinder, a worn or tapered flank): `t_enter` is the entry into the cylinder
//! of radius `r(h)` ([`crate::toolpath::envelope::line_entry`]) with `h` the height of the entry
//! point, solved by fixed-point iteration (`dh/dt = N·w` is small on a flank-milled wall, so three
//! passes converge to far below 1e-9 mm for `|dr/dh| ≤ 0.01`).
//!
//! The poses are the samples of a pass (every `step` mm of path). The minimum over them is found
//! by a scan every [`STRIDE`] samples over ±[`WINDOW_MM`] of path around the point's own sample
//! (widened while the minimum lies on the window's edge), then at every sample around the best
//! one, then by the parabola through the best sample and its neighbours (the entry is quadratic
//! in the path near its minimum: the vertex is exact for a quadratic, and the neighbours lie
//! `step` apart, 0.05 mm at most: the envelope of the continuous motion to ≪ 1e-6 mm). Poses are
//! asked for lazily (only the windows' samples are ever computed).

use nalgebra::Vector3;

use crate::toolpath::envelope::line_entry;
use crate::toolpath::flank::ToolPose;

use super::PhysicsError;

/// Half-width of the first scan window (mm of tool-tip path).
pub const WINDOW_MM: f64 = 5.0;
/// Samples between the scan's poses.
pub const STRIDE: usize = 4;

/// The tools of one pass, asked for by sample index.
pub struct PassTools<'a> {
    /// Number of samples.
    pub samples: usize,
    /// Sample spacing (mm of path).
    pub step: f64,
    /// The actual tool pose (tip and unit axis, part frame) at a sample.
    pub pose: &'a dyn Fn(usize) -> Result<ToolPose, PhysicsError>,
    /// The tool radius (mm) at a sample and a height above the tip (mm).
    pub radius: &'a dyn Fn(usize, f64) -> f64,
}

/// The deviation (mm) along `n` at `p` left by the tools of a pass, scanning from sample `near`;
/// `cache` holds the poses computed so far (one slot per sample).
pub fn deviation_at(
    tools: &PassTools,
    p: &Vector3<f64>,
    n: &Vector3<f64>,
    near: usize,
    cache: &mut [Option<ToolPose>],
) -> Result<f64, PhysicsError> {
    let last = tools.samples - 1;
    let mut entry = |k: usize| -> Result<Option<f64>, PhysicsError> {
        let pose = match cache[k] {
            Some(p) => p,
            None => {
                let p = (tools.pose)(k)?;
                cache[k] = Some(p);
                p
            }
        };
        Ok(entry_into(&pose, &|h| (tools.radius)(k, h), p, n))
    };
    let mut half = ((WINDOW_MM / tools.step).ceil() as usize).max(STRIDE);
    let best = loop {
        let lo = near.saturating_sub(half);
        let hi = (near + half).min(last);
        let mut best: Option<(usize, f64)> = None;
        let mut k = lo;
        while k <= hi {
            if let Some(t) = entry(k)? {
                if best.is_none_or(|(_, b)| t < b) {
                    best = Some((k, t));
                }
            }
            k += STRIDE;
        }
        let Some((kb, _)) = best else {
            return Err(PhysicsError::NoToolReaches {
                x: p.x,
                y: p.y,
                z: p.z,
            });
        };
        let on_edge = (kb < lo + STRIDE && lo > 0) || (kb + STRIDE > hi && hi < last);
        if on_edge && half < tools.samples {
            half *= 2;
            continue;
        }
        break kb;
    };
    // every sample around the scan's best, then the parabola
    let (lo, hi) = (best.saturating_sub(STRIDE), (best + STRIDE).min(last));
    let mut fine: Option<(usize, f64)> = None;
    for k in lo..=hi {
        if let Some(t) = entry(k)? {
            if fine.is_none_or(|(_, b)| t < b) {
                fine = Some((k, t));
            }
        }
    }
    let Some((k, t)) = fine else {
        return Err(PhysicsError::NoToolReaches {
            x: p.x,
            y: p.y,
            z: p.z,
        });
    };
    if k == 0 || k == last {
        return Ok(t);
    }
    Ok(match (entry(k - 1)?, entry(k + 1)?) {
        (Some(a), Some(c)) if a + c - 2.0 * t > 0.0 => {
            t - (c - a).powi(2) / (8.0 * (a + c - 2.0 * t))
        }
        _ => t,
    })
}

/// Where the line `p + t·n` enters a tool of radius `radius(h)` at `pose` (`None`: it misses).
pub fn entry_into(
    pose: &ToolPose,
    radius: &dyn Fn(f64) -> f64,
    p: &Vector3<f64>,
    n: &Vector3<f64>,
) -> Option<f64> {
    let height = |t: f64| (p + n * t - pose.tip).dot(&pose.axis);
    let mut r = radius(height(0.0));
    let mut t = line_entry(pose, r, p, n)?;
    for _ in 0..3 {
        let next = radius(height(t));
        if next == r {
            break;
        }
        r = next;
        t = line_entry(pose, r, p, n)?;
    }
    Some(t)
}
