//! Five-axis kinematic chains, inverse and direct kinematics (paper 000 eq. 8-10), ISO 230-1
//! location errors and error motions (eq. 11-12, paper 002 eq. 1-2, paper 004 eq. S1-S3).
//!
//! The pipeline of this module:
//! - [`chain`]: a machine as **data**: a structural code in the spirit of ISO 10791
//!   (`w C Y' b X Z B t`), the sign and offset of every axis and the tool offset. Nothing is
//!   hard-coded per machine; [`chain::Chain::paper000`], [`chain::Chain::paper002`] and
//!   [`chain::Chain::paper001`] are three instances of the same data.
//! - [`location_errors`]: the 6 ISO 230-1 location errors of every axis and the minimal
//!   independent set derived from the chain (paper 000 Table 3).
//! - [`error_motion`]: position-dependent error motions δ, ε of each axis (paper 004 eq. S2,
//!   paper 002 E_XX … E_CC), polynomial in the axis position.
//! - [`direct`]: exact direct kinematics with the error matrices of eq. 11 inserted before every
//!   axis motion (eq. 12), tool point and tool direction (paper 004 eq. S3), and the analytic
//!   Jacobian with respect to every error parameter.
//! - [`inverse`]: inverse kinematics of any chain with three linear and two rotary axes, with a
//!   branch choice (signed tilt, default, or tilt ≥ 0), and along a path with the outer rotary
//!   angle unwrapped and interpolated linearly across singular zones (spec s-shape.md).
//! - [`description`]: the JSON machine-description file read by `testpiece forward --machine`.
//! - [`unit`]: the unit of a parameter's value ([`Unit`]), set where the parameter is defined.
//!
//! Units: mm and rad (the CLI converts degrees at its boundary). Positions are the tool point in
//! the workpiece frame; the tool direction points from the tip up the tool, towards the spindle.

pub mod axis_lines;
pub mod chain;
pub mod description;
pub mod direct;
pub mod error_motion;
pub mod inverse;
pub mod location_errors;
pub mod rates;
mod transform;
pub mod unit;

pub use chain::{AxisKind, AxisName, AxisValues, Chain, ChainAxis, Side};
pub use description::MachineDescription;
pub use direct::{ErrorParam, MachineErrors, ToolPoint};
pub use error_motion::{ErrorMotion, MotionComponent};
pub use inverse::{Branch, PathSample};
pub use location_errors::{LocationError, LocationStatus, MinimalSet};
pub use unit::Unit;

/// Failures of the machine stage, with the offending values.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MachineError {
    #[error("structural code `{code}`: {reason}")]
    BadCode { code: String, reason: String },
    #[error("the chain `{code}` has {found} rotary axes; inverse kinematics needs exactly 2")]
    RotaryCount { code: String, found: usize },
    #[error("the chain `{code}` has {found} linear axes; inverse kinematics needs X, Y and Z")]
    LinearCount { code: String, found: usize },
    #[error(
        "rotary axes {outer} and {inner} cannot orient the tool: the inner one must not be \
         parallel to the tool and the two must be perpendicular"
    )]
    DegenerateRotaries { outer: String, inner: String },
    #[error("the linear axes do not span space at this pose (determinant {det:e})")]
    SingularLinear { det: f64 },
    #[error("tool direction ({x}, {y}, {z}) is not a unit vector (norm {norm})")]
    BadDirection { x: f64, y: f64, z: f64, norm: f64 },
    #[error("tool direction ({x}, {y}, {z}) cannot be reached by these rotary axes")]
    Unreachable { x: f64, y: f64, z: f64 },
    #[error("`{name}` is not an error parameter name (expected e.g. EC0Y, EX0B, or EXX1)")]
    BadErrorName { name: String },
    #[error(
        "error parameter {name} refers to axis {axis}, which the chain `{code}` does not have"
    )]
    UnknownAxis {
        name: String,
        axis: String,
        code: String,
    },
    #[error("error parameter {name} = {value} is too large for the eq. 11 matrix (needs |E| < 1)")]
    ErrorTooLarge { name: String, value: f64 },
    #[error("the error matrices make the workpiece chain singular (determinant {det:e})")]
    SingularErrorMatrix { det: f64 },
    #[error("machine description: {message}")]
    DescriptionJson {
        /// The JSON reader's message (line and column of the fault).
        message: String,
    },
    #[error("machine description: offsets: `{name}` is not an axis letter (X Y Z A B C)")]
    OffsetAxis { name: String },
    #[error("path: empty domain [{u0}, {u1}] or grid of {grid} steps")]
    EmptyDomain { u0: f64, u1: f64, grid: usize },
    #[error("path: u = {u} is outside the path domain [{u0}, {u1}]")]
    OutsideDomain { u: f64, u0: f64, u1: f64 },
    #[error("path: u = {u} lost from the grid")]
    LostFromGrid { u: f64 },
    #[error("path: axis rates: singular Jacobian")]
    SingularRates,
}
