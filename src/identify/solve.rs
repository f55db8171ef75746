//! Least squares on small dense matrices by a column-scaled SVD with a numerical rank: the core
//! shared by the gap diagnosis (baseline and candidate fits, cross-validation folds, equivalence
//! spans) and by identification's residual statistics.
//!
//! `min ‖y − A·x‖²`: the columns of `A` are scaled to unit norm (by `scale`, when given, the
//! norms of the columns *before* any projection, so that a column the baseline absorbs almost
//! entirely counts as rank-deficient rather than as a tiny but "new" direction), then
//! `A·D⁻¹ = U Σ Vᵀ` and `x = D⁻¹ V Σ⁺ Uᵀ y`, with singular values below [`RANK_TOL`] (relative to
//! the unit column scale) dropped. `cov = D⁻¹ V Σ⁻² Vᵀ D⁻¹` is `(AᵀA)⁺`; multiply by `σ²` for the
//! covariance of `x`.
//!
//! Why a fixed `RANK_TOL` here and not the `max(n, p)·ε·s₁` of [`super::ScaledSvd`]: the gap
//! diagnosis projects candidate signatures off the baseline and must treat a direction the
//! baseline absorbs to 1e-7 of its norm as absorbed (not as a new parameter fitted to rounding
//! noise); identification's rank rule decides only exact dependencies and leaves near ones to the
//! condition-index rule.
//!
//! Residual figures: [`rms`] and [`max_abs`] (mm for deviations), the `rms`/`max_abs` of
//! [`super::ResidualStats`] as well.

use nalgebra::{DMatrix, DVector};

/// Singular values (of the unit-column-scaled matrix) below this count as zero.
pub const RANK_TOL: f64 = 1e-7;

/// A factorised design: orthonormal basis of its column space and its pseudo-inverse.
#[derive(Debug, Clone)]
pub struct Factor {
    /// `n × r` orthonormal basis of the column space (`r` = numerical rank).
    pub basis: DMatrix<f64>,
    /// `p × n` pseudo-inverse: `x = pinv·y`.
    pub pinv: DMatrix<f64>,
    /// `p × p` unscaled covariance `(AᵀA)⁺`.
    pub cov: DMatrix<f64>,
    /// Numerical rank.
    pub rank: usize,
    /// Condition number of the retained part of the unit-scaled matrix.
    pub condition: f64,
}

impl Factor {
    /// Factorises `a`; `scale[j]` (if given) is the norm column `j` is measured against.
    pub fn new(a: &DMatrix<f64>, scale: Option<&[f64]>) -> Self {
        let (n, p) = a.shape();
        if p == 0 || n == 0 {
            return Self {
                basis: DMatrix::zeros(n, 0),
                pinv: DMatrix::zeros(p, n),
                cov: DMatrix::zeros(p, p),
                rank: 0,
                condition: 1.0,
            };
        }
        let d: Vec<f64> = (0..p)
            .map(|j| {
                let s = scale.map_or_else(|| a.column(j).norm(), |s| s[j]);
                if s > 0.0 && s.is_finite() {
                    s
                } else {
                    1.0
                }
            })
            .collect();
        let mut scaled = a.clone();
        for (j, dj) in d.iter().enumerate() {
            scaled.column_mut(j).scale_mut(1.0 / dj);
        }
        let svd = scaled.svd(true, true);
        // nalgebra always returns U and Vᵀ when asked for them.
        let (Some(u), Some(vt)) = (svd.u, svd.v_t) else {
            unreachable!("SVD computed with U and V")
        };
        let sv = svd.singular_values;
        let keep: Vec<usize> = (0..sv.len()).filter(|&k| sv[k] > RANK_TOL).collect();
        let rank = keep.len();
        let smax = keep.iter().map(|&k| sv[k]).fold(0.0, f64::max);
        let smin = keep.iter().map(|&k| sv[k]).fold(f64::INFINITY, f64::min);
        let basis = u.select_columns(&keep);
        // V Σ⁻¹ (p × r), then unscale rows by D⁻¹.
        let mut vsi = DMatrix::zeros(p, rank);
        for (c, &k) in keep.iter().enumerate() {
            for j in 0..p {
                vsi[(j, c)] = vt[(k, j)] / sv[k] / d[j];
            }
        }
        let pinv = &vsi * basis.transpose();
        let cov = &vsi * vsi.transpose();
        Self {
            basis,
            pinv,
            cov,
            rank,
            condition: if rank > 0 { smax / smin } else { 1.0 },
        }
    }

    /// `x - Q Qᵀ x`: the part of each column of `x` outside the column space.
    pub fn unabsorbed(&self, x: &DMatrix<f64>) -> DMatrix<f64> {
        x - &self.basis * (self.basis.transpose() * x)
    }

    /// Same for one vector.
    pub fn unabsorbed_vec(&self, x: &DVector<f64>) -> DVector<f64> {
        x - &self.basis * (self.basis.transpose() * x)
    }
}

/// `[a | b]`: the columns of `a`, then those of `b` (same number of rows).
pub fn hstack(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), a.ncols() + b.ncols(), |i, j| {
        if j < a.ncols() {
            a[(i, j)]
        } else {
            b[(i, j - a.ncols())]
        }
    })
}

/// Root mean square of a slice (0 for an empty one).
pub fn rms(x: &[f64]) -> f64 {
    if x.is_empty() {
        0.0
    } else {
        (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
    }
}

/// Largest absolute value (0 for an empty slice).
pub fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_fit_and_rank_deficiency() {
        // y = 2·c0 − 3·c1 exactly; c2 = c0 + c1 makes the matrix rank 2.
        let a = DMatrix::from_row_slice(
            5,
            3,
            &[
                1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 2.0, 3.0, 1.0, 3.0, 4.0, 1.0, 4.0, 5.0,
            ],
        );
        let y = DVector::from_fn(5, |i, _| 2.0 - 3.0 * i as f64);
        let f = Factor::new(&a, None);
        assert_eq!(f.rank, 2);
        let x = &f.pinv * &y;
        let r = &y - &a * &x;
        assert!(r.norm() < 1e-10, "residual {}", r.norm());
        assert!(f.unabsorbed_vec(&y).norm() < 1e-10);
    }

    #[test]
    fn residual_stats_use_the_same_rms_and_max() {
        // ResidualStats (paper 001 eq. 17) and the diagnosis read the same figures, bit for bit.
        let measured = [0.003, -0.0125, 0.007, 0.0, -0.001];
        let fitted = [0.001, -0.01, 0.009, 0.0005, 0.0];
        let r: Vec<f64> = measured.iter().zip(&fitted).map(|(m, f)| m - f).collect();
        let st = crate::identify::ResidualStats::of(&measured, &fitted, 0.003);
        assert_eq!(st.rms, rms(&r));
        assert_eq!(st.max_abs, max_abs(&r));
        // Closed form: r = (2, −2.5, −2, −0.5, −1) µm, Σr² = 15.5e-6 mm².
        crate::assert_near!(st.rms, (15.5e-6f64 / 5.0).sqrt(), 1e-15);
        crate::assert_near!(st.max_abs, 0.0025, 1e-15);
    }
}
