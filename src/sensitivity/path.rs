//! Axis values of the flank tool path (paper 000 eq. 10): inverse kinematics of
//! `u ↦ (T_tool(u), R(u))` with the outer rotary angle unwrapped from `u = 0` and interpolated
//! linearly in `u` on the vertical zone `u ∈ [6/13, 8/13]` where `R` is exactly vertical and C is
//! undefined (spec s-shape.md; [`crate::machine::inverse::inverse_path`]).

use std::cell::RefCell;
use std::rc::Rc;

use crate::machine::inverse::inverse_path;
use crate::machine::{Branch, Chain, PathSample};
use crate::numerics::memo::Memo;
use crate::part::{SShape, Surface};
use crate::toolpath::flank::tool_pose;

use super::SensitivityError;

/// Unwrapping grid: steps over `u ∈ [0, 1]` (20 per knot span of the S-shape curves; the test
/// below shows the paths bit-identical to 200 per span).
pub const PATH_GRID: usize = 260;

/// Point sets of at most this many parameters are kept by [`machine_path`].
pub const KEEP_MAX: usize = 25_000;

/// What a kept path depends on.
struct PathKey {
    part: SShape,
    chain: Chain,
    surface: Surface,
    branch: Branch,
    us: Vec<u64>,
}

thread_local! {
    /// The last few point sets' paths: a part model asks for the same points' axis values
    /// five times (location errors, scale, machine Z, index and backlash columns).
    static KEPT: RefCell<Memo<PathKey, Vec<PathSample>>> = const { RefCell::new(Memo::new(4)) };
}

/// Axis values of the flank path of surface `s` at the parameters `us` (each in [0, 1]). The
/// last few sets of parameters are kept per thread (the same values: the computation is
/// deterministic), so the part model's five uses of its points' axis values solve them once.
pub fn machine_path(
    part: &SShape,
    chain: &Chain,
    s: Surface,
    branch: Branch,
    us: &[f64],
) -> Result<Vec<PathSample>, SensitivityError> {
    if us.len() > KEEP_MAX {
        return solve_path(part, chain, s, branch, us);
    }
    let bits: Vec<u64> = us.iter().map(|u| u.to_bits()).collect();
    let is = |k: &PathKey| {
        k.surface == s && k.branch == branch && k.us == bits && k.chain == *chain && k.part == *part
    };
    if let Some(kept) = KEPT.with(|m| m.borrow_mut().find(is)) {
        return Ok(kept.to_vec());
    }
    let path = solve_path(part, chain, s, branch, us)?;
    let key = PathKey {
        part: part.clone(),
        chain: chain.clone(),
        surface: s,
        branch,
        us: bits,
    };
    KEPT.with(|m| m.borrow_mut().insert(key, Rc::new(path.clone())));
    Ok(path)
}

/// Forgets the kept paths of this thread (they belong to points: a first file, a benchmark of
/// the kernels).
pub fn clear_kept() {
    KEPT.with_borrow_mut(Memo::clear);
}

/// [`machine_path`] without keeping the result (the reversal passes' windows, asked once).
pub fn solve_path(
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

    /// A kept path is the solved one, bit for bit, and another set of parameters is not served
    /// from it.
    #[test]
    fn a_kept_path_is_the_solved_path() {
        let part = SShape::iso();
        let chain = Chain::paper000(PAPER000_L0);
        let us = [0.1, 0.5, 0.9];
        let solved = solve_path(&part, &chain, Surface::A, Branch::Signed, &us).unwrap();
        let first = machine_path(&part, &chain, Surface::A, Branch::Signed, &us).unwrap();
        let kept = machine_path(&part, &chain, Surface::A, Branch::Signed, &us).unwrap();
        assert_eq!(first, solved);
        assert_eq!(kept, solved);
        let other = machine_path(&part, &chain, Surface::B, Branch::Signed, &us).unwrap();
        assert_eq!(
            other,
            solve_path(&part, &chain, Surface::B, Branch::Signed, &us).unwrap()
        );
        assert_ne!(other, solved);
    }

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
