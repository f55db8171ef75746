//! Axis values of the flank tool path (paper 000 eq. 10): inverse kinematics of
//! `u ↦ (T_tool(u), R(u))` with the outer rotary angle unwrapped from `u = 0` and interpolated
//! linearly in `u` on the vertical zone `u ∈ [6/13, 8/13]` where `R` is exactly vertical and C is
//! undefined (spec s-shape.md; [`crate::machine::inverse::inverse_path`]).

use crate::machine::inverse::inverse_path;
use crate::machine::{Branch, Chain, PathSample};
use crate::part::{SShape, Surface};
use crate::toolpath::flank::tool_pose;

use super::SensitivityError;

/// Unwrapping grid: steps over `u ∈ [0, 1]` (200 per knot span of the S-shape curves).
pub const PATH_GRID: usize = 2600;

/// Axis values of the flank path of surface `s` at the parameters `us` (each in [0, 1]).
pub fn machine_path(
    part: &SShape,
    chain: &Chain,
    s: Surface,
    branch: Branch,
    us: &[f64],
) -> Result<Vec<PathSample>, SensitivityError> {
    let pose = |u: f64| {
        let p = tool_pose(part, s, u);
        (p.tip, p.axis)
    };
    Ok(inverse_path(
        chain,
        branch,
        pose,
        (0.0, 1.0),
        PATH_GRID,
        us,
    )?)
}
