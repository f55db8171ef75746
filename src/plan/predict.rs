//! What an identification on the plan's points will report before any part exists: the std of
//! every location error and the groups the part cannot separate.
//!
//! With an a priori σ the covariance of weighted least squares, `σ² D⁻¹ N (NᵀBᵀBN)⁻¹ Nᵀ D⁻¹`
//! ([`crate::identify`]), depends on the design alone, never on the measured deviations; the
//! groups (rank, condition indices, weak directions) likewise. So the prediction is
//! [`crate::identify::identify`] itself, run on the design at the plan's points with every
//! deviation 0 and `σ` given: the numbers a lab gets from `testpiece identify FILE --sigma σ
//! --effects none` on a part measured at these points (the same design), not a second formula
//! that could drift from it. Units: mm and rad (the parameters' own).

use serde::Serialize;

use super::PlanError;
use crate::analysis::{design_at, AnalysisOptions};
use crate::effects::prepared::Prepared;
use crate::identify::{
    identify, Group, Identification, IdentifyOptions, Observations, ParameterEstimate,
    ParameterMap, Status,
};
use crate::machine::AxisValues;
use crate::parameter::ParamId;
use crate::part::MeasurementPoint;

/// The predicted figures of one parameter (`{std, status}` with its `kind`, `name` and `unit`,
/// as `identify` names them).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PredictedParameter {
    #[serde(flatten)]
    pub id: ParamId,
    /// Predicted std (mm or rad); `None` (JSON null) when the parameter is not separable.
    pub std: Option<f64>,
    pub status: Status,
}

/// The prediction: per parameter, in design order, and the groups.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    pub names: Vec<String>,
    pub parameters: Vec<PredictedParameter>,
    pub groups: Vec<Group>,
    pub rank: usize,
    pub condition: f64,
}

impl Prediction {
    /// From an identification made with an a priori σ (its values are not used).
    pub fn of(id: &Identification) -> Self {
        let ParameterMap(ps) = &id.parameters;
        Prediction {
            names: ps.iter().map(ParameterEstimate::name).collect(),
            parameters: ps
                .iter()
                .map(|p| PredictedParameter {
                    id: p.id.clone(),
                    std: p.std,
                    status: p.status,
                })
                .collect(),
            groups: id.groups.clone(),
            rank: id.rank,
            condition: id.condition,
        }
    }
}

/// The identification of the baseline design of `opts` (its machine, mode, branch, L0, and the
/// `dR` column when asked; `prepared`: those settings) at `points` (axis values `q`,
/// [`Prepared::axis_values`]) for deviations all 0 and the a priori `sigma` (mm).
pub fn predicted_identification(
    prepared: &Prepared,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &AnalysisOptions,
    sigma: f64,
) -> Result<Identification, PlanError> {
    let (design, _) = design_at(prepared, points, q, opts).map_err(PlanError::Design)?;
    let obs = Observations::new(
        points.iter().map(|p| p.id.to_string()).collect(),
        points.iter().map(|p| p.curve.name().to_string()).collect(),
        vec![0.0; points.len()],
    );
    identify(&design, &obs, &IdentifyOptions::default().with_sigma(sigma))
        .map_err(PlanError::Identify)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// The std scales with σ exactly (the covariance is σ² times the design's): twice the σ,
    /// twice every std (relative 1e-12, rounding).
    #[test]
    fn std_is_linear_in_sigma() {
        let o = AnalysisOptions::default();
        let p = crate::analysis::prepare(&o).unwrap();
        let pts = crate::part::builtin_points(p.part());
        let q = p.axis_values(&pts).unwrap();
        let a = Prediction::of(&predicted_identification(&p, &pts, &q, &o, 0.001).unwrap());
        let b = Prediction::of(&predicted_identification(&p, &pts, &q, &o, 0.002).unwrap());
        for (p, q) in a.parameters.iter().zip(&b.parameters) {
            if let (Some(s), Some(t)) = (p.std, q.std) {
                assert_near!(t / s, 2.0, 1e-12);
            }
        }
        assert_eq!(a.names[5], "EX0B");
    }
}
