//! The std of every number a compensation writes, propagated from the entered errors.
//!
//! A written number `y = f(x)` (an axis direction component, an offset vector component, a
//! controller parameter) is a smooth function of the entered location errors `x`. To first
//! order `Δy = J Δx` with `J = ∂f/∂x` at the identified values, so (GUM, JCGM 100:2008 §5.2,
//! eq. 13) `Σ_y = J Σ_x Jᵀ` and `std(y_i) = √(Σ_y)_ii`. `J` is taken by central differences of
//! the exact map, step `h_j = 1e-4 ·` the error's typical size (its truncation error is
//! `O(h²)·f'''`, below 1e-12 of the value here); the tests check it against the closed-form
//! first-order derivatives of paper 000's chain.
//!
//! `Σ_x` is the final fit's covariance of the entered errors with each variance widened to the
//! final answer's std (which includes the model spread) and the fit's correlations kept:
//! `Σ_x,jk = ρ_jk s_j s_k`. Where the fit has no covariance the errors are taken as
//! uncorrelated (diagonal `s_j²`), and the compensation says so.

use nalgebra::DMatrix;

/// The covariance of the errors `rows` (indices into the fit's parameters) with stds `std`,
/// from the fit's `covariance` (module docs); `None` when the fit has none (diagonal then).
pub fn entered_covariance(covariance: &[Vec<f64>], rows: &[usize], std: &[f64]) -> DMatrix<f64> {
    let n = rows.len();
    DMatrix::from_fn(n, n, |a, b| {
        if a == b {
            return std[a] * std[a];
        }
        let c = |i: usize, j: usize| covariance.get(i).and_then(|r| r.get(j)).copied();
        let (i, j) = (rows[a], rows[b]);
        match (c(i, j), c(i, i), c(j, j)) {
            (Some(cij), Some(cii), Some(cjj)) if cii > 0.0 && cjj > 0.0 => {
                (cij / (cii * cjj).sqrt()).clamp(-1.0, 1.0) * std[a] * std[b]
            }
            _ => 0.0,
        }
    })
}

/// Whether the fit's covariance covers every pair of `rows`.
pub fn has_covariance(covariance: &[Vec<f64>], rows: &[usize]) -> bool {
    rows.iter().all(|&i| {
        rows.iter()
            .all(|&j| covariance.get(i).and_then(|r| r.get(j)).is_some())
    })
}

/// `J = ∂f/∂x` at `x` by central differences with steps `h` (module docs): `J[(i, j)]`.
pub fn jacobian(f: &dyn Fn(&[f64]) -> Vec<f64>, x: &[f64], h: &[f64]) -> DMatrix<f64> {
    let m = f(x).len();
    let mut j = DMatrix::zeros(m, x.len());
    for k in 0..x.len() {
        let mut xp = x.to_vec();
        let mut xm = x.to_vec();
        xp[k] += h[k];
        xm[k] -= h[k];
        let (fp, fm) = (f(&xp), f(&xm));
        for i in 0..m {
            j[(i, k)] = (fp[i] - fm[i]) / (2.0 * h[k]);
        }
    }
    j
}

/// `std(y_i) = √(J Σ Jᵀ)_ii`.
pub fn propagated_std(j: &DMatrix<f64>, cov: &DMatrix<f64>) -> Vec<f64> {
    let s = j * cov * j.transpose();
    (0..s.nrows()).map(|i| s[(i, i)].max(0.0).sqrt()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// `f(x) = (x0 x1, sin x0)` at (2, 3): J = [[3, 2], [cos 2, 0]] (closed form, 1e-9 with
    /// h = 1e-4: the truncation error of x0 x1 is 0, of sin is h²/6 ≈ 2e-9·cos).
    #[test]
    fn central_differences_match_the_closed_form() {
        let f = |x: &[f64]| vec![x[0] * x[1], x[0].sin()];
        let j = jacobian(&f, &[2.0, 3.0], &[1e-4, 1e-4]);
        assert_near!(j[(0, 0)], 3.0, 1e-9);
        assert_near!(j[(0, 1)], 2.0, 1e-9);
        assert_near!(j[(1, 0)], 2f64.cos(), 1e-9);
        assert_near!(j[(1, 1)], 0.0, 1e-12);
    }

    /// y = x0 + x1 with std (1, 2) and correlation 0.5 (fit covariance [[4, 4], [4, 16]] widened
    /// to stds 1, 2): var = 1 + 4 + 2·0.5·1·2 = 7 (closed form).
    #[test]
    fn correlations_are_kept_and_stds_widened() {
        let cov = vec![vec![4.0, 4.0], vec![4.0, 16.0]];
        let c = entered_covariance(&cov, &[0, 1], &[1.0, 2.0]);
        let j = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        assert_near!(propagated_std(&j, &c)[0], 7f64.sqrt(), 1e-12);
        assert!(has_covariance(&cov, &[0, 1]) && !has_covariance(&[], &[0]));
    }
}
