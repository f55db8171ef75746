//! Property tests of the B-spline curves (paper 000 eq. 1; Piegl & Tiller A2.1/A2.3) on random
//! curves: partition of unity of the basis (and zero sum of its derivatives), first and second
//! derivatives against central finite differences, endpoint interpolation of clamped curves
//! (rational too). Random degrees 1-5, 1-8 extra control points in ±100 mm, random interior
//! knots, weights 0.2-5.

use nalgebra::Vector3;
use proptest::prelude::*;
use testpiece::geometry::bspline::BSplineCurve;

/// A clamped knot vector with `n - p - 1` random distinct interior knots.
fn knots(n: usize, p: usize, interior: &[f64]) -> Vec<f64> {
    let mut inner: Vec<f64> = interior.iter().take(n - p - 1).copied().collect();
    inner.sort_by(f64::total_cmp);
    let mut k = vec![0.0; p + 1];
    k.extend(inner);
    k.extend(std::iter::repeat_n(1.0, p + 1));
    k
}

fn curve(
    p: usize,
    pts: &[(f64, f64, f64)],
    interior: &[f64],
    weights: Option<&[f64]>,
) -> BSplineCurve {
    let points: Vec<Vector3<f64>> = pts.iter().map(|&(x, y, z)| Vector3::new(x, y, z)).collect();
    let n = points.len();
    let k = knots(n, p, interior);
    match weights {
        None => BSplineCurve::try_new(p, k, points).unwrap(),
        Some(w) => BSplineCurve::try_new_rational(p, k, points, w[..n].to_vec()).unwrap(),
    }
}

/// (degree, control points, interior knots, weights, u).
type Inputs = (usize, Vec<(f64, f64, f64)>, Vec<f64>, Vec<f64>, f64);

fn inputs() -> impl Strategy<Value = Inputs> {
    (1usize..=5, 1usize..=8).prop_flat_map(|(p, extra)| {
        let n = p + extra;
        (
            Just(p),
            prop::collection::vec((-100.0..100.0f64, -100.0..100.0f64, -100.0..100.0f64), n),
            // interior knots kept 0.02 apart from the ends (distinct with probability 1)
            prop::collection::vec(0.02..0.98f64, n),
            prop::collection::vec(0.2..5.0f64, n),
            0.0..=1.0f64,
        )
    })
}

/// Distance of `u` from the nearest knot (the curve is only C^(p-1) across a knot).
fn knot_gap(c: &BSplineCurve, u: f64) -> f64 {
    c.knots()
        .iter()
        .map(|k| (k - u).abs())
        .fold(f64::INFINITY, f64::min)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Σ N_i,p(u) = 1 and Σ N_i,p^(k)(u) = 0 for k = 1..p, to 1e-12 (relative to the size of the
    /// derivatives, which grow like p/Δknot).
    #[test]
    fn partition_of_unity((p, pts, interior, _w, u) in inputs()) {
        let c = curve(p, &pts, &interior, None);
        let (_, ders) = c.basis_derivs(u, p);
        let s0: f64 = ders[0].iter().sum();
        prop_assert!((s0 - 1.0).abs() < 1e-12, "sum {}", s0);
        prop_assert!(ders[0].iter().all(|&v| v >= -1e-15), "negative basis {:?}", ders[0]);
        for row in &ders[1..] {
            let scale: f64 = row.iter().map(|v| v.abs()).sum::<f64>().max(1.0);
            let s: f64 = row.iter().sum();
            prop_assert!(s.abs() < 1e-12 * scale, "derivative sum {} of {:?}", s, row);
        }
    }

    /// C'(u) and C''(u) against central differences of C and C' (step 1e-6, away from knots by
    /// more than the step; degree >= 2 for C', >= 3 for C'' so that they are continuous).
    #[test]
    fn derivatives_match_finite_differences(
        (p, pts, interior, w, u) in inputs(), rational in any::<bool>()
    ) {
        let c = curve(p, &pts, &interior, rational.then_some(&w[..]));
        let h = 1e-6;
        prop_assume!(u > 2.0 * h && u < 1.0 - 2.0 * h && knot_gap(&c, u) > 4.0 * h);
        let d = c.derivs_at(u);
        let (dp, dm) = (c.derivs_at(u + h), c.derivs_at(u - h));
        if p >= 2 {
            let fd = (dp.point - dm.point) / (2.0 * h);
            let scale = 1.0 + d.d1.norm() + d.d2.norm() * h;
            prop_assert!((fd - d.d1).norm() < 1e-6 * scale, "d1 {} vs fd {}", d.d1, fd);
        }
        if p >= 3 {
            let fd2 = (dp.d1 - dm.d1) / (2.0 * h);
            let scale = 1.0 + d.d2.norm() + d.d1.norm();
            prop_assert!((fd2 - d.d2).norm() < 1e-5 * scale, "d2 {} vs fd {}", d.d2, fd2);
        }
    }

    /// A clamped curve passes through its first and last control points (rational or not).
    #[test]
    fn clamped_curves_interpolate_their_end_points(
        (p, pts, interior, w, _u) in inputs(), rational in any::<bool>()
    ) {
        let c = curve(p, &pts, &interior, rational.then_some(&w[..]));
        let cp = c.control_points();
        prop_assert!((c.point_at(0.0) - cp[0]).norm() < 1e-10);
        prop_assert!((c.point_at(1.0) - cp[cp.len() - 1]).norm() < 1e-10);
    }
}
