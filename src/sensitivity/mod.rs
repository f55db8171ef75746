//! Machined defect (paper 000 eq. 14), Figure-19 curves, surface-frame coefficients (paper 002).
//!
//! The flank tool path `u ↦ (T_tool(u), R(u))` of eq. 2 ([`crate::toolpath::flank`]) is turned
//! into axis values by the inverse kinematics of the chain (eq. 10, [`path`]); the tool-point
//! displacement of the exact eq. 12 (or its linearisation eq. 13) is projected on a normal
//! ([`defect`]). Two modes (spec s-shape.md, "Errors and machined defect"):
//!
//! | | [`Mode::Physical`] (default) | [`Mode::Paper`] (eq. 14 as printed) |
//! |---|---|---|
//! | displaced tool point | the point of the tool axis `h` above the tip (`h` = contact height) | the tool tip |
//! | normal | `N(u,v)` at the measured point | `N(u,1)` |
//! | reference subtracted | the tip displacement with the tip at the part origin and the tool vertical (`(0,0,L0,0,0)` on paper 000's machine) | the tip displacement at all axes 0 |
//!
//! Sign: defect = displacement · N, **+ = material left, − = overcut**. Units: mm; sensitivities
//! in mm per rad (mm per mm for position errors such as `EX0B`).

pub mod cone_frustum;
pub mod defect;
pub mod error_set;
pub mod frenet;
pub mod path;
pub mod reversal;
pub mod ringing;
pub mod servo;
pub mod take_up;

pub use defect::{
    axis_values, axis_values_on, defect, defect_xi, linear_defect, sensitivity_matrix, Mode,
    SensitivityMatrix, SensitivityOptions,
};
pub use path::{machine_path, PATH_GRID};

use crate::machine::MachineError;

/// Failures of the sensitivity stage, with the offending values.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SensitivityError {
    #[error(transparent)]
    Machine(#[from] MachineError),
    #[error("point {id}: u = {u} is outside [0, 1]")]
    BadPoint { id: usize, u: f64 },
    #[error("`{0}` is not a mode (expected `physical` or `paper`)")]
    BadMode(String),
    #[error("{values} error values for {params} parameters")]
    ErrorCount { values: usize, params: usize },
    #[error("{poses} axis values for {points} points")]
    PoseCount { poses: usize, points: usize },
}
