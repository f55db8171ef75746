//! The flank tool path of the S-shape (paper 000 eq. 2, `shared/spec/s-shape.md`), and of any
//! [`RuledPart`] with its own tip offset `L_tool` (the cone frustums).
//!
//! `T_tool(u) = C1(u) + R_tool·N(u,1) - L_tool·R(u)`, tool axis `w(u) = R(u)`, with
//! `R_tool = 10 mm` (radius) and `L_tool = 35 mm` (the tool tip is 35 mm below the top curve along
//! the axis). The tool is a cylinder of radius 10 mm standing on its tip. Its derivative
//! `T_tool' = C1' + R_tool·N_u(u,1) - L_tool·R'` enters the envelope condition (eq. 5).
//! Units: mm; `u` unitless.

use nalgebra::Vector3;

#[cfg(test)]
use crate::part::SShape;
use crate::part::{RuledPart, Surface};

/// Nominal tool radius `R_tool` (mm), paper 000 §3.1.
pub const TOOL_RADIUS: f64 = 10.0;

/// One tool position of the flank path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToolPose {
    /// Tool tip `T_tool(u)` (mm, part coordinates)
    pub tip: Vector3<f64>,
    /// Unit tool axis `R(u)`, pointing from the tip into the spindle
    pub axis: Vector3<f64>,
}

/// A tool pose with its derivatives along the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToolPoseDerivs {
    pub pose: ToolPose,
    /// `dT_tool/du` (mm)
    pub tip_u: Vector3<f64>,
    /// `dR/du`
    pub axis_u: Vector3<f64>,
}

/// The tool pose of eq. 2 at path parameter `u ∈ [0, 1]` (clamped) for surface `s`.
pub fn tool_pose<P: RuledPart + ?Sized>(part: &P, s: Surface, u: f64) -> ToolPose {
    // The frame alone (no curvature): the same arithmetic as `tool_pose_derivs(..).pose`.
    let f = part.frame_at(s, u, 1.0);
    ToolPose {
        tip: f.point + f.n * TOOL_RADIUS - f.r * part.tip_offset(),
        axis: f.r,
    }
}

/// The tool pose of eq. 2 and its first derivative in `u`.
pub fn tool_pose_derivs<P: RuledPart + ?Sized>(part: &P, s: Surface, u: f64) -> ToolPoseDerivs {
    let f = part.frame_derivs_at(s, u, 1.0);
    let c1 = f.frame.point;
    let l_tool = part.tip_offset();
    let tip = c1 + f.frame.n * TOOL_RADIUS - f.frame.r * l_tool;
    let tip_u = f.s_u + f.n_u * TOOL_RADIUS - f.r_u * l_tool;
    ToolPoseDerivs {
        pose: ToolPose {
            tip,
            axis: f.frame.r,
        },
        tip_u,
        axis_u: f.r_u,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::part::ruled::TIP_OFFSET;
    use crate::tolerance::FD_REL;

    /// The fast pose (frame without curvature) is the pose of `tool_pose_derivs`, bit for bit,
    /// and so is the S-shape's frame (tolerance: none).
    #[test]
    fn fast_pose_is_bit_identical() {
        let part = crate::part::SShape::iso();
        for s in Surface::BOTH {
            for k in 0..=10_000 {
                let u = k as f64 / 10_000.0;
                let a = tool_pose(&part, s, u);
                let b = tool_pose_derivs(&part, s, u).pose;
                assert_eq!((a.tip, a.axis), (b.tip, b.axis), "{s:?} u = {u}");
                for v in [0.0, 0.37, 1.0] {
                    assert_eq!(part.frame_at(s, u, v), part.frame_derivs_at(s, u, v).frame);
                }
            }
        }
    }

    #[test]
    fn tool_axis_passes_10_mm_from_the_top_curve_along_n() {
        // eq. 2: the axis point 35 mm above the tip is C1 + 10·N(u,1).
        let p = SShape::iso();
        for s in Surface::BOTH {
            for i in 0..=50 {
                let u = i as f64 / 50.0;
                let t = tool_pose(&p, s, u);
                let f = p.frame_at(s, u, 1.0);
                let top = t.tip + t.axis * TIP_OFFSET;
                assert_near!((top - f.point - f.n * TOOL_RADIUS).norm(), 0.0, 1e-12);
                // the axis is the ruling: C0 lies on the line through C1 along R, offset by 10 N
                let c0 = p.point_at(s, u, 0.0) + f.n * TOOL_RADIUS;
                let off = (c0 - t.tip) - t.axis * (c0 - t.tip).dot(&t.axis);
                assert_near!(off.norm(), 0.0, 1e-9);
            }
        }
    }

    #[test]
    fn derivative_matches_central_difference() {
        let p = SShape::iso();
        let h = 1e-6;
        for s in Surface::BOTH {
            for i in 1..100 {
                let u = i as f64 / 100.0 + 2.1e-4;
                let d = tool_pose_derivs(&p, s, u);
                let fd = (tool_pose(&p, s, u + h).tip - tool_pose(&p, s, u - h).tip) / (2.0 * h);
                assert!(
                    (d.tip_u - fd).norm() <= FD_REL * (1.0 + fd.norm()),
                    "u = {u}"
                );
                let fa = (tool_pose(&p, s, u + h).axis - tool_pose(&p, s, u - h).axis) / (2.0 * h);
                assert!(
                    (d.axis_u - fa).norm() <= FD_REL * (1.0 + fa.norm()),
                    "u = {u}"
                );
            }
        }
    }
}
