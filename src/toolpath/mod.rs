//! Flank tool path (paper 000 eq. 2), tool envelope and overcut (eq. 3-7), tool profile (paper 001).

pub mod flank;

pub use flank::{
    contact_height, tool_pose, tool_pose_derivs, ToolPose, ToolPoseDerivs, TIP_OFFSET, TOOL_RADIUS,
};
