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
        let nd = nd.min(p);
        if p <= MAX_STACK_DEGREE && nd <= 2 {
            let (span, d) = self.basis_derivs2(u);
            return (span, (0..=nd).map(|k| d[k][..=p].to_vec()).collect());
        }
        let span = self.find_span(u);
        let w = p + 1;
        let mut ndu = vec![0.0; w * w];
        let mut ders = vec![0.0; w * (nd + 1)];
        let mut work = vec![0.0; 4 * w];
        ders_basis_funs(
            &self.knots,
            span,
            p,
            u,
            nd,
            w,
            &mut ndu,
            &mut ders,
            &mut work,
        );
        (span, ders.chunks(w).map(<[f64]>::to_vec).collect())
    }

    /// The basis functions and their first two derivatives without heap allocation, for degrees
    /// up to [`MAX_STACK_DEGREE`] (the same arithmetic as [`Self::basis_derivs`]): row `k` holds
    /// the `k`-th derivatives of `N_{span-p+j}`, `j = 0..=p`; entries past `p` and rows past the
    /// degree are 0. The hot path of every curve and surface evaluation.
    ///
    /// # Panics
    /// When the degree exceeds [`MAX_STACK_DEGREE`] (callers check [`Self::degree`]).
    #[inline]
    pub fn basis_derivs2(&self, u: f64) -> (usize, [[f64; STACK_WIDTH]; 3]) {
        self.basis_stack(u, 2)
    }

    /// [`Self::basis_derivs2`] without the second derivatives (row 2 stays 0): the same
    /// arithmetic for rows 0 and 1, for callers that need no curvature (the tool pose).
    #[inline]
    pub fn basis_derivs1(&self, u: f64) -> (usize, [[f64; STACK_WIDTH]; 3]) {
        self.basis_stack(u, 1)
    }

    /// [`Self::basis_derivs2`] up to derivative order `nd <= 2` (higher rows stay 0).
    #[inline(always)]
    fn basis_stack(&self, u: f64, nd: usize) -> (usize, [[f64; STACK_WIDTH]; 3]) {
        let p = self.degree;
        assert!(p <= MAX_STACK_DEGREE, "degree {p} > {MAX_STACK_DEGREE}");
        let span = self.find_span(u);
        let nd = nd.min(2).min(p);
        const W: usize = STACK_WIDTH;
        // A literal degree lets the compiler unroll the cubic (the S-shape) and its hodograph.
        let d = match p {
            3 => ders_fixed::<W>(&self.knots, span, 3, u, nd),
            2 => ders_fixed::<W>(&self.knots, span, 2, u, nd),
            _ => ders_fixed::<W>(&self.knots, span, p, u, nd),
        };
        (span, d)
    }

    /// `C(u)` (mm). `u` outside the domain is clamped to it.
    pub fn point_at(&self, u: f64) -> Vector3<f64> {
        let p = self.degree;
        if p > MAX_STACK_DEGREE {
            return self.derivs_at(u).point;
        }
        // The value row of `derivs_at` alone (same arithmetic, no derivative rows).
        let (lo, hi) = self.domain();
        let (span, ders) = self.basis_stack(u.clamp(lo, hi), 0);
        let mut a = Vector3::zeros();
        let mut w = 0.0;
        for (j, nb) in ders[0][..=p].iter().enumerate() {
            let idx = span - p + j;
            let wi = self.weights[idx];
            a += self.points[idx] * (nb * wi);
            w += nb * wi;
        }
        a / w
    }

    /// The hodograph `C'(u)` as a B-spline of degree `p - 1` on the inner knots (NURBS Book
    /// eq. 3.8: `Q_i = p (P_{i+1} - P_i) / (u_{i+p+1} - u_{i+1})`), for a non-rational curve of
    /// degree >= 2; `None` otherwise. Its values equal `derivs_at(u).d1` to rounding.
    pub fn hodograph(&self) -> Option<Self> {
        let p = self.degree;
        if p < 2 || self.weights.iter().any(|w| *w != 1.0) {
            return None;
        }
        let k = &self.knots;
        let q = self
            .points
            .windows(2)
            .enumerate()
            .map(|(i, w)| {
                let dk = k[i + p + 1] - k[i + 1];
                if dk > 0.0 {
                    (w[1] - w[0]) * (p as f64 / dk)
                } else {
                    Vector3::zeros()
                }
            })
            .collect();
        Self::try_new(p - 1, k[1..k.len() - 1].to_vec(), q).ok()
    }

    /// `C(u)`, `C'(u)`, `C''(u)`; for rational curves by the quotient rule on the homogeneous form.
    pub fn derivs_at(&self, u: f64) -> CurveDerivs {
        let (lo, hi) = self.domain();
        let u = u.clamp(lo, hi);
        let p = self.degree;
        let mut a = [Vector3::zeros(); 3];
        let mut w = [0.0; 3];
        let mut add = |span: usize, k: usize, row: &[f64]| {
            for (j, nb) in row.iter().enumerate() {
                let idx = span - p + j;
                let wi = self.weights[idx];
                a[k] += self.points[idx] * (nb * wi);
                w[k] += nb * wi;
            }
        };
        if p <= MAX_STACK_DEGREE {
            let (span, ders) = self.basis_derivs2(u);
            for (k, row) in ders.iter().enumerate().take(3) {
                add(span, k, &row[..=p]);
            }
        } else {
            let (span, ders) = self.basis_derivs(u, 2);
            for (k, row) in ders.iter().enumerate() {
                add(span, k, row);
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

/// Highest degree evaluated on the stack ([`BSplineCurve::basis_derivs2`]).
pub const MAX_STACK_DEGREE: usize = 7;
/// Row width of [`BSplineCurve::basis_derivs2`].
pub const STACK_WIDTH: usize = MAX_STACK_DEGREE + 1;

/// Piegl & Tiller A2.3 on flat row-major buffers of row width `w >= p + 1`: `ndu` (`w × w`),
/// `ders` (`(nd + 1) × w`, output) and `work` (`4w`: `left`, `right`, and the two rows of `a`).
#[allow(clippy::too_many_arguments)]
#[inline]
fn ders_basis_funs(
    k: &[f64],
    span: usize,
    p: usize,
    u: f64,
    nd: usize,
    w: usize,
    ndu: &mut [f64],
    ders: &mut [f64],
    work: &mut [f64],
) {
    let (left, rest) = work.split_at_mut(w);
    let (right, a) = rest.split_at_mut(w);
    ndu[0] = 1.0;
    for j in 1..=p {
        left[j] = u - k[span + 1 - j];
        right[j] = k[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j * w + r] = right[r + 1] + left[j - r];
            let temp = ndu[r * w + j - 1] / ndu[j * w + r];
            ndu[r * w + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * w + j] = saved;
    }
    for j in 0..=p {
        ders[j] = ndu[j * w + p];
    }
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, w);
        a[0] = 1.0;
        for kk in 1..=nd {
            let mut d = 0.0;
            let rk = r as isize - kk as isize;
            let pk = p - kk;
            if r >= kk {
                a[s2] = a[s1] / ndu[(pk + 1) * w + rk as usize];
                d = a[s2] * ndu[rk as usize * w + pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if (r as isize - 1) <= pk as isize {
                kk - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2 + j] = (a[s1 + j] - a[s1 + j - 1]) / ndu[(pk + 1) * w + idx];
                d += a[s2 + j] * ndu[idx * w + pk];
            }
            if r <= pk {
                a[s2 + kk] = -a[s1 + kk - 1] / ndu[(pk + 1) * w + r];
                d += a[s2 + kk] * ndu[r * w + pk];
            }
            ders[kk * w + r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut f = p as f64;
    for kk in 1..=nd {
        for v in ders[kk * w..kk * w + p + 1].iter_mut() {
            *v *= f;
        }
        f *= (p - kk) as f64;
    }
}

/// The basis functions of degree `p` at `u` in `span` and their first `nd <= 2` derivatives, on
/// fixed arrays of width `W > p` (rows: value, first, second derivative; entries past `p` are 0).
///
/// Values by the triangular Cox–de Boor scheme (A2.2), keeping the lower-degree values
/// `N_{span-d+m, d}`; derivatives from them by `N'_{i,d} = d·(N_{i,d-1}/(u_{i+d} - u_i) -
/// N_{i+1,d-1}/(u_{i+d+1} - u_{i+1}))` (NURBS Book eq. 2.7), applied twice for the second
/// derivative. Every denominator used is the length of a support that contains the span, so it
/// is positive. Equal to A2.3 ([`ders_basis_funs`]) to rounding.
#[inline(always)]
fn ders_fixed<const W: usize>(
    k: &[f64],
    span: usize,
    p: usize,
    u: f64,
    nd: usize,
) -> [[f64; W]; 3] {
    assert!(p < W && nd <= 2 && span + p < k.len() && span >= p);
    // vals[d][m] = N_{span-d+m, d}(u)
    let mut vals = [[0.0; W]; W];
    let mut left = [0.0; W];
    let mut right = [0.0; W];
    vals[0][0] = 1.0;
    for d in 1..=p {
        left[d] = u - k[span + 1 - d];
        right[d] = k[span + d] - u;
        let mut saved = 0.0;
        for r in 0..d {
            let temp = vals[d - 1][r] / (right[r + 1] + left[d - r]);
            vals[d][r] = saved + right[r + 1] * temp;
            saved = left[d - r] * temp;
        }
        vals[d][d] = saved;
    }
    // d·(lower[m-1]/(u_{i+d} - u_i) - lower[m]/(u_{i+d+1} - u_{i+1})), i = span-d+m, from the
    // row `lower` of degree d-1 (m-1 and m outside 0..d-1 are zero functions).
    let deriv = |lower: &[f64; W], d: usize| {
        let mut out = [0.0; W];
        let df = d as f64;
        for (m, o) in out.iter_mut().enumerate().take(d + 1) {
            let i = span + m - d;
            let mut v = 0.0;
            if m >= 1 {
                v += lower[m - 1] / (k[i + d] - k[i]);
            }
            if m < d {
                v -= lower[m] / (k[i + d + 1] - k[i + 1]);
            }
            *o = df * v;
        }
        out
    };
    let mut ders = [[0.0; W]; 3];
    ders[0] = vals[p];
    if nd >= 1 {
        ders[1] = deriv(&vals[p - 1], p);
    }
    if nd >= 2 && p >= 2 {
        ders[2] = deriv(&deriv(&vals[p - 2], p - 1), p);
    }
    ders
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
    fn stack_basis_and_hodograph_match_the_general_evaluation() {
        let c = s_like();
        let h = c.hodograph().unwrap();
        assert_eq!(h.degree(), 2);
        for i in 0..=300 {
            let u = i as f64 / 300.0;
            let d = c.derivs_at(u);
            // the first derivative as a B-spline of its own (NURBS Book eq. 3.8)
            assert!(
                (h.point_at(u) - d.d1).norm() <= 1e-12 * (1.0 + d.d1.norm()),
                "u={u}"
            );
            assert_eq!(c.point_at(u), d.point);
            // the Vec form is the stack form
            let (span, v) = c.basis_derivs(u, 2);
            let (span2, a) = c.basis_derivs2(u);
            assert_eq!(span, span2);
            for k in 0..3 {
                assert_eq!(v[k][..], a[k][..4]);
            }
            // the stack form is Piegl & Tiller's A2.3 to rounding
            let mut ndu = [0.0; 16];
            let mut ders = [0.0; 12];
            let mut work = [0.0; 16];
            ders_basis_funs(c.knots(), span, 3, u, 2, 4, &mut ndu, &mut ders, &mut work);
            for k in 0..3 {
                for j in 0..4 {
                    let scale = [1.0, 13.0, 169.0][k];
                    assert_near!(a[k][j], ders[k * 4 + j], 1e-13 * scale);
                }
            }
        }
        // a degree above the stack limit takes the heap path and still sums to 1
        let pts: Vec<_> = (0..12).map(|i| Vector3::new(i as f64, 0.0, 0.0)).collect();
        let high = BSplineCurve::clamped_uniform(9, pts).unwrap();
        let (_, d) = high.basis_derivs(0.37, 2);
        assert_near!(d[0].iter().sum::<f64>(), 1.0, 1e-14);
        assert_near!(high.derivs_at(0.37).d1.y, 0.0, 1e-15);
        assert!(BSplineCurve::clamped_uniform(1, vec![Vector3::zeros(); 3])
            .unwrap()
            .hodograph()
            .is_none());
    }

    #[test]
    fn stack_basis_equals_a2_3_for_every_stack_degree() {
        // non-uniform knots with an interior double knot
        for p in 1..=MAX_STACK_DEGREE {
            let n = p + 6;
            let mut knots = vec![0.0; p + 1];
            knots.extend([0.1, 0.25, 0.25, 0.6, 0.7]);
            knots.extend((0..n - p - 6).map(|i| 0.8 + 0.01 * i as f64));
            knots.extend(vec![1.0; p + 1]);
            let pts: Vec<_> = (0..n).map(|i| Vector3::new(i as f64, 0.0, 0.0)).collect();
            let c = BSplineCurve::try_new(p, knots, pts).unwrap();
            for i in 0..=97 {
                let u = i as f64 / 97.0;
                let (span, a) = c.basis_derivs2(u);
                let w = p + 1;
                let (mut ndu, mut ders, mut work) =
                    (vec![0.0; w * w], vec![0.0; 3 * w], vec![0.0; 4 * w]);
                let nd = 2.min(p);
                ders_basis_funs(c.knots(), span, p, u, nd, w, &mut ndu, &mut ders, &mut work);
                for k in 0..=nd {
                    for j in 0..w {
                        let r = ders[k * w + j];
                        assert!(
                            (a[k][j] - r).abs() <= 1e-12 * (1.0 + r.abs()),
                            "p={p} u={u} k={k} j={j}: {} vs {r}",
                            a[k][j]
                        );
                    }
                }
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
