//! The commanded motion of one pass: the flank path of paper 000 eq. 2 timed at a constant feed,
//! the axis commands the inverse kinematics give at each sample (eq. 10).
//!
//! A pass is one surface machined in increasing `u` (effects.md). The tool tip moves at the
//! programmed feed `F` along the pass, so the path length `s = F·t` is the clock: the pass is
//! sampled every `step` mm of tool-tip path (`s_k = k·step`, the last sample at the end of the
//! pass), `s` being the chord sum of the tip on a grid of [`CHORD_GRID`] steps of `u` (the
//! `servo_signatures.csv` convention, reference README "How the path is timed"); `u(s)` is
//! linear between that grid's nodes. The commanded axes at `u_k` are
//! [`crate::machine::inverse::inverse_path`] of the eq. 2 pose: signed B, C unwrapped from the
//! start of the pass and linear in `u` across the vertical zone (s-shape.md). Between samples the
//! command is linear in time. Units: mm, rad.

use crate::machine::inverse::inverse_path;
use crate::machine::{AxisValues, Branch, Chain};
use crate::part::{SShape, Surface};
use crate::toolpath::flank::tool_pose;

use super::PhysicsError;

/// Steps of `u` of the chord sum that times the pass (0.0034 mm of path a chord: a chord is
/// shorter than its arc by κ²h²/24 of it, far below 1e-9 mm over the pass).
pub const CHORD_GRID: usize = 200_000;

/// Steps of the grid on which the C angle is unwrapped ([`crate::machine::inverse::inverse_path`];
/// the product's own path uses 260, bit-identical to ten times finer).
const UNWRAP_GRID: usize = 260;

/// The commanded motion of one pass, sampled every `step` mm of tool-tip path.
#[derive(Debug, Clone)]
pub struct CommandedPass {
    pub surface: Surface,
    /// Sample spacing along the tool-tip path (mm).
    pub step: f64,
    /// Tool-tip path length of each sample from the start of the pass (mm).
    pub s: Vec<f64>,
    /// Path parameter of each sample.
    pub u: Vec<f64>,
    /// Commanded axis values of each sample (mm, rad).
    pub q: Vec<AxisValues>,
    /// Length of the pass (mm).
    pub length: f64,
}

impl CommandedPass {
    /// The pass of surface `surface` on `chain` (branch `branch`), sampled every `step` mm.
    pub fn new(
        part: &SShape,
        chain: &Chain,
        branch: Branch,
        surface: Surface,
        step: f64,
    ) -> Result<Self, PhysicsError> {
        if !(step.is_finite() && step > 0.0) {
            return Err(PhysicsError::BadStep { step });
        }
        let chords = chord_sum(part, surface);
        let length = chords[CHORD_GRID];
        let samples = (length / step).ceil() as usize;
        let s: Vec<f64> = (0..=samples)
            .map(|k| (k as f64 * step).min(length))
            .collect();
        let u: Vec<f64> = s.iter().map(|&sk| u_at(&chords, sk)).collect();
        let pose = |u: f64| {
            let p = tool_pose(part, surface, u);
            (p.tip, p.axis)
        };
        let q = inverse_path(chain, branch, pose, (0.0, 1.0), UNWRAP_GRID, &u)?
            .into_iter()
            .map(|p| p.values)
            .collect();
        Ok(Self {
            surface,
            step,
            s,
            u,
            q,
            length,
        })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.s.len()
    }

    /// Whether the pass has no samples (never: a pass has at least its two ends).
    pub fn is_empty(&self) -> bool {
        self.s.is_empty()
    }

    /// The sample whose path parameter is nearest `u`.
    pub fn index_near(&self, u: f64) -> usize {
        let k = self.u.partition_point(|&x| x < u);
        if k == 0 {
            0
        } else if k >= self.u.len() {
            self.u.len() - 1
        } else if (self.u[k] - u) < (u - self.u[k - 1]) {
            k
        } else {
            k - 1
        }
    }
}

/// Chord sum of the tool tip at `u = i/CHORD_GRID` (mm), `i = 0..=CHORD_GRID`.
fn chord_sum(part: &SShape, surface: Surface) -> Vec<f64> {
    let mut out = Vec::with_capacity(CHORD_GRID + 1);
    let mut prev = tool_pose(part, surface, 0.0).tip;
    let mut acc = 0.0;
    out.push(0.0);
    for i in 1..=CHORD_GRID {
        let tip = tool_pose(part, surface, i as f64 / CHORD_GRID as f64).tip;
        acc += (tip - prev).norm();
        out.push(acc);
        prev = tip;
    }
    out
}

/// `u` at path length `s` (mm): linear between the chord grid's nodes.
fn u_at(chords: &[f64], s: f64) -> f64 {
    let k = chords.partition_point(|&c| c <= s).clamp(1, CHORD_GRID);
    let (a, b) = (chords[k - 1], chords[k]);
    let f = if b > a {
        ((s - a) / (b - a)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((k - 1) as f64 + f) / CHORD_GRID as f64
}
