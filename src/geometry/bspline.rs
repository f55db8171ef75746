//! Cubic (any degree) B-spline curves in 3-D, optionally rational.
//!
//! Paper 000 eq. 1: `C(u) = Σ_i N_{i,p}(u) P_i` with the clamped uniform knot vector
//! `{0,0,0,0, 1/13, …, 12/13, 1,1,1,1}` for the S-shape (16 control points, p = 3).
//! Basis functions and their derivatives by the Cox–de Boor recursion (Piegl & Tiller, *The NURBS
//! Book*, A2.1 FindSpan and A2.3 DersBasisFuns). Knot spans are right-open, except that `u = 1`
//! belongs to the last non-empty span, so the curve is defined on the closed interval `[0, 1]`.
//!
//! Units: whatever the control points are in (mm for every part in this crate); `u` is unitless.

use nalgebra::Vector3;

use super::GeometryError;

/// A (rational) B-spline curve of degree `p`.
#[derive(Debug, Clone, PartialEq)]
pub struct BSplineCurve {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<Vector3<f64>>,
    weights: Vec<f64>,
}

/// Value and first two derivatives of a curve at one parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveDerivs {
    /// `C(u)` (mm)
    pub point: Vector3<f64>,
    /// `dC/du` (mm)
    pub d1: Vector3<f64>,
    /// `d²C/du²` (mm)
    pub d2: Vector3<f64>,
}

impl BSplineCurve {
    /// A non-rational curve; checks `knots.len() == points.len() + degree + 1`, non-decreasing knots.
    pub fn try_new(
        degree: usize,
        knots: Vec<f64>,
        points: Vec<Vector3<f64>>,
    ) -> Result<Self, GeometryError> {
        let n = points.len();
        Self::try_new_rational(degree, knots, points, vec![1.0; n])
    }

    /// A rational curve with one positive weight per control point.
    pub fn try_new_rational(
        degree: usize,
        knots: Vec<f64>,
        points: Vec<Vector3<f64>>,
        weights: Vec<f64>,
    ) -> Result<Self, GeometryError> {
        if degree == 0 || points.len() <= degree {
            return Err(GeometryError::TooFewControlPoints {
                degree,
                points: points.len(),
            });
        }
        if knots.len() != points.len() + degree + 1 {
            return Err(GeometryError::KnotCount {
                knots: knots.len(),
                expected: points.len() + degree + 1,
            });
        }
        if let Some(i) = knots
            .windows(2)
            .position(|w| w[1].partial_cmp(&w[0]).is_none_or(|o| o.is_lt()))
        {
            return Err(GeometryError::KnotsNotIncreasing {
                index: i + 1,
                previous: knots[i],
                value: knots[i + 1],
            });
        }
        if weights.len() != points.len() {
            return Err(GeometryError::WeightCount {
                weights: weights.len(),
                points: points.len(),
            });
        }
        if let Some(i) = weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(GeometryError::BadWeight {
                index: i,
                value: weights[i],
            });
        }
        Ok(Self {
            degree,
            knots,
            points,
            weights,
        })
    }

    /// Clamped uniform knot vector on `[0, 1]` for `n` control points of degree `p`:
    /// `p+1` zeros, the interior knots `1/(n-p) … (n-p-1)/(n-p)`, `p+1` ones.
    pub fn clamped_uniform_knots(n: usize, p: usize) -> Vec<f64> {
        let spans = n - p;
        let mut k = vec![0.0; p + 1];
        k.extend((1..spans).map(|i| i as f64 / spans as f64));
        k.extend(std::iter::repeat_n(1.0, p + 1));
        k
    }

    /// A non-rational curve with clamped uniform knots (the S-shape's construction).
    pub fn clamped_uniform(
        degree: usize,
        points: Vec<Vector3<f64>>,
    ) -> Result<Self, GeometryError> {
        let knots = Self::clamped_uniform_knots(points.len(), degree);
        Self::try_new(degree, knots, points)
    }

    pub fn degree(&self) -> usize {
        self.degree
    }
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }
    pub fn control_points(&self) -> &[Vector3<f64>] {
        &self.points
    }
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }
    /// Parameter domain `[knots[p], knots[n]]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.points.len()])
    }

    /// The curve whose control points are `other - self` (same knots and degree, non-rational).
    /// For the S-shape this is `C1 - C0`, exactly vertical where the two share control points.
    pub fn difference(&self, other: &Self) -> Result<Self, GeometryError> {
        if self.knots != other.knots || self.degree != other.degree {
            return Err(GeometryError::IncompatibleCurves);
        }
        let pts = self
            .points
            .iter()
            .zip(&other.points)
            .map(|(a, b)| b - a)
            .collect();
        Self::try_new(self.degree, self.knots.clone(), pts)
    }

    /// Knot span index `i` with `knots[i] <= u < knots[i+1]` (A2.1); `u` is clamped to the domain.
    fn find_span(&self, u: f64) -> usize {
        let n = self.points.len() - 1;
        let p = self.degree;
        if u >= self.knots[n + 1] {
            return n;
        }
        if u <= self.knots[p] {
            return p;
        }
        // binary search on the right-open spans
        let (mut low, mut high) = (p, n + 1);
        let mut mid = (low + high) / 2;
        while u < self.knots[mid] || u >= self.knots[mid + 1] {
            if u < self.knots[mid] {
                high = mid;
            } else {
                low = mid;
            }
            mid = (low + high) / 2;
        }
        mid
    }

    /// Non-zero basis functions `N_{span-p..=span, p}(u)` and their derivatives up to order `nd`
    /// (A2.3). Row `k` holds the `k`-th derivatives.
    pub fn basis_derivs(&self, u: f64, nd: usize) -> (usize, Vec<Vec<f64>>) {
        let p = self.degree;
        let span = self.find_span(u);
        let k = &self.knots;
        let mut ndu = vec![vec![0.0; p + 1]; p + 1];
        let mut left = vec![0.0; p + 1];
        let mut right = vec![0.0; p + 1];
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = u - k[span + 1 - j];
            right[j] = k[span + j] - u;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = ndu[r][j - 1] / ndu[j][r];
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        let nd = nd.min(p);
        let mut ders = vec![vec![0.0; p + 1]; nd + 1];
        for j in 0..=p {
            ders[0][j] = ndu[j][p];
        }
        let mut a = vec![vec![0.0; p + 1]; 2];
        for r in 0..=p {
            let (mut s1, mut s2) = (0usize, 1usize);
            a[0][0] = 1.0;
            for kk in 1..=nd {
                let mut d = 0.0;
                let rk = r as isize - kk as isize;
                let pk = p - kk;
                if r >= kk {
                    a[s2][0] = a[s1][0] / ndu[pk + 1][rk as usize];
                    d = a[s2][0] * ndu[rk as usize][pk];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if (r as isize - 1) <= pk as isize {
                    kk - 1
                } else {
                    p - r
                };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                    d += a[s2][j] * ndu[idx][pk];
                }
                if r <= pk {
                    a[s2][kk] = -a[s1][kk - 1] / ndu[pk + 1][r];
                    d += a[s2][kk] * ndu[r][pk];
                }
                ders[kk][r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut f = p as f64;
        for row in ders.iter_mut().skip(1).enumerate() {
            let (kk, row) = row;
            for v in row.iter_mut() {
                *v *= f;
            }
            f *= (p - kk - 1) as f64;
        }
        (span, ders)
    }

    /// `C(u)` (mm). `u` outside the domain is clamped to it.
    pub fn point_at(&self, u: f64) -> Vector3<f64> {
        self.derivs_at(u).point
    }

    /// `C(u)`, `C'(u)`, `C''(u)`; for rational curves by the quotient rule on the homogeneous form.
    pub fn derivs_at(&self, u: f64) -> CurveDerivs {
        let (lo, hi) = self.domain();
        let u = u.clamp(lo, hi);
        let p = self.degree;
        let (span, ders) = self.basis_derivs(u, 2);
        let mut a = [Vector3::zeros(); 3];
        let mut w = [0.0; 3];
        for (k, row) in ders.iter().enumerate() {
            for (j, nb) in row.iter().enumerate() {
                let idx = span - p + j;
                let wi = self.weights[idx];
                a[k] += self.points[idx] * (nb * wi);
                w[k] += nb * wi;
            }
        }
        // Quotient rule (NURBS Book eq. 4.8): C = A/w, C' = (A' - w'C)/w, C'' = (A'' - 2w'C' - w''C)/w.
        let c0 = a[0] / w[0];
        let c1 = (a[1] - c0 * w[1]) / w[0];
        let c2 = (a[2] - c1 * (2.0 * w[1]) - c0 * w[2]) / w[0];
        CurveDerivs {
            point: c0,
            d1: c1,
            d2: c2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::FD_REL;

    fn s_like() -> BSplineCurve {
        let pts: Vec<_> = (0..16)
            .map(|i| Vector3::new(i as f64 * 10.0, ((i * 7) % 5) as f64 * 3.0 - 4.0, 0.0))
            .collect();
        BSplineCurve::clamped_uniform(3, pts).unwrap()
    }

    #[test]
    fn partition_of_unity_and_derivative_sums() {
        let c = s_like();
        for i in 0..=200 {
            let u = i as f64 / 200.0;
            let (_, d) = c.basis_derivs(u, 2);
            let s0: f64 = d[0].iter().sum();
            let s1: f64 = d[1].iter().sum();
            let s2: f64 = d[2].iter().sum();
            assert_near!(s0, 1.0, 1e-14);
            assert_near!(s1, 0.0, 1e-11);
            assert_near!(s2, 0.0, 1e-9);
        }
    }

    #[test]
    fn clamped_ends_interpolate_first_and_last_control_points() {
        let c = s_like();
        assert_near!((c.point_at(0.0) - c.control_points()[0]).norm(), 0.0, 1e-12);
        assert_near!(
            (c.point_at(1.0) - c.control_points()[15]).norm(),
            0.0,
            1e-12
        );
    }

    #[test]
    fn derivatives_match_central_differences() {
        let mut c = s_like();
        // also a rational version
        let mut cr = c.clone();
        cr.weights = (0..16).map(|i| 1.0 + 0.3 * ((i % 3) as f64)).collect();
        for curve in [&mut c, &mut cr] {
            for i in 1..100 {
                let u = i as f64 / 100.0 + 0.0013;
                let h = 1e-6;
                let d = curve.derivs_at(u);
                let fd1 = (curve.point_at(u + h) - curve.point_at(u - h)) / (2.0 * h);
                let fd2 = (curve.derivs_at(u + h).d1 - curve.derivs_at(u - h).d1) / (2.0 * h);
                assert!((d.d1 - fd1).norm() <= FD_REL * (1.0 + d.d1.norm()), "u={u}");
                assert!((d.d2 - fd2).norm() <= FD_REL * (1.0 + d.d2.norm()), "u={u}");
            }
        }
    }

    #[test]
    fn knot_vector_of_the_s_shape() {
        let k = BSplineCurve::clamped_uniform_knots(16, 3);
        assert_eq!(k.len(), 20);
        assert_near!(k[4], 1.0 / 13.0, 1e-15);
        assert_near!(k[15], 12.0 / 13.0, 1e-15);
    }

    #[test]
    fn rejects_bad_input_with_values() {
        let e = BSplineCurve::try_new(3, vec![0.0; 5], vec![Vector3::zeros(); 4]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "8 knots expected for this degree and control-point count, found 5"
        );
    }
}
