//! Where the plan measures: `n` points per measurement curve at equal arc length from 5 % to
//! 95 % of the curve `S(·, v)`, `v = Z/30`, in increasing `u` (the built-in layout of
//! `shared/spec/s-shape.md` "Measurement points" with 25 replaced by `n`; one point sits at
//! 50 %). Ids run 1.. curve by curve in the order `A_Z11, A_Z25, B_Z11, B_Z25`. With `n = 25`
//! the points are [`crate::part::builtin_points`] exactly (same arc-length table, same
//! fractions). Units: mm.

use super::PlanError;
pub use crate::part::points::arc_fraction;
use crate::part::points::{curve_points_n, Curve};
use crate::part::{MeasurementPoint, SShape};

/// Most points per curve a plan places (a CMM program of 4 × 1000 points is already long).
pub const MAX_PER_CURVE: usize = 1000;

/// Points per curve of a plan of `total` points: `total / 4` each, the remainder to the first
/// curves (`A_Z11` first). `total` must lie in `4..=4·MAX_PER_CURVE`.
pub fn split_total(total: usize) -> Result<[usize; 4], PlanError> {
    if !(4..=4 * MAX_PER_CURVE).contains(&total) {
        return Err(PlanError::TotalPoints {
            total,
            max: 4 * MAX_PER_CURVE,
        });
    }
    let (q, r) = (total / 4, total % 4);
    Ok([0, 1, 2, 3].map(|k| q + usize::from(k < r)))
}

/// The points of a plan with `per_curve[c]` points on curve `Curve::ALL[c]` (each in
/// `1..=MAX_PER_CURVE`), ids from 1.
pub fn plan_points(
    part: &SShape,
    per_curve: [usize; 4],
) -> Result<Vec<MeasurementPoint>, PlanError> {
    if let Some(&bad) = per_curve
        .iter()
        .find(|&&n| !(1..=MAX_PER_CURVE).contains(&n))
    {
        return Err(PlanError::PointsPerCurve {
            per_curve: bad,
            max: MAX_PER_CURVE,
        });
    }
    let mut out = Vec::with_capacity(per_curve.iter().sum());
    for (curve, &n) in Curve::ALL.iter().zip(&per_curve) {
        out.extend(curve_points_n(part, *curve, out.len() + 1, n));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::part::builtin_points;

    /// 25 per curve is the built-in layout, bit for bit (same table, same fractions).
    #[test]
    fn twenty_five_per_curve_is_the_builtin_layout() {
        let part = SShape::iso();
        let plan = plan_points(&part, [25; 4]).unwrap();
        assert_eq!(plan, builtin_points(&part));
    }

    #[test]
    fn totals_split_with_the_remainder_first() {
        assert_eq!(split_total(100).unwrap(), [25; 4]);
        assert_eq!(split_total(42).unwrap(), [11, 11, 10, 10]);
        assert_eq!(
            split_total(3).unwrap_err().to_string(),
            "3 points in all: expected 4 to 4000 (spread over the 4 curves)"
        );
        assert_eq!(arc_fraction(0, 1), 0.5);
        let part = SShape::iso();
        assert!(plan_points(&part, [0, 1, 1, 1]).is_err());
        let p = plan_points(&part, [1, 2, 3, 4]).unwrap();
        assert_eq!(p.len(), 10);
        assert_eq!(
            p.iter().map(|q| q.id).collect::<Vec<_>>(),
            (1..=10).collect::<Vec<_>>()
        );
    }
}
