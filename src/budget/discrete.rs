//! The deviation a discrete tool path leaves at a measurement point (paper 000 §4.1, Fig. 13).
//!
//! "For each point `P_s`, a vector `n_s` is computed regarding the normal to the surface. The
//! vector is oriented outwards from the surface and defines a line `(n_s)`. […] The intersection
//! is calculated between each line `(n_s)` and each tool position defined by the tool tip and the
//! axis of the tool. The smallest abscissa along the straight line `(n_s)` of all existing
//! intersections is retained."
//!
//! Each tool position `k` is the solid cylinder of radius `R` standing on its tip `E_k` with unit
//! axis `w_k` ([`crate::toolpath::envelope::line_entry`]: smaller root of
//! `|a⊥ + t·N⊥|² = R²`, `a = P − E_k`, with the flat end `h ≥ 0`), so
//!
//! `deviation(P) = min_k t_enter(k)`   (mm; + = material left, − = overcut).
//!
//! Only positions that **face** the point take part: the tool's axis must lie on the outward
//! side of `P` (`((P − E_k)⊥w_k)·N < 0`) and the entry within [`MAX_ABSCISSA`] of `P`. This keeps
//! the tools of the other side of the S-shape wall (which the normal line also crosses, beyond
//! the wall) and tools of far-away parts of the path out of the minimum.
//!
//! Between two positions the real tool sweeps material the discrete positions do not remove: the
//! discrete deviation is larger than the swept envelope's by at most the chord (scallop) error
//! of eq. 7, `error ≈ step² / (8·R_tool)` (reported in its exact form [`chord_error`]), with
//! `step` the distance moved by the axis point at the contact height between the retained
//! position and its neighbours on the same pass (a jump over [`MAX_PASS_STEP`] starts a new
//! pass: retracts, the other surface). Eq. 7 is exact for a straight path; where the path curves
//! around the part with radius ρ (tool centre), the scallop is `step²/8R · ρ_s/ρ` with ρ_s = ρ ± R
//! the surface's radius, a few % more on the concave parts of the S. [`DiscreteHit::local_bound`]
//! is eq. 7 with that local radius, measured from the neighbouring positions.

use nalgebra::Vector3;
use serde::Serialize;

use super::{BudgetError, ToolPath};
use crate::part::MeasurementPoint;
use crate::toolpath::envelope::line_entry;
use crate::toolpath::ToolPose;

/// Largest |abscissa| (mm) of an entry that counts: a path farther than this from the part is
/// not a path for it.
pub const MAX_ABSCISSA: f64 = 5.0;
/// A jump of the tool tip larger than this (mm) between consecutive positions starts a new pass.
pub const MAX_PASS_STEP: f64 = 5.0;

/// The deepest entry of the normal line of one point into a discrete tool path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DiscreteHit {
    /// `min_k t_enter(k)` (mm): + material left, − overcut.
    pub deviation: f64,
    /// Index of the retained tool position (0-based, file order).
    pub index: usize,
    /// Its line in the file.
    pub line: usize,
    /// Height of the entry point above that tool's tip (mm).
    pub height: f64,
    /// Distance moved at the contact height to the neighbouring positions of the pass (mm).
    pub step: f64,
    /// Eq. 7 bound of the discretisation error, `step² / (8R)` (mm, exact chord form).
    pub chord_bound: f64,
    /// Eq. 7 with the local radius of the path's envelope along this normal line instead of
    /// `R`: `(t_{k−1} − 2 t_k + t_{k+1}) / 8` from the neighbouring positions' entries (mm); it
    /// exceeds `chord_bound` where the path curves towards the part (concave, ρ/(ρ−R)).
    pub local_bound: f64,
}

/// A tool path ready for intersections: poses and pass boundaries.
#[derive(Debug, Clone)]
pub struct PreparedPath {
    poses: Vec<ToolPose>,
    lines: Vec<usize>,
    /// `pass[k]`: index of the pass of position `k`.
    pass: Vec<usize>,
}

impl PreparedPath {
    pub fn new(path: &ToolPath) -> Self {
        let v = |a: &[f64; 3]| Vector3::new(a[0], a[1], a[2]);
        let poses: Vec<ToolPose> = path
            .tips
            .iter()
            .zip(&path.axes)
            .map(|(t, a)| ToolPose {
                tip: v(t),
                axis: v(a),
            })
            .collect();
        let mut pass = Vec::with_capacity(poses.len());
        let mut p = 0;
        for k in 0..poses.len() {
            if k > 0 && (poses[k].tip - poses[k - 1].tip).norm() > MAX_PASS_STEP {
                p += 1;
            }
            pass.push(p);
        }
        Self {
            poses,
            lines: path.lines.clone(),
            pass,
        }
    }

    /// Number of passes (runs of positions without a jump over [`MAX_PASS_STEP`]).
    pub fn passes(&self) -> usize {
        self.pass.last().map_or(0, |p| p + 1)
    }

    /// Largest tip step within a pass (mm).
    pub fn max_step(&self) -> f64 {
        (1..self.poses.len())
            .filter(|&k| self.pass[k] == self.pass[k - 1])
            .map(|k| (self.poses[k].tip - self.poses[k - 1].tip).norm())
            .fold(0.0, f64::max)
    }

    /// The deepest entry of the line `p + t·n` (n the outward unit normal) among the positions
    /// facing `p`, for a tool of radius `radius` (mm); `None` when none reaches it.
    pub fn deviation_at(
        &self,
        p: &Vector3<f64>,
        n: &Vector3<f64>,
        radius: f64,
    ) -> Option<DiscreteHit> {
        let mut best: Option<(usize, f64)> = None;
        for (k, pose) in self.poses.iter().enumerate() {
            let Some(t) = line_entry(pose, radius, p, n) else {
                continue;
            };
            if t.abs() > MAX_ABSCISSA || best.is_some_and(|(_, b)| t >= b) {
                continue;
            }
            let a = p - pose.tip;
            let radial = a - pose.axis * a.dot(&pose.axis);
            if radial.dot(n) < 0.0 {
                best = Some((k, t));
            }
        }
        let (k, t) = best?;
        let pose = &self.poses[k];
        let height = (p + n * t - pose.tip).dot(&pose.axis);
        let at = |j: usize| self.poses[j].tip + self.poses[j].axis * height;
        let mut step: f64 = 0.0;
        for j in [k.wrapping_sub(1), k + 1] {
            if j < self.poses.len() && self.pass[j] == self.pass[k] {
                step = step.max((at(j) - at(k)).norm());
            }
        }
        let chord_bound = chord_error(step, radius);
        // eq. 7 with the local radius: the second difference of the entry abscissa over the
        // neighbouring positions, t(j) ≈ t_min + a (j − j0)² with |j0 − k| ≤ 1/2, so
        // t_k − t_min ≤ a/4 = (t_{k−1} − 2 t_k + t_{k+1}) / 8.
        let neighbour = |j: usize| {
            (j < self.poses.len() && self.pass[j] == self.pass[k])
                .then(|| line_entry(&self.poses[j], radius, p, n))
                .flatten()
        };
        let local_bound = match (neighbour(k.wrapping_sub(1)), neighbour(k + 1)) {
            (Some(a), Some(c)) => ((a - 2.0 * t + c) / 8.0).max(0.0),
            _ => chord_bound,
        };
        Some(DiscreteHit {
            deviation: t,
            index: k,
            line: self.lines.get(k).copied().unwrap_or(0),
            height,
            step,
            chord_bound,
            local_bound,
        })
    }
}

/// The chord (scallop) error of a discretisation step (mm): `R − √(R² − step²/4)`, whose Taylor
/// expansion is paper 000 eq. 7, `error ≈ step² / (8R)` (the exact form is a true bound for two
/// circles `step` apart; eq. 7 is `s⁴/128R³` = 5e-7 mm below it at 0.5 mm steps and R = 10 mm).
pub fn chord_error(step: f64, radius: f64) -> f64 {
    let half = 0.5 * step;
    if half >= radius {
        radius
    } else {
        // R − √(R² − s²/4) written without cancellation
        half * half / (radius + (radius * radius - half * half).sqrt())
    }
}

/// The deviation of a discrete path at each point (its outward normal line), tool radius
/// `radius` (mm). A point no facing position reaches is an error naming it.
pub fn path_deviation(
    path: &ToolPath,
    points: &[MeasurementPoint],
    radius: f64,
) -> Result<Vec<DiscreteHit>, BudgetError> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(BudgetError::BadRadius(radius));
    }
    let prepared = PreparedPath::new(path);
    points
        .iter()
        .map(|p| {
            prepared
                .deviation_at(&p.point, &p.normal, radius)
                .ok_or_else(|| BudgetError::NotReached {
                    name: path.name.clone(),
                    id: p.id.to_string(),
                    curve: p.curve.name().to_string(),
                    x: p.point.x,
                    y: p.point.y,
                    z: p.point.z,
                    limit: MAX_ABSCISSA,
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    fn straight(step: f64, n: usize) -> ToolPath {
        // a vertical tool of radius 10 moving along +x at y = 10: a plane wall y = 0 is machined,
        // with scallops between positions (eq. 7).
        ToolPath {
            name: "line".into(),
            format: "test".into(),
            tips: (0..n).map(|k| [k as f64 * step, 10.0, 0.0]).collect(),
            axes: vec![[0.0, 0.0, 1.0]; n],
            lines: (1..=n).collect(),
            times: None,
            cutter_diameter: None,
            notes: vec![],
        }
    }

    #[test]
    fn scallop_between_positions_is_the_chord_error_of_eq7() {
        // closed form: midway between two circles of radius R whose centres are s apart, the
        // wall is at R − √(R² − s²/4) ≈ s²/8R (eq. 7).
        let (s, r) = (0.5, 10.0);
        let path = PreparedPath::new(&straight(s, 21));
        let n = Vector3::new(0.0, 1.0, 0.0);
        let mid = path
            .deviation_at(&Vector3::new(2.25, 0.0, 5.0), &n, r)
            .unwrap();
        assert_near!(mid.deviation, r - (r * r - s * s / 4.0).sqrt(), 1e-12);
        assert_near!(mid.chord_bound, mid.deviation, 1e-15);
        // eq. 7 is its Taylor expansion
        assert_near!(
            chord_error(s, r) - s * s / (8.0 * r),
            s.powi(4) / (128.0 * r.powi(3)),
            1e-9
        );
        let on = path
            .deviation_at(&Vector3::new(2.0, 0.0, 5.0), &n, r)
            .unwrap();
        assert_near!(on.deviation, 0.0, 1e-12);
        assert_near!(on.height, 5.0, 1e-12);
        // the tools on the other side of a 3 mm wall do not count, the normal of the far side
        // is reached by them alone
        let mut both = straight(s, 21);
        both.tips
            .extend((0..21).map(|k| [k as f64 * s, -13.0, 0.0]));
        both.axes.extend(vec![[0.0, 0.0, 1.0]; 21]);
        both.lines.extend(22..=42);
        let prepared = PreparedPath::new(&both);
        assert_eq!(prepared.passes(), 2);
        let a = prepared
            .deviation_at(&Vector3::new(2.0, 0.0, 5.0), &n, r)
            .unwrap();
        assert_near!(a.deviation, 0.0, 1e-12);
        let b = prepared
            .deviation_at(&Vector3::new(2.0, -3.0, 5.0), &-n, r)
            .unwrap();
        assert_near!(b.deviation, 0.0, 1e-12);
        assert!(b.index >= 21);
    }
}
