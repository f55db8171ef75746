//! The std of every number of the corrected kinematic description (each axis's point and
//! direction, the tool tip, each offset vector), propagated from the entered errors
//! ([`super::propagate`]), returned in the description's own shape: the same
//! [`KinematicDescription`] with each number replaced by its std (mm, or unit-vector
//! components).

use nalgebra::DMatrix;

use super::controller::machine_errors;
use super::propagate::{jacobian, propagated_std};
use crate::machine::axis_lines::{kinematic_description, KinematicDescription};
use crate::machine::{Chain, LocationError};

/// The description's numbers in order: per axis its point (rotary) then its direction, the
/// tool tip, the offset vectors.
pub fn numbers(d: &KinematicDescription) -> Vec<f64> {
    let mut v = Vec::new();
    for a in &d.axes {
        if let Some(p) = a.point {
            v.extend(p);
        }
        v.extend(a.direction);
    }
    v.extend(d.tool_tip);
    for o in &d.offsets {
        v.extend(o.vector);
    }
    v
}

/// `d` with its numbers replaced by `v` (in [`numbers`] order).
pub fn with_numbers(d: &KinematicDescription, v: &[f64]) -> KinematicDescription {
    let mut it = v.iter().copied();
    let mut take = || -> [f64; 3] {
        [
            it.next().unwrap_or(f64::NAN),
            it.next().unwrap_or(f64::NAN),
            it.next().unwrap_or(f64::NAN),
        ]
    };
    let mut out = d.clone();
    for a in &mut out.axes {
        if a.point.is_some() {
            a.point = Some(take());
        }
        a.direction = take();
    }
    out.tool_tip = take();
    for o in &mut out.offsets {
        o.vector = take();
    }
    out
}

/// The std of the description of `chain` with `errors` at `values`, covariance `cov`, and the
/// Jacobian it was propagated with (rows in [`numbers`] order).
pub fn description_std(
    chain: &Chain,
    errors: &[LocationError],
    values: &[f64],
    cov: &DMatrix<f64>,
) -> (KinematicDescription, DMatrix<f64>) {
    let f = |x: &[f64]| numbers(&kinematic_description(chain, &machine_errors(errors, x)));
    let steps: Vec<f64> = errors.iter().map(|l| 1e-2 * l.typical()).collect();
    let j = jacobian(&f, values, &steps);
    let std = propagated_std(&j, cov);
    let d = kinematic_description(chain, &machine_errors(errors, values));
    (with_numbers(&d, &std), j)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::machine::chain::PAPER000_L0;
    use crate::machine::AxisName;

    fn err(s: &str) -> LocationError {
        LocationError::parse(s).unwrap()
    }

    /// The Jacobian of paper 000's description against its closed-form first-order derivatives
    /// at small errors: the B line's direction is (−EC0B, 1, EA0B + EA0Z) (the tilts of B and of
    /// Z, which carries it), its point moves by EX0B along x; the tool tip, L0 below B, moves by
    /// (−L0·EB0Z, L0·EA0Z + L0·EA0B, 0) (a rotation of the head by a about x moves the tip at
    /// (0, 0, −L0) by (0, L0·a, 0)). Tolerance 1e-6 per unit (the second-order terms at the
    /// evaluation point 1e-5 rad: ~L0·1e-5·(derivative) ≈ 5e-3 mm/rad on 500 mm/rad, relative
    /// 1e-5; and 1e-6 on the unit-vector entries).
    #[test]
    fn the_jacobian_matches_the_first_order_closed_form() {
        let chain = Chain::paper000(PAPER000_L0);
        let errors: Vec<LocationError> = [
            "EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B",
        ]
        .iter()
        .map(|s| err(s))
        .collect();
        let x = vec![0.0; errors.len()];
        let cov = DMatrix::identity(errors.len(), errors.len());
        let (_, j) = description_std(&chain, &errors, &x, &cov);
        let d = kinematic_description(&chain, &machine_errors(&errors, &x));
        // Row of the B line's point x, direction x/z, and the tool tip.
        let mut row = 0;
        let mut b_point = 0;
        let mut b_dir = 0;
        for a in &d.axes {
            if a.point.is_some() {
                if a.axis == AxisName::B {
                    b_point = row;
                }
                row += 3;
            }
            if a.axis == AxisName::B {
                b_dir = row;
            }
            row += 3;
        }
        let tip = row;
        let col = |n: &str| errors.iter().position(|e| e.name() == n).unwrap();
        assert_near!(j[(b_dir, col("EC0B"))], -1.0, 1e-6);
        assert_near!(j[(b_dir + 2, col("EA0B"))], 1.0, 1e-6);
        assert_near!(j[(b_dir + 2, col("EA0Z"))], 1.0, 1e-6);
        assert_near!(j[(b_point, col("EX0B"))], 1.0, 1e-6);
        assert_near!(j[(tip + 1, col("EA0B"))], PAPER000_L0, 5e-3);
        assert_near!(j[(tip + 1, col("EA0Z"))], PAPER000_L0, 5e-3);
        assert_near!(j[(tip, col("EB0Z"))], -PAPER000_L0, 5e-3);
        assert_near!(j[(tip, col("EX0B"))], 1.0, 1e-6);
        // Unit covariance: std² of the tip's y is the sum of its squared derivatives.
        let (s, _) = description_std(&chain, &errors, &x, &cov);
        let sum: f64 = (0..errors.len()).map(|k| j[(tip + 1, k)].powi(2)).sum();
        assert_near!(s.tool_tip[1], sum.sqrt(), 1e-9);
    }
}
