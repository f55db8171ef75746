//! Flank tool path (paper 000 eq. 2), tool envelope and overcut (eq. 3-7), tool profile (paper 001).

pub mod envelope;
pub mod flank;

pub use envelope::{
    builtin_envelope, points_deviation, surface_max_overcut, EnvelopeHit, FlankPath,
    PointDeviation, SurfaceMax,
};
pub use flank::{
    contact_height, tool_pose, tool_pose_derivs, ToolPose, ToolPoseDerivs, TIP_OFFSET, TOOL_RADIUS,
};

/// Failures of tool-path and envelope computations, with the offending values.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ToolpathError {
    #[error("tool radius {radius} mm is not a positive finite number")]
    BadRadius { radius: f64 },
    #[error("no tool position of the flank path reaches the normal line at ({x}, {y}, {z})")]
    NoToolReaches { x: f64, y: f64, z: f64 },
}
