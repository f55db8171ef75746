//! The errors of the identification stage. Every message carries the offending values.

use thiserror::Error;

/// What can go wrong when identifying parameters from measured deviations.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum IdentifyError {
    /// The design has no parameter column.
    #[error("the design matrix has no parameter column (0 columns)")]
    NoParameters,
    /// No measured point is left to fit.
    #[error("no measured point to fit ({total} points given, {excluded} excluded)")]
    NoPoints { total: usize, excluded: usize },
    /// The design's data do not have the announced shape.
    #[error("design matrix data has {found} numbers, expected {rows} rows x {cols} columns = {}", rows * cols)]
    DesignShape {
        rows: usize,
        cols: usize,
        found: usize,
    },
    /// Number of names does not match the number of columns.
    #[error("{names} parameter names for {cols} design columns")]
    NameCount { names: usize, cols: usize },
    /// A parameter name appears twice.
    #[error("parameter name `{name}` appears twice (columns {first} and {second})")]
    DuplicateName {
        name: String,
        first: usize,
        second: usize,
    },
    /// A parameter name is empty.
    #[error("parameter {index} has an empty name")]
    EmptyName { index: usize },
    /// The typical magnitude of a parameter is not a positive finite number.
    #[error("typical magnitude of `{name}` is {value}; it must be positive and finite")]
    BadTypical { name: String, value: f64 },
    /// A design entry is NaN or infinite.
    #[error("design matrix entry at point {row} (0-based), column `{column}` is {value}")]
    NonFiniteDesign {
        row: usize,
        column: String,
        value: f64,
    },
    /// The number of measured values does not match the design rows.
    #[error("{what}: {found} values for {expected} design rows")]
    LengthMismatch {
        what: &'static str,
        found: usize,
        expected: usize,
    },
    /// A measured deviation is NaN or infinite.
    #[error("measured deviation of point `{id}` is {value}")]
    NonFiniteDeviation { id: String, value: f64 },
    /// A weight is negative, NaN or infinite.
    #[error(
        "weight of point `{id}` is {value}; weights must be finite and >= 0 (0 excludes the point)"
    )]
    BadWeight { id: String, value: f64 },
    /// An option is out of its range.
    #[error("option {name} = {value} is out of range: {expected}")]
    BadOption {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
    /// A parameter named in an input is not in the design.
    #[error("unknown parameter `{name}`; the design has {known}")]
    UnknownParameter { name: String, known: String },
    /// A parameter named in text that comes in is not one.
    #[error(transparent)]
    Parameter(#[from] crate::parameter::ParameterError),
    /// A parameter named in text has no typical size of its own (an effect's parameter).
    #[error("`{name}` has no typical size of its own: give it with its column")]
    NoTypical { name: String },
    /// The exact model given to the refinement failed or returned the wrong shape.
    #[error("exact model: {0}")]
    Model(#[from] crate::identify::refine::ModelError),
}
