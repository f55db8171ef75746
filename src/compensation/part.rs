//! The part the same program would leave once the identified location errors are compensated.
//!
//! The identified model at every point is `Σ_j A_ij x_j` over the final answer's columns
//! (paper 000 eq. 13-14: location errors, then `dR` and the named effect's columns
//! `<id>.<parameter>` when fitted). A controller whose kinematic description holds the
//! identified location errors removes their part, `m_i = Σ_{j ∈ location} A_ij x_j`, from the
//! machined part (to first order: the compensated machine cuts the nominal path); everything
//! else stays: the part of the named effect and of `dR` (not errors of the kinematic
//! description: a tool, a setup, a backlash, a drift …) and the residual (noise and whatever
//! no model explains). So, per point (mm, + = material left, − = overcut):
//!
//! `after_i = measured_i − m_i = (effect part)_i + residual_i`.
//!
//! For a group the part cannot separate the individual values are a convention, but their
//! combined effect on this part, `m_i`, is determined: the prediction holds for this part and
//! this program (not for the machine elsewhere).

use serde::Serialize;

use crate::identify::solve::{max_abs, rms};
use crate::machine::Unit;
use crate::parameter::{ParamId, ParamKind};

/// One point before and after.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PredictedPoint {
    pub id: String,
    pub curve: String,
    /// The measured deviation (mm).
    pub measured: f64,
    /// The location errors' part, removed by the compensation (mm).
    pub machine: f64,
    /// The fitted part of what is not a location error (`dR`, effect columns; mm).
    pub left_model: f64,
    /// Measured minus every fitted part (mm).
    pub residual: f64,
    /// `measured − machine` (mm): the predicted deviation after compensation.
    pub after: f64,
    /// Whether the point entered the fit (outliers and excluded rows do not).
    pub used: bool,
}

/// RMS and largest |value| over the used points (mm).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Spread {
    pub rms: f64,
    pub max_abs: f64,
}

impl Spread {
    pub fn of(v: &[f64]) -> Self {
        Spread {
            rms: rms(v),
            max_abs: max_abs(v),
        }
    }
}

/// A fitted term the compensation leaves in the part.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LeftIn {
    /// The column's parameter.
    #[serde(skip)]
    pub id: ParamId,
    /// Its name (`dR`, `backlash_c.b`).
    pub parameter: String,
    pub value: f64,
    pub unit: Unit,
    /// RMS of its part over the used points (mm).
    pub rms: f64,
    /// What the parameter is.
    pub kind: ParamKind,
}

/// The predicted part after compensation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PredictedPart {
    pub points: Vec<PredictedPoint>,
    /// Measured deviations (used points).
    pub before: Spread,
    /// Predicted deviations after compensation (used points).
    pub after: Spread,
    /// The location errors' part alone.
    pub machine: Spread,
    pub left_in: Vec<LeftIn>,
}

/// The prediction from the final design's columns (`columns[j][i]`, mm per unit), their
/// parameters, values, which of them the compensation removes (the entered location errors,
/// [`super::entry`]; a location error not entered stays like an effect), and the measured
/// deviations.
#[allow(clippy::too_many_arguments)]
pub fn predicted_part(
    ids: &[String],
    curves: &[String],
    used: &[bool],
    measured: &[f64],
    params: &[ParamId],
    columns: &[Vec<f64>],
    values: &[f64],
    is_location: &[bool],
) -> PredictedPart {
    let n = measured.len();
    let part_of = |keep: bool| -> Vec<f64> {
        (0..n)
            .map(|i| {
                columns
                    .iter()
                    .zip(values)
                    .zip(is_location)
                    .filter(|(_, &loc)| loc == keep)
                    .map(|((c, x), _)| c[i] * x)
                    .sum()
            })
            .collect()
    };
    let (machine, left) = (part_of(true), part_of(false));
    let points: Vec<PredictedPoint> = (0..n)
        .map(|i| PredictedPoint {
            id: ids[i].clone(),
            curve: curves[i].clone(),
            measured: measured[i],
            machine: machine[i],
            left_model: left[i],
            residual: measured[i] - machine[i] - left[i],
            after: measured[i] - machine[i],
            used: used[i],
        })
        .collect();
    let over_used = |f: &dyn Fn(&PredictedPoint) -> f64| -> Vec<f64> {
        points.iter().filter(|p| p.used).map(f).collect()
    };
    let left_in = params
        .iter()
        .enumerate()
        .filter(|&(j, _)| !is_location[j])
        .map(|(j, id)| LeftIn {
            id: id.clone(),
            parameter: id.name(),
            value: values[j],
            unit: id.unit(),
            rms: rms(&(0..n)
                .filter(|&i| used[i])
                .map(|i| columns[j][i] * values[j])
                .collect::<Vec<_>>()),
            kind: id.kind(),
        })
        .collect();
    PredictedPart {
        before: Spread::of(&over_used(&|p| p.measured)),
        after: Spread::of(&over_used(&|p| p.after)),
        machine: Spread::of(&over_used(&|p| p.machine)),
        points,
        left_in,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// Two columns, a location error (1, 2) × 0.5 and an effect (1, −1) × 0.1: measured
    /// (0.7, 0.95) → machine (0.5, 1.0), left (0.1, −0.1), residual (0.1, 0.05), after
    /// (0.2, −0.05) (closed form, 1e-15 mm).
    #[test]
    fn the_location_part_is_removed_and_the_rest_left() {
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        let p = predicted_part(
            &s(&["1", "2"]),
            &s(&["A_Z11", "A_Z11"]),
            &[true, true],
            &[0.7, 0.95],
            &["EX0B".parse().unwrap(), "backlash_c.b".parse().unwrap()],
            &[vec![1.0, 2.0], vec![1.0, -1.0]],
            &[0.5, 0.1],
            &[true, false],
        );
        assert_near!(p.points[0].after, 0.2, 1e-15);
        assert_near!(p.points[1].after, -0.05, 1e-15);
        assert_near!(p.points[1].residual, 0.05, 1e-15);
        assert_near!(p.left_in[0].rms, 0.1, 1e-15);
        assert_near!(p.after.max_abs, 0.2, 1e-15);
    }
}
