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
}

impl PositionError {
    /// The value at the axis values `q`.
    pub fn at(&self, q: &AxisValues) -> f64 {
        self.law.at(q.get(self.axis))
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
