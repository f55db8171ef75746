//! The serialisable result of an identification (`testpiece identify --json`, cli.md).

use serde::ser::SerializeMap;
use serde::{Deserialize, Serialize, Serializer};

use super::groups::Group;
use super::stats::ResidualStats;
use crate::machine::Unit;
use crate::parameter::ParamId;

/// How well one parameter is determined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Determined, std below the weak limit.
    Identified,
    /// Determined with a large std (member of a weak group or std above the weak limit).
    Weak,
    /// Not separable from other parameters: its value is the minimum-norm one and it has no
    /// std of its own; see the group's estimable combinations.
    NotSeparable,
}

/// One identified parameter: its id (serialised as `kind`, `name`, `unit`), value and std.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParameterEstimate {
    #[serde(flatten)]
    pub id: ParamId,
    /// Identified value (in the parameter's unit: mm or rad).
    pub value: f64,
    /// Standard deviation (same unit); `None` (JSON null) when not separable or no dof.
    pub std: Option<f64>,
    pub status: Status,
    /// `|value| / std`: below 2 the value is not distinguishable from 0 at 95 %.
    pub t: Option<f64>,
    /// Identified and clearly non-zero: `t ≥` [`NONZERO_T`] (the page's summary lists these).
    pub nonzero: bool,
}

impl ParameterEstimate {
    /// Its name ([`ParamId::name`]).
    pub fn name(&self) -> String {
        self.id.name()
    }
    /// Its unit ([`ParamId::unit`]).
    pub fn unit(&self) -> Unit {
        self.id.unit()
    }
}

/// `t` at or above which an identified value is reported as clearly non-zero.
pub const NONZERO_T: f64 = 3.0;

/// Parameters in design order, serialised as a JSON object `{name: {...}}` in that order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ParameterMap(pub Vec<ParameterEstimate>);

impl Serialize for ParameterMap {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for p in &self.0 {
            m.serialize_entry(&p.name(), p)?;
        }
        m.end()
    }
}

impl ParameterMap {
    /// The estimate of a parameter by name (as a report or a caller writes it).
    pub fn get(&self, name: &str) -> Option<&ParameterEstimate> {
        self.0.iter().find(|p| p.id.name() == name)
    }
    /// The estimate of a parameter.
    pub fn of(&self, id: &ParamId) -> Option<&ParameterEstimate> {
        self.0.iter().find(|p| p.id == *id)
    }
}

/// A point left out of the fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExcludedPoint {
    pub id: String,
    pub reason: String,
}

/// Residual statistics of one curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CurveStats {
    pub curve: String,
    #[serde(flatten)]
    pub stats: ResidualStats,
}

/// The cosine of two design columns (the "correlation" of s-shape.md: -0.9996 for EA0Z/EA0C in
/// paper mode), listed when `|cos|` is at least the report limit (0.7).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ColumnCorrelation {
    pub a: String,
    pub b: String,
    pub cosine: f64,
}

/// Fitted value and residual at one point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointFit {
    pub id: String,
    pub curve: String,
    pub measured: f64,
    pub fitted: f64,
    pub residual: f64,
    pub used: bool,
}

/// Everything an identification reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identification {
    /// `{name: {value, std, unit, status, t}}`.
    pub parameters: ParameterMap,
    /// Not-separable and weak groups with their named combinations.
    pub groups: Vec<Group>,
    /// Numerical rank of the scaled design (threshold `max(n,p)·ε·s₁`).
    pub rank: usize,
    /// Directions kept in the solution (rank minus the near-dependent ones).
    pub rank_used: usize,
    /// Condition number of the unit-column-scaled weighted design (JSON null if infinite).
    pub condition: f64,
    /// Condition number over the kept directions.
    pub condition_used: f64,
    /// The condition-index limit above which a direction is not separated.
    pub condition_index_limit: f64,
    /// Singular values of the scaled design, decreasing.
    pub singular_values: Vec<f64>,
    /// Residual statistics over the used points.
    pub residual: ResidualStats,
    /// Per curve, in order of first appearance.
    pub per_curve: Vec<CurveStats>,
    pub points_used: usize,
    pub points_excluded: Vec<ExcludedPoint>,
    /// σ of unit weight used for the covariance (mm).
    pub sigma: Option<f64>,
    /// `a_posteriori` (from the residual, n - rank_used dof) or `a_priori` (given).
    pub sigma_source: String,
    /// Degrees of freedom of the residual.
    pub dof: usize,
    /// Parameter correlation matrix, rows/columns in `parameters` order (null where undefined).
    pub correlation: Vec<Vec<Option<f64>>>,
    /// Covariance matrix (units² of the parameters), same order.
    pub covariance: Vec<Vec<f64>>,
    /// Strongly correlated design columns.
    pub column_correlations: Vec<ColumnCorrelation>,
    /// Per point fit.
    pub points: Vec<PointFit>,
    /// What was fixed or regularised, and why, in sentences.
    pub notes: Vec<String>,
}

impl Identification {
    /// Parameter names in design order.
    pub fn names(&self) -> Vec<String> {
        self.parameters
            .0
            .iter()
            .map(ParameterEstimate::name)
            .collect()
    }
    /// Values in design order.
    pub fn values(&self) -> Vec<f64> {
        self.parameters.0.iter().map(|p| p.value).collect()
    }
    /// Value of a parameter by name.
    pub fn value(&self, name: &str) -> Option<f64> {
        self.parameters.get(name).map(|p| p.value)
    }
}
