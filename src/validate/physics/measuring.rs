//! What happens on the CMM: the part's placement, a part that moves while it is measured, and
//! the touch probe's direction-dependent pre-travel.
//!
//! A machined point `M = P + d·N` (`P` nominal, `d` the machined deviation) is probed along its
//! nominal normal; the CMM records the deviation `(M' − P)·N` of where it finds it, `M'` the
//! point as it really stands (to first order in the small displacements, which are µm on a
//! 250 mm part):
//! - **placement** (datum alignment): the part rotated by `θz` about Z and shifted by
//!   `(tx, ty)`: `M' = Rz(θz)·M + t`;
//! - **drift while measured**: the same rigid motion growing over the measurement order (the
//!   points in the order given, `x = k/(n − 1)` for the `k`-th), `θz(x), t(x) = (θz, t)·g(x)`,
//!   `g(x) = (1 − exp(−x/f))/(1 − exp(−1/f))`: a clamp relaxing, a part cooling on the table
//!   (linear for a large `f`);
//! - **three-lobed pre-travel** of a kinematic touch probe: the probe triggers late by
//!   `a·cos(3(φ − φ₀))` beyond its calibrated mean, `φ` the azimuth of the probing direction
//!   (`−N`) in the CMM's frame, so the point is recorded that much inside the material:
//!   `d' = d − a·cos(3(φ − φ₀))`.
//!
//! Units: mm, rad.

use nalgebra::{Rotation3, Vector3};

use crate::part::MeasurementPoint;

/// A small rigid motion of the part on the CMM table: rotation `theta_z` (rad) about Z, shift
/// `(tx, ty)` (mm).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Placement {
    pub theta_z: f64,
    pub tx: f64,
    pub ty: f64,
}

impl Placement {
    /// Where the point `m` stands after the motion scaled by `f`.
    fn moved(&self, m: &Vector3<f64>, f: f64) -> Vector3<f64> {
        Rotation3::from_axis_angle(&Vector3::z_axis(), self.theta_z * f) * m
            + Vector3::new(self.tx, self.ty, 0.0) * f
    }
}

/// How the measurement itself departs from the ideal.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Measuring {
    /// The part's placement (constant over the measurement).
    pub placement: Option<Placement>,
    /// The motion reached at the last point, and the shape `f` of its growth.
    pub drift: Option<(Placement, f64)>,
    /// The probe's lobing: amplitude `a` (mm) and phase `φ₀` (rad).
    pub lobing: Option<(f64, f64)>,
}

impl Measuring {
    /// The deviations the CMM records (mm) for the machined deviations `machined` at `points`.
    pub fn record(&self, points: &[MeasurementPoint], machined: &[f64]) -> Vec<f64> {
        let n = points.len();
        points
            .iter()
            .zip(machined)
            .enumerate()
            .map(|(k, (p, &d))| {
                let m = p.point + p.normal * d;
                let mut at = m;
                if let Some(pl) = &self.placement {
                    at = pl.moved(&at, 1.0);
                }
                if let Some((pl, f)) = &self.drift {
                    let x = if n > 1 {
                        k as f64 / (n - 1) as f64
                    } else {
                        0.0
                    };
                    at = pl.moved(&at, (1.0 - (-x / f).exp()) / (1.0 - (-1.0 / f).exp()));
                }
                let mut dev = (at - p.point).dot(&p.normal);
                if let Some((a, phase)) = self.lobing {
                    let phi = (-p.normal.y).atan2(-p.normal.x);
                    dev -= a * (3.0 * (phi - phase)).cos();
                }
                dev
            })
            .collect()
    }
}
