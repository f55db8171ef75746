//! The pooled families of [`crate::effects::nuisance`] (the linear axes' error motions) as one
//! random effect beside the location errors: a model of the model spread
//! ([`crate::final_fit::model_spread`]) whose amplitude the part itself says.
//!
//! The model is `y = Aβ + Uγ + e`, `e ~ N(0, σ²I)`, `γ ~ N(0, τ²I)`, `U` the families' columns
//! (each family orthonormalised and scaled to unit RMS over the points, so that `τ` is the RMS of
//! one direction of a family). `τ²` is estimated by maximum likelihood on the residual of the
//! location errors, where `A` is gone (restricted likelihood, Patterson and Thompson 1971): with
//! `B = P⊥U` (`P⊥` the projector off `A`), `BᵀB = V diag(s²) Vᵀ` and `z_k = v_kᵀBᵀr / s_k`
//! (`r = P⊥y`), the `z_k` are independent `N(0, σ² + τ² s_k²)`, and
//!
//! `−2 ln L(τ²) + 2 ln L(0) = Σ_k [ln(1 + τ² s_k²/σ²) + z_k²/(σ² + τ² s_k²) − z_k²/σ²]`,
//!
//! minimised over `ln τ²` by golden section (the envelope's `golden_min`). A minimum at or above
//! 0 means no error motion the data can see: no model. Otherwise the model's estimate and
//! covariance are those of generalised least squares, in closed form (Henderson's mixed-model
//! equations; the block inverse of
//! `[A U]ᵀ[A U] + diag(0, λI)`, `λ = σ²/τ²`):
//!
//! `β̂ = β̂_OLS − H (BᵀB + λI)⁻¹ Bᵀr`, `Cov β̂ = σ²(AᵀA)⁻¹ + σ² H (BᵀB + λI)⁻¹ Hᵀ`,
//! `H = (AᵀA)⁻¹AᵀU`,
//!
//! and its BIC-like score against the model of `A` alone is the likelihood's gain plus `ln n`
//! for `τ`. `A` is the location errors' columns, or theirs with a named effect's.
//! The second term of the covariance is what an error motion of the size the part shows could
//! move the location errors by, seen or not: the spread adds it, weighted.

use nalgebra::{DMatrix, DVector};

use crate::effects::nuisance::Nuisance;
use crate::identify::solve::{tr_mul, Factor};
use crate::toolpath::envelope::golden_min;

/// The pooled random effect's fit.
#[derive(Debug, Clone)]
pub struct PooledFit {
    /// Its estimate of the location errors.
    pub beta: DVector<f64>,
    /// `σ² H (BᵀB + λI)⁻¹ Hᵀ`: its covariance beyond that of the columns in `fa` (units² of the
    /// parameters).
    pub extra: DMatrix<f64>,
    /// `−2 ln` of its likelihood over that of the columns in `fa`, plus `ln n` for `τ`
    /// (negative: better).
    pub score: f64,
    /// `τ` (mm).
    pub tau: f64,
}

/// The bracket of the golden-section search over `ln τ²` in `[ln 1e-6 σ², ln 1e2 σ²]` at its
/// end (about what 60 steps leave of the 18.4 it starts from).
const LN_TAU2_TOL: f64 = 1e-11;

/// The pooled random effect of the `families` (their rows `used`) beside the columns factorised
/// in `fa` (on those rows: the location errors', or theirs with a named effect's, whose
/// coefficients follow theirs in `beta` and `extra`), for the deviations `yu` on those rows,
/// with the noise `sigma` (mm); `None` when the likelihood does not rise with `τ` or there is
/// nothing to pool.
pub fn pooled_fit(
    fa: &Factor,
    yu: &DVector<f64>,
    families: &[&Nuisance],
    used: &[usize],
    sigma: f64,
) -> Option<PooledFit> {
    let n = yu.len();
    let cols: Vec<DVector<f64>> = families
        .iter()
        .flat_map(|f| {
            let q = Factor::of(f.columns.select_rows(used), None).basis;
            q.column_iter()
                .map(|c| c.into_owned() * (n as f64).sqrt())
                .collect::<Vec<_>>()
        })
        .collect();
    if cols.is_empty() || n <= fa.cov.nrows() {
        return None;
    }
    let u = DMatrix::from_columns(&cols);
    let b = fa.unabsorbed(&u);
    let r = fa.unabsorbed_vec(yu);
    let eig = nalgebra::SymmetricEigen::new(tr_mul(&b, &b));
    let btr = b.tr_mul(&r);
    let sg2 = sigma * sigma;
    // the directions B sees, with z_k = v_kᵀBᵀr / s_k
    let seen: Vec<(f64, f64)> = (0..eig.eigenvalues.len())
        .filter(|&k| eig.eigenvalues[k] > 1e-12 * n as f64)
        .map(|k| {
            let s2 = eig.eigenvalues[k];
            (s2, eig.eigenvectors.column(k).dot(&btr) / s2.sqrt())
        })
        .collect();
    let gain = |t: f64| -> f64 {
        seen.iter()
            .map(|&(s2, z)| {
                let v = sg2 + t * s2;
                libm::log(v / sg2) + z * z / v - z * z / sg2
            })
            .sum()
    };
    let (lt, best) = golden_min(
        &|lt: f64| gain(libm::exp(lt)),
        libm::log(1e-6 * sg2),
        libm::log(1e2 * sg2),
        LN_TAU2_TOL,
    );
    let t = libm::exp(lt);
    if best.is_nan() || best >= 0.0 {
        return None;
    }
    // H = (AᵀA)⁻¹AᵀU, column by column; (BᵀB + λI)⁻¹ by its eigen-decomposition
    let h = DMatrix::from_columns(
        &u.column_iter()
            .map(|c| fa.solve(&c.into_owned()))
            .collect::<Vec<_>>(),
    );
    let lambda = sg2 / t;
    let inv = {
        let v = &eig.eigenvectors;
        let d = DMatrix::from_diagonal(&eig.eigenvalues.map(|s2| 1.0 / (s2.max(0.0) + lambda)));
        v * d * v.transpose()
    };
    let gamma = &inv * btr;
    let beta = fa.solve(yu) - &h * gamma;
    let extra = &h * inv * h.transpose() * sg2;
    Some(PooledFit {
        beta,
        extra,
        score: best + libm::log(n as f64),
        tau: t.sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::random::Sampler;

    fn family(columns: DMatrix<f64>) -> Nuisance {
        Nuisance {
            id: "motion_EYX".into(),
            columns,
            pooled: true,
        }
    }

    /// A line `[1, t]` and a quadratic-and-cubic family on 80 points of `[0, 1)`.
    fn line_and_family(n: usize) -> (DMatrix<f64>, DMatrix<f64>) {
        let t: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
        let a = DMatrix::from_fn(n, 2, |i, j| if j == 0 { 1.0 } else { t[i] });
        let u = DMatrix::from_fn(n, 2, |i, j| t[i].powi(j as i32 + 2));
        (a, u)
    }

    /// The closed form is the generalised least squares it stands for: the ridge-augmented least
    /// squares of `[A U]` with rows `√λ I` under `U`'s unit-RMS orthonormal columns gives the
    /// same `β̂` and the same covariance of the location errors (measured to 1e-12 relative,
    /// asserted 1e-9), on a part with a quadratic error motion of 5 µm and 1 µm of noise.
    #[test]
    fn the_closed_form_is_the_augmented_least_squares() {
        let n = 80;
        let (a, u) = line_and_family(n);
        let mut rng = Sampler::new(4);
        let y = DVector::from_fn(n, |i, _| {
            0.01 + 0.002 * a[(i, 1)] + 0.005 * u[(i, 0)] + 0.001 * rng.normal()
        });
        let used: Vec<usize> = (0..n).collect();
        let f = family(u.clone());
        let fit = pooled_fit(&Factor::new(&a, None), &y, &[&f], &used, 0.001)
            .expect("a motion the data see");
        let q = Factor::new(&u, None).basis * (n as f64).sqrt();
        let lambda = (0.001 / fit.tau).powi(2);
        let m = q.ncols();
        let mut x = DMatrix::zeros(n + m, 2 + m);
        x.view_mut((0, 0), (n, 2)).copy_from(&a);
        x.view_mut((0, 2), (n, m)).copy_from(&q);
        for k in 0..m {
            x[(n + k, 2 + k)] = lambda.sqrt();
        }
        let mut ya = DVector::zeros(n + m);
        ya.rows_mut(0, n).copy_from(&y);
        let full = Factor::new(&x, None);
        let beta = full.solve(&ya);
        let base = Factor::new(&a, None).cov * 1e-6;
        for i in 0..2 {
            assert!(
                (beta[i] - fit.beta[i]).abs() < 1e-9 * beta[i].abs(),
                "{beta} {}",
                fit.beta
            );
            for j in 0..2 {
                let want = full.cov[(i, j)] * 1e-6 - base[(i, j)];
                let scale = (full.cov[(i, i)] * full.cov[(j, j)]).sqrt() * 1e-6;
                assert!((fit.extra[(i, j)] - want).abs() < 1e-9 * scale, "{i} {j}");
            }
        }
    }

    /// An error motion the location errors absorb in part moves their least-squares estimate
    /// beyond its own std; the pooled model's estimate, with its covariance, holds the truth
    /// (5 µm of `t² + t³` on 1 µm of noise, 80 points, true `β = 0`: the intercept's least
    /// squares is off by 5.0 of its std; the pooled estimate is within 2 of its std, intercept
    /// and slope).
    #[test]
    fn an_absorbed_error_motion_is_covered() {
        let n = 80;
        let (a, u) = line_and_family(n);
        let mut rng = Sampler::new(6);
        let y = DVector::from_fn(n, |i, _| {
            0.005 * (u[(i, 0)] + u[(i, 1)]) + 0.001 * rng.normal()
        });
        let used: Vec<usize> = (0..n).collect();
        let f = family(u);
        let fit = pooled_fit(&Factor::new(&a, None), &y, &[&f], &used, 0.001)
            .expect("a motion the data see");
        let base = Factor::new(&a, None);
        let ols = base.solve(&y);
        for j in 0..2 {
            let own = 0.001 * base.cov[(j, j)].sqrt();
            let wide = (own * own + fit.extra[(j, j)]).sqrt();
            assert!(ols[j].abs() > 2.0 * own, "{j}: {} against {own}", ols[j]);
            assert!(
                fit.beta[j].abs() < 2.0 * wide,
                "{j}: {} against {wide}",
                fit.beta[j]
            );
        }
    }

    /// White noise alone: the likelihood does not rise enough with `τ` to pay its `ln n`, or not
    /// at all (seeded, 80 points): no model, or one that loses to the baseline.
    #[test]
    fn white_noise_gives_no_error_motion() {
        let n = 80;
        let (a, u) = line_and_family(n);
        let mut rng = Sampler::new(9);
        let y = DVector::from_fn(n, |_, _| 0.001 * rng.normal());
        let used: Vec<usize> = (0..n).collect();
        let f = family(u);
        if let Some(fit) = pooled_fit(&Factor::new(&a, None), &y, &[&f], &used, 0.001) {
            assert!(fit.score > 0.0, "{fit:?}");
        }
    }
}
