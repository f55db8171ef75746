//! Error motions of an axis as functions of its position (ISO 230-1; paper 004 eq. S2; paper 002
//! E_XX): what a real slide adds to its commanded motion wherever it stands.
//!
//! Each is `E_{component, axis}(q)` (mm for the translations X, Y, Z; rad for the rotations),
//! given by a [`Law`] in the axis position `q`, and enters the exact chain at every pose as the
//! error motion of [`crate::machine::direct`] with the value it has there (a constant, power 0,
//! per pose; [`error_params`]). The laws:
//! - **linear** `k·q` (a scale error: `E_XX = k·X`);
//! - **bow** `a·((q − q₀)/w)²` (the straightness of a slide whose guideway sags or arches; its
//!   linear part is a squareness, which the location errors hold);
//! - **sine** `a·sin(2π q/λ + φ)`: a cyclic error (the ballscrew's lead, a scale's period) when `λ`
//!   is short, a long-wave pitch error of the ballscrew when `λ` is long.
//!
//! **Reference.** ISO 230-1 measures an error motion from its reference straight line: the
//! least-squares line of a straightness error motion over the travel is the axis's squareness
//! and its offset a position of the axis, both location errors; a positioning error motion is
//! measured from the axis's reference position (here `q = 0`, the reference pose where the
//! part origin is set), its slope being the axis's scale. A motion made by
//! [`PositionError::from_reference`] has that part taken off its law, so that what it adds to
//! the part is an error motion and not a location error under another name (the product's
//! machine convention maps such offsets onto the kept location errors: `testpiece machine`,
//! `EY0Y ≈ … EA0B …`).
//!
//! Units: mm and rad.

use crate::machine::{AxisName, AxisValues, ErrorParam};

/// How an error motion varies with its axis's position.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "law", rename_all = "snake_case")]
pub enum Law {
    /// `k·q`.
    Linear { k: f64 },
    /// `a·((q − center)/half_width)²`.
    Bow {
        a: f64,
        center: f64,
        half_width: f64,
    },
    /// `a·sin(2π q/wavelength + phase)`.
    Sine { a: f64, wavelength: f64, phase: f64 },
}

impl Law {
    /// The value at axis position `q`.
    pub fn at(&self, q: f64) -> f64 {
        match *self {
            Law::Linear { k } => k * q,
            Law::Bow {
                a,
                center,
                half_width,
            } => a * ((q - center) / half_width).powi(2),
            Law::Sine {
                a,
                wavelength,
                phase,
            } => a * (2.0 * std::f64::consts::PI * q / wavelength + phase).sin(),
        }
    }

    /// The same law with its amplitude times `f`.
    pub fn scaled(&self, f: f64) -> Self {
        match *self {
            Law::Linear { k } => Law::Linear { k: k * f },
            Law::Bow {
                a,
                center,
                half_width,
            } => Law::Bow {
                a: a * f,
                center,
                half_width,
            },
            Law::Sine {
                a,
                wavelength,
                phase,
            } => Law::Sine {
                a: a * f,
                wavelength,
                phase,
            },
        }
    }
}

/// One error motion: `component` (X, Y, Z: translation; A, B, C: rotation) of `axis`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PositionError {
    pub component: AxisName,
    pub axis: AxisName,
    pub law: Law,
    /// The line `c₀ + c₁·q` taken off the law (module docs, **Reference**; zero: the law as it
    /// is).
    pub reference: [f64; 2],
}

/// Samples of the travel the least-squares reference line is fitted on.
const REFERENCE_SAMPLES: usize = 201;

impl PositionError {
    /// The law as it is, no reference taken off (a scale error `k·q`, zero at the reference
    /// pose).
    pub fn new(component: AxisName, axis: AxisName, law: Law) -> Self {
        Self {
            component,
            axis,
            law,
            reference: [0.0; 2],
        }
    }

    /// The law measured from its ISO 230-1 reference over the travel `(lo, hi)` of `axis`: a
    /// straightness (`component ≠ axis`) from its least-squares line over the travel, a
    /// positioning error (`component = axis`) from its value at `q = 0`.
    pub fn from_reference(
        component: AxisName,
        axis: AxisName,
        law: Law,
        travel: (f64, f64),
    ) -> Self {
        let reference = if component == axis {
            [law.at(0.0), 0.0]
        } else {
            let (lo, hi) = travel;
            let m = REFERENCE_SAMPLES as f64;
            let q: Vec<f64> = (0..REFERENCE_SAMPLES)
                .map(|i| lo + (hi - lo) * i as f64 / (m - 1.0))
                .collect();
            let v: Vec<f64> = q.iter().map(|&x| law.at(x)).collect();
            let qm = q.iter().sum::<f64>() / m;
            let vm = v.iter().sum::<f64>() / m;
            let sqq: f64 = q.iter().map(|x| (x - qm).powi(2)).sum();
            let sqv: f64 = q.iter().zip(&v).map(|(x, y)| (x - qm) * (y - vm)).sum();
            let c1 = if sqq > 0.0 { sqv / sqq } else { 0.0 };
            [vm - c1 * qm, c1]
        };
        Self {
            component,
            axis,
            law,
            reference,
        }
    }

    /// The same motion with its amplitude (and its reference) times `f`.
    pub fn scaled(&self, f: f64) -> Self {
        Self {
            law: self.law.scaled(f),
            reference: [self.reference[0] * f, self.reference[1] * f],
            ..*self
        }
    }

    /// The value at the axis values `q`.
    pub fn at(&self, q: &AxisValues) -> f64 {
        let x = q.get(self.axis);
        self.law.at(x) - self.reference[0] - self.reference[1] * x
    }
}

/// The error parameters of `motions` at the pose `q`: each one's value there as a constant error
/// motion (power 0) of its axis.
pub fn error_params(motions: &[PositionError], q: &AxisValues) -> Vec<(ErrorParam, f64)> {
    motions
        .iter()
        .map(|m| {
            (
                ErrorParam::Motion {
                    component: m.component,
                    axis: m.axis,
                    power: 0,
                },
                m.at(q),
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bow off the middle of its travel measured from its least-squares line: over the travel
    /// it has no mean and no slope left (the sums over the 201 samples, 1e-12 of its size), and
    /// its curvature is the law's (the second difference at the middle, 1e-9 relative); a
    /// positioning error is zero at `q = 0` with its slope, the scale, kept.
    #[test]
    fn a_motion_is_measured_from_its_reference() {
        let law = Law::Bow {
            a: 0.01,
            center: 40.0,
            half_width: 250.0,
        };
        let m = PositionError::from_reference(AxisName::X, AxisName::Y, law, (-100.0, 100.0));
        let at = |y: f64| {
            let mut q = AxisValues::default();
            q.set(AxisName::Y, y);
            m.at(&q)
        };
        let ys: Vec<f64> = (0..REFERENCE_SAMPLES)
            .map(|i| -100.0 + 200.0 * i as f64 / (REFERENCE_SAMPLES as f64 - 1.0))
            .collect();
        let mean: f64 = ys.iter().map(|&y| at(y)).sum::<f64>();
        let slope: f64 = ys.iter().map(|&y| y * at(y)).sum::<f64>();
        assert!(mean.abs() < 1e-12 * 0.01 * 201.0, "{mean}");
        assert!(slope.abs() < 1e-12 * 0.01 * 201.0 * 100.0, "{slope}");
        let curvature = at(1.0) - 2.0 * at(0.0) + at(-1.0);
        let want = law.at(1.0) - 2.0 * law.at(0.0) + law.at(-1.0);
        assert!(
            (curvature - want).abs() < 1e-9 * want.abs(),
            "{curvature} {want}"
        );
        let pitch = Law::Sine {
            a: 0.003,
            wavelength: 300.0,
            phase: 0.7,
        };
        let p = PositionError::from_reference(AxisName::Y, AxisName::Y, pitch, (-100.0, 100.0));
        let mut q = AxisValues::default();
        assert_eq!(p.at(&q), 0.0);
        q.set(AxisName::Y, 50.0);
        assert!((p.at(&q) - (pitch.at(50.0) - pitch.at(0.0))).abs() < 1e-15);
    }
}
