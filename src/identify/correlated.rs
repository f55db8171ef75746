//! Identification when the deviations' errors are correlated: generalised least squares with a
//! full noise covariance `Σ` (n × n, mm²).
//!
//! `x̂ = (AᵀΣ⁻¹A)⁻¹ AᵀΣ⁻¹ y` and `Cov(x̂) = (AᵀΣ⁻¹A)⁻¹` (Aitken's estimator; the covariance
//! needs no σ of unit weight, `Σ` carries the scale). It is computed as ordinary least squares on
//! the whitened problem `W A x ≈ W y` with the symmetric `W = Σ^{-½}` (from the eigen-
//! decomposition of `Σ`) and an a priori σ of 1, so the same rank, groups and weak-direction
//! rules of [`super::identify`] apply to the directions the correlated errors leave
//! determined. The residuals, fitted values and their statistics are then restated in mm on the
//! measured (not whitened) deviations, and the σ reported is the white part given by the caller.
//! Weights may only be 0 (a point excluded, e.g. an outlier of [`crate::measurement::outliers`]) or 1;
//! `Σ` must not correlate an excluded point with the others (block-diagonal), so that the
//! whitened rows of the kept points do not depend on it.
//!
//! Used by the final identification of the gap stage ([`crate::final_fit::correct`]) when a part
//! carries structure that no candidate effect explains: the structure is modelled as a
//! correlated error ([`crate::final_fit::structure`]) and its influence on the location errors then
//! shows in their std.

use nalgebra::{DMatrix, DVector};

use super::least_squares::restate_residuals;
use super::refine::{ExactModel, ModelError};
use super::{
    identify, Design, Identification, IdentifyError, IdentifyOptions, Observations, ScaledSvd,
};

/// `Σ^{-½}` of a symmetric positive definite matrix, by its eigen-decomposition; the offending
/// eigenvalue in the error when `Σ` is not positive definite.
pub fn inverse_square_root(sigma: &DMatrix<f64>) -> Result<DMatrix<f64>, IdentifyError> {
    let n = sigma.nrows();
    if sigma.ncols() != n {
        return Err(IdentifyError::LengthMismatch {
            what: "noise covariance columns",
            found: sigma.ncols(),
            expected: n,
        });
    }
    let eig = nalgebra::SymmetricEigen::new(sigma.clone());
    let largest = eig.eigenvalues.iter().copied().fold(0.0, f64::max);
    let mut w = DMatrix::zeros(n, n);
    for (k, &l) in eig.eigenvalues.iter().enumerate() {
        if !(l > largest * 1e-14 && l.is_finite()) {
            return Err(IdentifyError::BadOption {
                name: "noise covariance eigenvalue",
                value: l,
                expected: "> 0: the covariance must be positive definite",
            });
        }
        let q = eig.eigenvectors.column(k);
        w += (q * q.transpose()) / l.sqrt();
    }
    Ok(w)
}

/// `W = Σ^{-½}` for the generalised least squares: a dense `n × n` matrix, or, for a covariance
/// `Σ = σ² I + U diag(d) Uᵀ` with few orthonormal columns `U` shared by groups of points
/// ([`GroupedLowRank`]), its closed form `W = σ⁻¹ (I + U diag(g) Uᵀ)`, `g_k = (1 + d_k/σ²)^{-½} − 1`,
/// applied without forming `n × n` (a dense scan of 20,000 points would need 3.2 GB).
#[derive(Debug, Clone)]
pub enum Whitener {
    Dense(DMatrix<f64>),
    LowRank(GroupedLowRank),
}

/// `U = P C^{-½} V`: point `i` belongs to group `group[i]` (or to none: its row of `U` is 0),
/// `C` the groups' sizes, `V` (groups × rank) orthonormal, so that `U` has orthonormal columns;
/// `σ²` the white variance and `g` the whitening factors of [`Whitener`].
#[derive(Debug, Clone)]
pub struct GroupedLowRank {
    pub white_variance: f64,
    pub group: Vec<Option<usize>>,
    /// `c_b^{-½}` per group.
    pub scale: Vec<f64>,
    /// `V`, groups × rank.
    pub v: DMatrix<f64>,
    /// `g_k` per column of `V`.
    pub g: Vec<f64>,
}

impl GroupedLowRank {
    /// `Uᵀ x` (rank).
    pub fn ut(&self, x: &[f64]) -> DVector<f64> {
        let mut sums = DVector::zeros(self.scale.len());
        for (i, g) in self.group.iter().enumerate() {
            if let Some(b) = g {
                sums[*b] += x[i];
            }
        }
        for (b, c) in self.scale.iter().enumerate() {
            sums[b] *= c;
        }
        self.v.transpose() * sums
    }
    /// `U z` (points).
    pub fn u(&self, z: &DVector<f64>) -> Vec<f64> {
        let per_group = &self.v * z;
        self.group
            .iter()
            .map(|g| g.map_or(0.0, |b| per_group[b] * self.scale[b]))
            .collect()
    }
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        let mut t = self.ut(x);
        for (k, g) in self.g.iter().enumerate() {
            t[k] *= g;
        }
        let inv = 1.0 / self.white_variance.sqrt();
        x.iter()
            .zip(self.u(&t))
            .map(|(a, b)| (a + b) * inv)
            .collect()
    }
}

impl Whitener {
    /// The number of points.
    pub fn ncols(&self) -> usize {
        match self {
            Whitener::Dense(w) => w.ncols(),
            Whitener::LowRank(l) => l.group.len(),
        }
    }
    /// `W m`, column by column.
    pub fn apply(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        match self {
            Whitener::Dense(w) => w * m,
            Whitener::LowRank(l) => {
                let cols: Vec<DVector<f64>> = m
                    .column_iter()
                    .map(|c| {
                        let x: Vec<f64> = c.iter().copied().collect();
                        DVector::from_vec(l.apply(&x))
                    })
                    .collect();
                if cols.is_empty() {
                    DMatrix::zeros(m.nrows(), 0)
                } else {
                    DMatrix::from_columns(&cols)
                }
            }
        }
    }
    /// `W v`.
    pub fn apply_vec(&self, v: &DVector<f64>) -> DVector<f64> {
        match self {
            Whitener::Dense(w) => w * v,
            Whitener::LowRank(l) => {
                let x: Vec<f64> = v.iter().copied().collect();
                DVector::from_vec(l.apply(&x))
            }
        }
    }
}

/// The condition-index limit for the whitened design `wd` of `design`. Separability is a
/// property of the part's design, not of the noise model: whitening by a short-range
/// covariance stretches the condition of the design (8.4 → 31-46 measured on local bumps) and
/// would declare directions not separable that the part does separate. The limit is stretched
/// by the same factor (condition of the whitened over that of the plain unit-scaled design,
/// at least 1), so the groups are those of the design and the whitened std says how weak a
/// direction is.
pub fn whitened_limit(design: &Design, wd: &Design, opts: &IdentifyOptions) -> f64 {
    let stretch =
        ScaledSvd::new(wd.matrix()).condition() / ScaledSvd::new(design.matrix()).condition();
    opts.condition_index_limit
        * if stretch.is_finite() {
            stretch.max(1.0)
        } else {
            1.0
        }
}

/// The whitened problem and the identification on it, restated in mm.
#[derive(Debug, Clone)]
pub struct Correlated {
    /// The identification: values, std from `(AᵀΣ⁻¹A)⁻¹`, groups of the whitened design;
    /// residuals and their statistics on the measured deviations (mm).
    pub identification: Identification,
    /// `W = Σ^{-½}` (1/mm): [`whiten`] gives the whitened problem again (for the
    /// refinement).
    pub whitener: Whitener,
}

/// The whitened problem `W A x ≈ W y`: the design `W A` and the observations `W y` (same ids,
/// curves and weights: a point of weight 0, an outlier, stays excluded, and its covariance must
/// not couple it to the others).
pub fn whiten(
    design: &Design,
    obs: &Observations,
    w: &Whitener,
) -> Result<(Design, Observations), IdentifyError> {
    let wd = Design::try_new(design.parameters().to_vec(), w.apply(design.matrix()))?;
    let wy = w.apply_vec(&DVector::from_column_slice(&obs.deviation));
    let mut wobs = Observations::new(
        obs.ids.clone(),
        obs.curves.clone(),
        wy.iter().copied().collect(),
    );
    wobs.weights = obs.weights.clone();
    Ok((wd, wobs))
}

/// Generalised least squares of `design` on `obs` with the noise covariance `sigma` (mm²);
/// `white` is the σ of the uncorrelated part (mm), reported as the identification's σ.
pub fn identify_correlated(
    design: &Design,
    obs: &Observations,
    sigma: &DMatrix<f64>,
    white: f64,
    opts: &IdentifyOptions,
) -> Result<Correlated, IdentifyError> {
    obs.validate(design.rows())?;
    check_weights(obs)?;
    if sigma.nrows() != design.rows() {
        return Err(IdentifyError::LengthMismatch {
            what: "noise covariance rows",
            found: sigma.nrows(),
            expected: design.rows(),
        });
    }
    identify_whitened(
        design,
        obs,
        Whitener::Dense(inverse_square_root(sigma)?),
        white,
        opts,
    )
}

/// [`identify_correlated`] with the whitener of the covariance given (a [`Whitener::LowRank`]
/// for a large structured part); weights as there (0 or 1, checked by the caller).
pub fn identify_whitened(
    design: &Design,
    obs: &Observations,
    w: Whitener,
    white: f64,
    opts: &IdentifyOptions,
) -> Result<Correlated, IdentifyError> {
    obs.validate(design.rows())?;
    check_weights(obs)?;
    if w.ncols() != design.rows() {
        return Err(IdentifyError::LengthMismatch {
            what: "whitener columns",
            found: w.ncols(),
            expected: design.rows(),
        });
    }
    let (wd, wobs) = whiten(design, obs, &w)?;
    let limit = whitened_limit(design, &wd, opts);
    let mut id = identify(
        &wd,
        &wobs,
        &opts
            .clone()
            .with_sigma(1.0)
            .with_condition_index_limit(limit),
    )?;
    let fitted = design.predict(&id.values());
    restate_residuals(&mut id, obs, &fitted, opts.mape_floor);
    id.sigma = Some(white);
    id.sigma_source = "correlated: white σ plus the structure's covariance".to_string();
    id.notes
        .retain(|n| !n.starts_with("covariance scaled with sigma"));
    id.notes.push(format!(
        "generalised least squares with a full noise covariance (white σ = {white:.4e} mm plus a \
         correlated part): the std are those of (AᵀΣ⁻¹A)⁻¹"
    ));
    Ok(Correlated {
        identification: id,
        whitener: w,
    })
}

/// Weights with a covariance may only be 0 (a point excluded) or 1.
fn check_weights(obs: &Observations) -> Result<(), IdentifyError> {
    match obs
        .weights
        .iter()
        .flatten()
        .find(|&&w| w != 0.0 && w != 1.0)
    {
        Some(&bad) => Err(IdentifyError::BadOption {
            name: "weights with a noise covariance",
            value: bad,
            expected: "0 (point excluded) or 1: the covariance carries every point's variance",
        }),
        None => Ok(()),
    }
}

/// An exact model seen through a whitener: deviations `W f(x)`, Jacobian `W ∂f/∂x`, so the
/// refinement of [`super::refine`] works on the whitened problem unchanged.
pub struct Whitened<'a, M: ExactModel> {
    pub model: M,
    pub whitener: &'a Whitener,
}

impl<M: ExactModel> ExactModel for Whitened<'_, M> {
    fn deviation(&self, x: &[f64]) -> Result<Vec<f64>, ModelError> {
        let f = DVector::from_vec(self.model.deviation(x)?);
        if f.len() != self.whitener.ncols() {
            return Err(ModelError::Whitener {
                found: f.len(),
                expected: self.whitener.ncols(),
            });
        }
        Ok(self.whitener.apply_vec(&f).iter().copied().collect())
    }
    fn jacobian(&self, x: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        Ok(self.whitener.apply(&self.model.jacobian(x)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// Closed form: with `Σ = diag(1, 4, 4) + 0` and one column of ones, GLS is the weighted
    /// mean `Σ (y_i/σ_i²) / Σ (1/σ_i²) = (3 + 2/4 + 6/4) / 1.5 = 10/3` and its variance
    /// `1 / 1.5 = 2/3` (to 1e-12).
    #[test]
    fn diagonal_covariance_gives_the_weighted_mean() {
        let d = Design::from_column_major(&["EX0B"], 3, &[1.0, 1.0, 1.0]).unwrap();
        let obs = Observations::plain(vec![3.0, 2.0, 6.0]);
        let s = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 4.0, 4.0]));
        let c = identify_correlated(&d, &obs, &s, 1.0, &IdentifyOptions::default()).unwrap();
        let p = &c.identification.parameters.0[0];
        assert_near!(p.value, 10.0 / 3.0, 1e-12);
        assert_near!(p.std.unwrap(), (2.0f64 / 3.0).sqrt(), 1e-12);
        // residuals in mm on the measured deviations, not whitened
        assert_near!(c.identification.points[0].residual, 3.0 - 10.0 / 3.0, 1e-12);
    }

    /// Two perfectly correlated points carry the information of one: with
    /// `Σ = [[1+ρ, ρ],[ρ, 1+ρ]]`-type structure (`τ² = 9` shared, white 1) and a third independent
    /// point, the mean's variance is `1 / (2/(1+2·9) + 1) = 19/21` (closed form, to 1e-12).
    #[test]
    fn a_shared_error_counts_once() {
        let d = Design::from_column_major(&["EX0B"], 3, &[1.0, 1.0, 1.0]).unwrap();
        let obs = Observations::plain(vec![1.0, 1.0, 0.0]);
        let s = DMatrix::from_row_slice(3, 3, &[10.0, 9.0, 0.0, 9.0, 10.0, 0.0, 0.0, 0.0, 1.0]);
        let c = identify_correlated(&d, &obs, &s, 1.0, &IdentifyOptions::default()).unwrap();
        // 1ᵀΣ⁻¹1: the pair block [[10,9],[9,10]] has 1ᵀB⁻¹1 = 2/19; plus 1.
        assert_near!(
            c.identification.parameters.0[0].std.unwrap(),
            (19.0f64 / 21.0).sqrt(),
            1e-12
        );
    }

    /// A point of weight 0 (an outlier) not correlated with the others changes nothing: the
    /// pair-plus-one case of `a_shared_error_counts_once` with a fourth point of weight 0 and a
    /// wild value gives the same estimate and std, and the point is listed as excluded.
    #[test]
    fn a_point_of_weight_zero_is_left_out() {
        let d = Design::from_column_major(&["EX0B"], 4, &[1.0, 1.0, 1.0, 1.0]).unwrap();
        let obs =
            Observations::plain(vec![1.0, 1.0, 0.0, 50.0]).with_weights(vec![1.0, 1.0, 1.0, 0.0]);
        let mut s = DMatrix::identity(4, 4);
        s.view_mut((0, 0), (3, 3))
            .copy_from(&DMatrix::from_row_slice(
                3,
                3,
                &[10.0, 9.0, 0.0, 9.0, 10.0, 0.0, 0.0, 0.0, 1.0],
            ));
        let c = identify_correlated(&d, &obs, &s, 1.0, &IdentifyOptions::default()).unwrap();
        let p = &c.identification.parameters.0[0];
        assert_near!(p.std.unwrap(), (19.0f64 / 21.0).sqrt(), 1e-12);
        // GLS mean: (1ᵀB⁻¹y_pair + y_3) / (2/19 + 1) = (2/19) / (21/19) = 2/21.
        assert_near!(p.value, 2.0 / 21.0, 1e-12);
        assert_eq!(c.identification.points_used, 3);
        assert_eq!(c.identification.points_excluded[0].id, "4");
        // Other weights are refused: Σ carries the variances.
        let bad = obs.clone().with_weights(vec![1.0, 2.0, 1.0, 1.0]);
        assert!(identify_correlated(&d, &bad, &s, 1.0, &IdentifyOptions::default()).is_err());
    }

    #[test]
    fn a_covariance_that_is_not_positive_definite_is_refused_with_its_eigenvalue() {
        let s = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        let e = inverse_square_root(&s).unwrap_err().to_string();
        assert!(e.contains("-1"), "{e}");
    }
}
