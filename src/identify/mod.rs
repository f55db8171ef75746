//! Least-squares identification of error parameters, identifiability, uncertainty.
//!
//! Pipeline position: sensitivity (design matrix `A`, paper 000 eq. 13-14) + CMM deviations →
//! **identify** → gap diagnosis. Everything here is generic over a named design matrix, so the
//! same code fits the 8 ISO 230-1 location errors, with or without the tool-radius term `dR`,
//! or any extra effect column.
//!
//! - [`Design`], [`Parameter`]: the columns, each with its parameter's id (kind, name and unit:
//!   [`crate::parameter::ParamId`]) and typical magnitude.
//! - [`Observations`]: measured deviations `(measured - nominal)·N` (mm; + = material left).
//! - [`identify`]: weighted least squares by truncated SVD of the column-scaled design
//!   ([`ScaledSvd`]: numerical rank, condition indices), covariance, correlations, residual
//!   statistics (paper 001 eq. 15-17), and the groups ([`groups`]): not-separable combinations
//!   (paper mode rediscovers `EA0Z`/`EA0C` and `EB0Z`/`EB0C`) and weak directions (physical mode:
//!   the squareness errors barely show above the CMM noise).
//! - [`monte_carlo`]: repeated fits with seeded noise from a CMM's maximum permissible error.
//! - [`refine`]: Levenberg-Marquardt on an exact model, where the linearisation error matters.
//! - [`correlated`]: generalised least squares with a full noise covariance (correlated errors).
//! - [`export`]: the identified values as a compensation table (CSV, JSON).
//!
//! Units: mm and rad. Sign convention: `deviation = (machined - nominal)·N`.

pub mod added_fits;
pub mod correlated;
mod design;
mod error;
pub mod export;
pub mod groups;
mod householder;
mod least_squares;
pub mod monte_carlo;
mod observations;
pub mod refine;
mod report;
mod scaled_svd;
pub mod solve;
mod stats;

pub use design::{Design, Parameter};
pub use error::IdentifyError;
pub use groups::{
    Combination, ConventionShare, Direction, Estimable, Group, GroupKind, CONVENTION_SHARE_FLOOR,
};
pub use least_squares::{identify, identify_factored, Factored, IdentifyOptions};
pub use observations::Observations;
pub use report::{
    ColumnCorrelation, CurveStats, ExcludedPoint, Identification, ParameterEstimate, ParameterMap,
    PointFit, Status, NONZERO_T,
};
pub use scaled_svd::{condition_of, ScaledSvd};
pub use stats::ResidualStats;
