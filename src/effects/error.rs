//! The one error type of the gap stage: every message carries the offending values.

use thiserror::Error;

/// Why a diagnosis (or one of its inputs) was rejected.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GapError {
    #[error("{what}: {got} values, expected {expected} (one per point)")]
    LengthMismatch {
        what: String,
        got: usize,
        expected: usize,
    },
    #[error("{what}: {count} names for {columns} columns")]
    NameMismatch {
        what: String,
        count: usize,
        columns: usize,
    },
    #[error("{what} is not finite at point index {index} (value {value})")]
    NotFinite {
        what: String,
        index: usize,
        value: f64,
    },
    #[error("too few points: {points} points for {parameters} baseline parameters (need at least {needed})")]
    TooFewPoints {
        points: usize,
        parameters: usize,
        needed: usize,
    },
    #[error("noise sigma must be positive and finite, got {0}")]
    BadSigma(f64),
    #[error("candidate `{0}` appears twice")]
    DuplicateCandidate(crate::parameter::Effect),
    #[error("candidate `{0}` has no signature column")]
    EmptyCandidate(crate::parameter::Effect),
    /// An effect or a parameter named in text that comes in.
    #[error(transparent)]
    Parameter(#[from] crate::parameter::ParameterError),
    #[error("`{effect}` is not a candidate on the {machine}: {reason}")]
    NotOnMachine {
        effect: crate::parameter::Effect,
        /// The machine's description.
        machine: String,
        /// Why its physics does not exist there ([`crate::parameter::Effect::absent_from`]).
        reason: String,
    },
    #[error(
        "`{0}` has no signature in this part model (its axis is not modelled on this machine)"
    )]
    NotModelled(crate::parameter::Effect),
    #[error("the structure's covariance cannot be estimated (σ = {sigma} mm, {points} points)")]
    StructureNotEstimated { sigma: f64, points: usize },
    #[error("final identification: {0}")]
    Identify(#[from] crate::identify::IdentifyError),
    #[error("model of the part or machine: {0}")]
    Sensitivity(#[from] crate::sensitivity::SensitivityError),
    #[error("model of the part or machine: {0}")]
    Machine(#[from] crate::machine::MachineError),
    #[error("model of the part or machine: {0}")]
    Toolpath(#[from] crate::toolpath::ToolpathError),
    #[error("model of the part or machine: {0}")]
    Exact(#[from] crate::identify::refine::ModelError),
}
