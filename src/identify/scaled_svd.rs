//! SVD of the column-scaled weighted design, numerical rank and condition indices.
//!
//! `B = W^½ A D⁻¹` with `D = diag(‖W^½ a_j‖)`: every column of `B` has unit length, so the
//! singular values do not depend on the units of the parameters (mm vs rad) and the condition
//! number `s₁/s_p` is the "unit-scaled" one quoted in s-shape.md (paper mode 323, physical 8.4).
//! An all-zero column keeps the scale 1 and shows up as a zero singular value.
//!
//! **Numerical rank**: `s_k > τ` with `τ = max(n, p)·ε·s₁` (ε = 2.2e-16), the threshold of
//! LAPACK's and MATLAB's `rank`: below it a singular value is indistinguishable from the rounding
//! error of the SVD itself, so its direction is a true null direction of the data. Such singular
//! values are reported as exact zeros, and the null space by [`canonical_basis`]: the SVD's own
//! basis of a degenerate subspace is decided by rounding and differs between the native and the
//! wasm build (its vectors, their signs, the noise values), the canonical one does not.
//!
//! **Condition indices** `η_k = s₁/s_k` (Belsley, Kuh & Welsch 1980, *Regression Diagnostics*,
//! ch. 3): on unit-length columns, `η ≥ 30` marks a moderate-to-strong near-dependency among the
//! columns, whose parameters the least squares can only separate by amplifying the noise by `η`
//! relative to the best-determined direction. Such directions are not separated: see
//! [`crate::identify`].

use crate::numerics::order::argsort_descending;
use nalgebra::DMatrix;

/// The SVD of the scaled design, singular values sorted in decreasing order.
#[derive(Debug, Clone)]
pub struct ScaledSvd {
    /// Column scale `D_j = ‖W^½ a_j‖` (1 for an all-zero column).
    pub scale: Vec<f64>,
    /// Indices of all-zero columns.
    pub zero_columns: Vec<usize>,
    /// Singular values `s_1 >= ... >= s_p` (p of them; zeros when there are fewer rows than columns).
    pub singular: Vec<f64>,
    /// Left singular vectors (rows x p), column k for `s_k`.
    pub u: DMatrix<f64>,
    /// Right singular vectors (p x p), column k for `s_k`, in the scaled space.
    pub v: DMatrix<f64>,
    /// Rank threshold `τ` (absolute, on the scaled matrix).
    pub rank_tolerance: f64,
    /// Number of singular values above `τ`.
    pub rank: usize,
}

impl ScaledSvd {
    /// SVD of `b` (= `W^½ A`, rows already weighted) after scaling its columns to unit length.
    /// Never fails: an empty or all-zero matrix has rank 0.
    pub fn new(b: &DMatrix<f64>) -> Self {
        let (n, p) = (b.nrows(), b.ncols());
        let mut scale = vec![1.0; p];
        let mut zero_columns = Vec::new();
        let mut m = b.clone();
        for (j, sj) in scale.iter_mut().enumerate() {
            let c = m.column(j).norm();
            if c > 0.0 && c.is_finite() {
                *sj = c;
                m.column_mut(j).scale_mut(1.0 / c);
            } else {
                zero_columns.push(j);
            }
        }
        // Fewer rows than columns: pad with zero rows so that the SVD gives all p right vectors.
        let rows = n.max(p);
        let mut padded = DMatrix::zeros(rows, p);
        padded.view_mut((0, 0), (n, p)).copy_from(&m);
        let svd = nalgebra::SVD::new(padded, true, true);
        let s = svd.singular_values;
        let u0 = svd.u.unwrap_or_else(|| DMatrix::zeros(rows, p));
        let vt = svd.v_t.unwrap_or_else(|| DMatrix::identity(p, p));
        let order = argsort_descending(s.as_slice());
        let singular: Vec<f64> = order.iter().map(|&k| s[k]).collect();
        let mut u = DMatrix::zeros(n, p);
        let mut v = DMatrix::zeros(p, p);
        for (k, &o) in order.iter().enumerate() {
            u.column_mut(k).copy_from(&u0.column(o).rows(0, n));
            v.column_mut(k).copy_from(&vt.row(o).transpose());
        }
        let s1 = singular.first().copied().unwrap_or(0.0);
        let rank_tolerance = (n.max(p) as f64) * f64::EPSILON * s1;
        let rank = singular.iter().filter(|&&x| x > rank_tolerance).count();
        // Below the threshold: rounding noise, reported as exact zeros, and the null space
        // given by its canonical basis rather than the one the SVD happened to return.
        let mut singular = singular;
        for s in singular.iter_mut().skip(rank) {
            *s = 0.0;
        }
        if rank < p {
            let null = canonical_basis(&v.columns(rank, p - rank).into_owned());
            v.columns_mut(rank, p - rank).copy_from(&null);
        }
        ScaledSvd {
            scale,
            zero_columns,
            singular,
            u,
            v,
            rank_tolerance,
            rank,
        }
    }

    /// Condition number `s₁/s_p` of the scaled matrix (infinite when rank-deficient).
    pub fn condition(&self) -> f64 {
        condition_of(&self.singular)
    }

    /// Condition index `η_k = s₁/s_k` (infinite for a zero singular value).
    pub fn condition_index(&self, k: usize) -> f64 {
        let s1 = self.singular.first().copied().unwrap_or(0.0);
        if self.singular[k] > 0.0 {
            s1 / self.singular[k]
        } else {
            f64::INFINITY
        }
    }
}

/// A canonical orthonormal basis of the span of the orthonormal columns of `v0` (p x t): the
/// same whatever basis of that subspace `v0` holds.
///
/// The rows `c_j` of `v0` change by a rotation when the basis changes, so their norms and inner
/// products do not: pivots are chosen by pivoted Gram–Schmidt on them (the parameter with the
/// largest remaining `‖c_j‖²`, ties within 1e-9 relative going to the lower index), then
/// `N = v0 · v0[pivots]⁻¹` has the identity on the pivot rows (the reduced echelon form of the
/// subspace, unique for given pivots) and is orthonormalised in pivot order (each column keeps
/// `+1` on its pivot row, so the signs are fixed too).
pub fn canonical_basis(v0: &DMatrix<f64>) -> DMatrix<f64> {
    let (p, t) = v0.shape();
    if t == 0 {
        return v0.clone();
    }
    let mut res: Vec<Vec<f64>> = (0..p)
        .map(|j| v0.row(j).iter().copied().collect())
        .collect();
    let mut pivots: Vec<usize> = Vec::with_capacity(t);
    for _ in 0..t {
        let norm2 = |j: usize| res[j].iter().map(|x| x * x).sum::<f64>();
        let best = (0..p)
            .filter(|j| !pivots.contains(j))
            .map(norm2)
            .fold(0.0, f64::max);
        if best <= 0.0 {
            break;
        }
        let Some(j) = (0..p).find(|&j| !pivots.contains(&j) && norm2(j) >= best * (1.0 - 1e-9))
        else {
            break;
        };
        let q: Vec<f64> = res[j].iter().map(|x| x / best.sqrt()).collect();
        for r in res.iter_mut() {
            let d: f64 = r.iter().zip(&q).map(|(a, b)| a * b).sum();
            for (a, b) in r.iter_mut().zip(&q) {
                *a -= d * b;
            }
        }
        pivots.push(j);
    }
    if pivots.len() < t {
        return v0.clone();
    }
    let vp = v0.select_rows(&pivots);
    let Some(inv) = vp.try_inverse() else {
        return v0.clone();
    };
    let mut n = v0 * inv;
    for c in 0..t {
        for k in 0..c {
            let d = n.column(c).dot(&n.column(k));
            let ck = n.column(k).into_owned();
            n.column_mut(c).axpy(-d, &ck, 1.0);
        }
        let norm = n.column(c).norm();
        if norm > 0.0 {
            n.column_mut(c).scale_mut(1.0 / norm);
        }
    }
    n
}

/// `max/min` of singular values, infinite if the smallest is 0 or the list is empty.
pub fn condition_of(s: &[f64]) -> f64 {
    let max = s.iter().copied().fold(0.0, f64::max);
    let min = s.iter().copied().fold(f64::INFINITY, f64::min);
    if min > 0.0 && min.is_finite() {
        max / min
    } else {
        f64::INFINITY
    }
}
