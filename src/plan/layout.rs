//! Where the plan measures: `n` points per measurement curve at equal arc length from 5 % to
//! 95 % of the curve `S(·, v)`, `v = Z/30`, in increasing `u` (the built-in layout of
//! `shared/spec/s-shape.md` "Measurement points" with 25 replaced by `n`; one point sits at
//! 50 %). Ids run 1.. curve by curve in the order `A_Z11, A_Z25, B_Z11, B_Z25`. With `n = 25`
//! the points are [`crate::part::builtin_points`] exactly (same arc-length table, same
//! fractions). Units: mm.

use super::PlanError;
use crate::part::points::{arc_length_table, Curve, ARC_FRACTION_RANGE};
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

/// The arc-length fraction of point `k` of `n` on a curve: `5 % + k·90 %/(n − 1)`, or 50 % for
/// a single point.
pub fn arc_fraction(k: usize, n: usize) -> f64 {
    let (f0, f1) = ARC_FRACTION_RANGE;
    if n <= 1 {
        0.5 * (f0 + f1)
    } else {
        f0 + (f1 - f0) * k as f64 / (n - 1) as f64
    }
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
        let v = curve.v();
        let table = arc_length_table(part, curve.surface(), v);
        for k in 0..n {
            let frac = arc_fraction(k, n);
            // The fraction is inside [0, 1], so the length is in range: param_at cannot fail.
            let u = table
                .param_at(frac * table.total())
                .unwrap_or(frac)
                .clamp(0.0, 1.0);
            out.push(MeasurementPoint::at(part, out.len() + 1, *curve, u, v));
        }
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
