//! Flank tool path (paper 000 eq. 2), tool envelope and overcut (eq. 3-7), tool profile (paper 001).

pub mod envelope;
pub mod flank;
pub mod layers;
pub mod profile;
pub mod tip_length;

pub use envelope::{
    builtin_envelope, points_deviation, surface_max_overcut, EnvelopeHit, FlankPath,
    PointDeviation, SurfaceMax,
};
pub use flank::{tool_pose, tool_pose_derivs, ToolPose, ToolPoseDerivs, TOOL_RADIUS};
pub use layers::{multilayer_deviation, LayerPlan, LayeredDeviation};
pub use profile::ToolProfile;

/// Failures of tool-path and envelope computations, with the offending values.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ToolpathError {
    #[error("tool radius {radius} mm is not a positive finite number")]
    BadRadius { radius: f64 },
    #[error("no tool position of the flank path reaches the normal line at ({x}, {y}, {z})")]
    NoToolReaches { x: f64, y: f64, z: f64 },
    #[error("a tool profile needs at least one (height, radius) pair")]
    EmptyProfile,
    #[error("profile height {index} = {height} mm is not finite or not above the previous one")]
    ProfileHeights { index: usize, height: f64 },
    #[error(
        "tool setup error rho = {rho} mm, phi = {phi} rad: both must be finite and |phi| < pi/2"
    )]
    BadSetupError { rho: f64, phi: f64 },
    #[error("layer plan: {layers} layers, pitch {pitch} mm, cutting length {cutting_length} mm; need at least one layer, pitch >= 0 and cutting length > 0 (overlap below the band)")]
    BadLayerPlan {
        layers: usize,
        pitch: f64,
        cutting_length: f64,
    },
    #[error("point {id} is not reached by any layer of the plan")]
    NotReachedByLayers { id: usize },
}
