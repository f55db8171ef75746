//! Axis values of the flank tool path (paper 000 eq. 10): inverse kinematics of
//! `u ↦ (T_tool(u), R(u))` with the outer rotary angle unwrapped from `u = 0` and interpolated
//! linearly in `u` on the vertical zone `u ∈ [6/13, 8/13]` where `R` is exactly vertical and C is
//! undefined (spec s-shape.md; [`crate::machine::inverse::inverse_path`]).

use crate::machine::inverse::inverse_path;
use crate::machine::{Branch, Chain, PathSample};
use crate::part::{SShape, Surface};
use crate::toolpath::flank::tool_pose;

use super::SensitivityError;

/// Unwrapping grid: steps over `u ∈ [0, 1]` (20 per knot span of the S-shape curves; the test
/// below shows the paths bit-identical to 200 per span).
pub const PATH_GRID: usize = 260;

/// Axis values of the flank path of surface `s` at the parameters `us` (each in [0, 1]),
/// solved at each call: a caller that needs the same points' axis values several times solves
/// them once ([`crate::sensitivity::defect::axis_values`]) and passes them on.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::chain::PAPER000_L0;

    /// The unwrapping grid only has to keep the outer angle's step below a quarter turn; the
    /// result at every requested `u` is then bit-identical to a 10× finer grid (the singular
    /// zone's ends are found by bisection to adjacent doubles either way).
    #[test]
    fn path_is_bit_identical_to_a_ten_times_finer_grid() {
        let part = SShape::iso();
        let us: Vec<f64> = (0..=1999).map(|i| i as f64 / 1999.0).collect();
        for chain in [
            Chain::paper000(PAPER000_L0),
            Chain::paper002(),
            Chain::paper001(120.0, 80.0),
        ] {
            for s in Surface::BOTH {
                for branch in [Branch::Signed, Branch::Positive] {
                    let pose = |u: f64| {
                        let p = tool_pose(&part, s, u);
                        (p.tip, p.axis)
                    };
                    let fine = inverse_path(&chain, branch, pose, (0.0, 1.0), 10 * PATH_GRID, &us);
                    let ours = machine_path(&part, &chain, s, branch, &us);
                    match (fine, ours) {
                        (Ok(f), Ok(o)) => assert_eq!(f, o, "{} {s:?} {branch:?}", chain.code()),
                        (Err(_), Err(_)) => {}
                        (f, o) => panic!("{} {s:?}: {f:?} vs {o:?}", chain.code()),
                    }
                }
            }
        }
    }
}
