//! Weighted linear least squares on a named design, by SVD in the column-scaled space.
//!
//! Minimise `Σ w_i (y_i - (A x)_i)²`. With `B = W^½ A D⁻¹ = U S Vᵀ` ([`ScaledSvd`]) and
//! `ξ = D x`, a direction `v_k` is *unresolved* when `s_k ≤ τ` (numerical rank) or
//! `η_k = s₁/s_k ≥ η_max` (default 30, Belsley): along it the noise is amplified 30 times more
//! than along the best direction, and the part cannot separate the parameters that make it up.
//!
//! **What is fixed, and why.** The unresolved directions span a subspace `V_u` of the scaled
//! parameter space; the parameters with at least `1 − naming_share` (10 %) of their unit vector
//! in it, `‖P_u e_j‖² ≥ 0.1` with the projector `P_u = V_u V_uᵀ`, form the not-separable set `S`
//! ([`not_separable_set`]). The solution is fixed by `P_S ξ ⟂ P_S V_u`: within `S` it is the
//! **minimum-norm solution in the scaled space** (`ξ_j = D_j x_j`, each parameter times its
//! column norm, i.e. measured by the deviation, in mm, that it makes on the part), the
//! parameters outside `S` are not pulled toward 0. (The plain truncated-SVD minimum-norm solution
//! would also pull the well-determined parameters that have a small share in `V_u`: on Table 4
//! it biases `EX0B` by 0.5 %, 5 std.) This is the data-driven analogue of paper 000 §6 fixing
//! `EA0C = -EA0Z`. The individual values of a not-separable group are therefore a *convention*:
//! only the group's estimable combinations (orthogonal to `V_u`) are determined by the part and
//! carry a std; the report lists the group as not separable.
//!
//! The constraint depends on `V_u` only through `P_u`, never on the basis the SVD chose in it:
//! on an exactly rank-deficient design (e.g. the tilting table of paper 002, rank 6 of 8) the null
//! directions are a degenerate subspace whose basis is decided by rounding, and it differs
//! between the native and the wasm build; `P_u` does not (up to `ε·s₁/gap`, the gap being
//! between the last solved and the first unresolved singular value, ≥ the condition-index
//! limit). So native and wasm report the same values. Then ordinary least squares on the
//! constrained subspace `ξ = N w` (`N` an orthonormal basis of the constraints' null space), by
//! SVD of `B N`; its solution does not depend on the choice of `N` either.
//!
//! Covariance: `Cov(x) = σ² D⁻¹ N (NᵀBᵀBN)⁻¹ Nᵀ D⁻¹` with `σ² = Σ w_i r_i² / (n - r)` (a posteriori,
//! `r` solved directions) or a given σ (a priori; then `w_i` should be `1/σ_i²` relative to it).
//! Without unresolved directions this is `σ² (AᵀWA)⁻¹`.

use nalgebra::{DMatrix, DVector};

use crate::numerics::order::groups_in_order;

use super::groups::{not_separable_groups, weak_groups, Group, GroupKind};
use super::report::{
    ColumnCorrelation, CurveStats, ExcludedPoint, Identification, ParameterEstimate, ParameterMap,
    PointFit, Status, NONZERO_T,
};
use super::scaled_svd::{condition_of, ScaledSvd};
use super::stats::ResidualStats;
use super::{Design, IdentifyError, Observations};

/// Options of [`identify`]; `Default` gives the values stated in the module docs.
#[derive(Debug, Clone, PartialEq)]
pub struct IdentifyOptions {
    /// Condition index `s₁/s_k` at or above which a direction is not separated (default 30).
    pub condition_index_limit: f64,
    /// Std, in typical magnitudes, above which a direction or parameter is weak (default 0.25).
    pub weak_limit: f64,
    /// A priori σ of unit weight (mm); `None` uses the residual.
    pub sigma: Option<f64>,
    /// Smallest |measured| entering MAPE (mm, default 0.003 = R0 of paper 000 §6).
    pub mape_floor: f64,
    /// |cosine| from which a pair of design columns is listed (default 0.7).
    pub correlation_report: f64,
    /// Share of a direction's squared norm kept when naming it (default 0.9).
    pub naming_share: f64,
}

impl Default for IdentifyOptions {
    fn default() -> Self {
        IdentifyOptions {
            condition_index_limit: 30.0,
            weak_limit: 0.25,
            sigma: None,
            mape_floor: 0.003,
            correlation_report: 0.7,
            naming_share: 0.9,
        }
    }
}

impl IdentifyOptions {
    /// Sets the condition-index limit (> 1).
    pub fn with_condition_index_limit(mut self, v: f64) -> Self {
        self.condition_index_limit = v;
        self
    }
    /// Sets the weak limit (std in typical magnitudes, > 0).
    pub fn with_weak_limit(mut self, v: f64) -> Self {
        self.weak_limit = v;
        self
    }
    /// Uses an a priori σ (mm) instead of the residual's.
    pub fn with_sigma(mut self, sigma: f64) -> Self {
        self.sigma = Some(sigma);
        self
    }
    /// Sets the MAPE floor (mm).
    pub fn with_mape_floor(mut self, v: f64) -> Self {
        self.mape_floor = v;
        self
    }

    fn validate(&self) -> Result<(), IdentifyError> {
        let bad = |name, value, expected| {
            Err(IdentifyError::BadOption {
                name,
                value,
                expected,
            })
        };
        if self.condition_index_limit.is_nan() || self.condition_index_limit <= 1.0 {
            return bad("condition_index_limit", self.condition_index_limit, "> 1");
        }
        if !(self.weak_limit > 0.0 && self.weak_limit.is_finite()) {
            return bad("weak_limit", self.weak_limit, "> 0 and finite");
        }
        if let Some(s) = self.sigma {
            if !(s > 0.0 && s.is_finite()) {
                return bad("sigma", s, "> 0 and finite (mm)");
            }
        }
        if !(self.mape_floor >= 0.0 && self.mape_floor.is_finite()) {
            return bad("mape_floor", self.mape_floor, ">= 0 (mm)");
        }
        if !(self.naming_share > 0.0 && self.naming_share <= 1.0) {
            return bad("naming_share", self.naming_share, "in (0, 1]");
        }
        Ok(())
    }
}

/// The parameters the unresolved subspace `V_u` (columns of `vu`, orthonormal, scaled space)
/// is restricted to when it is fixed: `j` with `‖P_u e_j‖² = Σ_k v_jk² ≥ 1 − share` (at least
/// 10 % of the unit vector of parameter `j` lies in `V_u`, by default).
///
/// `P_u = V_u V_uᵀ` does not depend on which orthonormal basis of `V_u` the SVD returned: on an
/// exactly rank-deficient design the null directions are defined only as a subspace, and the SVD
/// of the native build and of the wasm build pick different bases in it (the rounding of the
/// tiny singular values decides). A set or a constraint built from one basis vector at a time
/// would differ between the two; this one does not.
pub fn not_separable_set(vu: &DMatrix<f64>, share: f64) -> Vec<usize> {
    let floor = (1.0 - share).max(1e-3);
    (0..vu.nrows())
        .filter(|&j| vu.row(j).norm_squared() >= floor)
        .collect()
}

/// The factored problem: used points, weights, scaled SVD, the constraints that fix the
/// unresolved directions, and the SVD of the constrained problem.
#[derive(Debug, Clone)]
pub struct Factored {
    /// Indices of the points with weight > 0.
    pub used: Vec<usize>,
    /// √w of the used points.
    pub sqrt_w: Vec<f64>,
    /// SVD of the scaled weighted design over the used points.
    pub svd: ScaledSvd,
    /// Index of the first unresolved singular direction (`svd.v` columns `first_unresolved..p`
    /// are the unresolved directions, in the scaled space).
    pub first_unresolved: usize,
    /// The parameters each unresolved direction is restricted to when it is fixed (naming rule).
    pub constrained_sets: Vec<Vec<usize>>,
    /// Number of directions of the solution (columns of `basis_xi`).
    pub kept: usize,
    /// Orthonormal basis of the solved subspace in the scaled space (p x kept).
    pub basis_xi: DMatrix<f64>,
    /// Singular values of the constrained problem (kept of them).
    pub s_red: Vec<f64>,
    /// Left singular vectors of the constrained problem (n_used x kept).
    pub u_red: DMatrix<f64>,
}

impl Factored {
    /// Validates and factors `design` for the points of `obs` with weight > 0.
    ///
    /// Unresolved directions `v_k` (condition index ≥ limit or below the rank threshold) are
    /// fixed by the constraint `Σ_{j∈J_k} v_jk ξ_j = 0`, `J_k` being the parameters that name the
    /// direction: the minimum-norm choice in the scaled space, restricted to the group so that
    /// the parameters outside it are not pulled toward 0. Then ordinary least squares on the
    /// constrained subspace (by SVD; anything still below the rank threshold is dropped).
    pub fn new(
        design: &Design,
        obs: &Observations,
        opts: &IdentifyOptions,
    ) -> Result<Self, IdentifyError> {
        opts.validate()?;
        obs.validate(design.rows())?;
        let used: Vec<usize> = (0..obs.len()).filter(|&i| obs.weight(i) > 0.0).collect();
        if used.is_empty() {
            return Err(IdentifyError::NoPoints {
                total: obs.len(),
                excluded: obs.len(),
            });
        }
        let p = design.cols();
        let sqrt_w: Vec<f64> = used.iter().map(|&i| obs.weight(i).sqrt()).collect();
        let a = design.matrix();
        let b = DMatrix::from_fn(used.len(), p, |r, j| a[(used[r], j)] * sqrt_w[r]);
        let svd = ScaledSvd::new(&b);
        let s1 = svd.singular.first().copied().unwrap_or(0.0);
        let first_unresolved = svd
            .singular
            .iter()
            .take_while(|&&s| s > svd.rank_tolerance && s1 / s < opts.condition_index_limit)
            .count();
        // Constraints G ξ = 0: the unresolved subspace restricted to the not-separable set `S`
        // (decided from its projector, so independent of the basis the SVD picked inside it).
        let t = p - first_unresolved;
        let vu = svd.v.columns(first_unresolved, t).into_owned();
        let set = not_separable_set(&vu, opts.naming_share);
        let mut g = DMatrix::zeros(t.max(1), p);
        for r in 0..t {
            for &j in &set {
                g[(r, j)] = vu[(j, r)];
            }
        }
        let constrained_sets = vec![set; t];
        // Orthonormal basis N of null(G): right singular vectors of G beyond its rank.
        let n_basis = if t == 0 {
            DMatrix::identity(p, p)
        } else {
            let mut padded = DMatrix::zeros(p.max(t), p);
            padded.view_mut((0, 0), (t, p)).copy_from(&g.rows(0, t));
            let sv = nalgebra::SVD::new(padded, false, true);
            let vt = sv.v_t.unwrap_or_else(|| DMatrix::identity(p, p));
            let smax = sv.singular_values.iter().copied().fold(0.0, f64::max);
            let tol = (p as f64) * f64::EPSILON * smax.max(f64::MIN_POSITIVE);
            let cols: Vec<DVector<f64>> = (0..sv.singular_values.len())
                .filter(|&k| sv.singular_values[k] <= tol)
                .map(|k| vt.row(k).transpose())
                .collect();
            if cols.is_empty() {
                DMatrix::zeros(p, 0)
            } else {
                DMatrix::from_columns(&cols)
            }
        };
        // Constrained problem B_s N = U' S' V'ᵀ (B_s: the scaled design).
        let mut bs = b;
        for j in 0..p {
            let c = svd.scale[j];
            bs.column_mut(j).scale_mut(1.0 / c);
        }
        let (basis_xi, s_red, u_red) = if n_basis.ncols() == 0 {
            (
                DMatrix::zeros(p, 0),
                Vec::new(),
                DMatrix::zeros(used.len(), 0),
            )
        } else {
            let red = &bs * &n_basis;
            let q = red.ncols();
            let rows = red.nrows().max(q);
            let mut padded = DMatrix::zeros(rows, q);
            padded.view_mut((0, 0), (red.nrows(), q)).copy_from(&red);
            let sv = nalgebra::SVD::new(padded, true, true);
            let u = sv.u.unwrap_or_else(|| DMatrix::zeros(rows, q));
            let vt = sv.v_t.unwrap_or_else(|| DMatrix::identity(q, q));
            let tol = svd.rank_tolerance.max(f64::MIN_POSITIVE);
            let keep: Vec<usize> = (0..sv.singular_values.len())
                .filter(|&k| sv.singular_values[k] > tol)
                .collect();
            let basis = DMatrix::from_fn(p, keep.len(), |j, c| {
                (n_basis.row(j) * vt.row(keep[c]).transpose())[(0, 0)]
            });
            let s: Vec<f64> = keep.iter().map(|&k| sv.singular_values[k]).collect();
            let ur = DMatrix::from_fn(used.len(), keep.len(), |r, c| u[(r, keep[c])]);
            (basis, s, ur)
        };
        let kept = s_red.len();
        // An all-zero column is not seen at all: its parameter is exactly 0 (not rounding noise
        // of the constraint basis), with no variance.
        let mut basis_xi = basis_xi;
        for &j in &svd.zero_columns {
            basis_xi.row_mut(j).fill(0.0);
        }
        Ok(Factored {
            used,
            sqrt_w,
            svd,
            first_unresolved,
            constrained_sets,
            kept,
            basis_xi,
            s_red,
            u_red,
        })
    }

    /// The linear estimator `x = M y_used` (p x n_used): `D⁻¹ N V' S'⁻¹ U'ᵀ W^½`.
    pub fn estimator(&self) -> DMatrix<f64> {
        let p = self.basis_xi.nrows();
        let n = self.used.len();
        // `f_jk = (N V')_jk / (s'_k d_j)`, then each point's column of `M` in turn, its terms in
        // the order of `k` (the same sums as direction by direction over every point, which
        // wrote across all of `M` once a term: 64 passes over 13 MB at 200,000 points, issue 31)
        let f = DMatrix::from_fn(p, self.kept, |j, k| {
            self.basis_xi[(j, k)] / (self.s_red[k] * self.svd.scale[j])
        });
        let mut m = DMatrix::zeros(p, n);
        for (r, mut col) in m.column_iter_mut().enumerate() {
            for k in 0..self.kept {
                let uw = self.u_red[(r, k)];
                for j in 0..p {
                    col[j] += f[(j, k)] * uw * self.sqrt_w[r];
                }
            }
        }
        m
    }

    /// `D⁻¹ N V' S'⁻² V'ᵀ Nᵀ D⁻¹`: the covariance for σ = 1.
    pub fn unit_covariance(&self) -> DMatrix<f64> {
        let p = self.basis_xi.nrows();
        let mut c = DMatrix::zeros(p, p);
        for k in 0..self.kept {
            let s2 = self.s_red[k].powi(2);
            for i in 0..p {
                for j in 0..p {
                    c[(i, j)] += self.basis_xi[(i, k)] * self.basis_xi[(j, k)]
                        / s2
                        / (self.svd.scale[i] * self.svd.scale[j]);
                }
            }
        }
        c
    }

    /// The basis of solved directions in parameter space, `D⁻¹ N V'` (p x kept).
    pub fn kept_basis(&self) -> DMatrix<f64> {
        let p = self.basis_xi.nrows();
        DMatrix::from_fn(p, self.kept, |j, k| {
            self.basis_xi[(j, k)] / self.svd.scale[j]
        })
    }
}

/// Identifies the parameters of `design` from the measured deviations of `obs`.
///
/// Never panics on user data; rank-deficient designs (fewer points than parameters, collinear
/// or zero columns) give the minimum-norm solution with the unresolved directions named.
///
/// The steps, each a function of this file: factor ([`Factored::new`]), solve in the scaled
/// space, σ of unit weight from the residual, the covariance, the groups, the parameter
/// estimates with their status, the correlations, the residual statistics and the notes.
pub fn identify(
    design: &Design,
    obs: &Observations,
    opts: &IdentifyOptions,
) -> Result<Identification, IdentifyError> {
    identify_factored(design, obs, opts).map(|(id, _)| id)
}

/// [`identify`], and the factored problem it solved ([`Factored::new`] of the same `design`,
/// `obs` and `opts`): for an exact-model refinement of the same fit
/// ([`crate::identify::refine::refine_factored`]), which would otherwise factorise it again.
pub fn identify_factored(
    design: &Design,
    obs: &Observations,
    opts: &IdentifyOptions,
) -> Result<(Identification, Factored), IdentifyError> {
    let f = Factored::new(design, obs, opts)?;
    let p = design.cols();
    let x = solve_scaled(&f, obs);
    let fitted = design.predict(&x);
    let wss = weighted_residual_sum(&f.used, &f.sqrt_w, &obs.deviation, &fitted);
    let noise = noise_sigma(wss, f.used.len(), f.kept, opts.sigma);
    let cov = noise.sigma.map(|s| f.unit_covariance() * (s * s));
    let groups = parameter_groups(design, &f, &x, cov.as_ref(), opts);
    let params = parameter_estimates(design, &x, cov.as_ref(), &groups, opts.weak_limit);
    let (correlation, covariance) = correlations(cov.as_ref(), &params);
    let notes = notes(&f, p, opts, &noise);
    let svd = &f.svd;
    let id = Identification {
        parameters: ParameterMap(params),
        groups,
        rank: svd.rank,
        rank_used: f.kept,
        condition: svd.condition(),
        condition_used: condition_of(&f.s_red),
        condition_index_limit: opts.condition_index_limit,
        singular_values: svd.singular.clone(),
        residual: residual_statistics(obs, &f.used, &fitted, opts.mape_floor),
        per_curve: per_curve_statistics(obs, &f.used, &fitted, opts.mape_floor),
        points_used: f.used.len(),
        points_excluded: excluded_points(obs),
        sigma: noise.sigma,
        sigma_source: noise.source,
        dof: noise.dof,
        correlation,
        covariance,
        column_correlations: column_correlations(
            design,
            &f.used,
            &f.sqrt_w,
            opts.correlation_report,
        ),
        points: point_fits(obs, &fitted),
        notes,
    };
    Ok((id, f))
}

/// The least-squares solution `x = M y_used` ([`Factored::estimator`]: `D⁻¹ N V' S'⁻¹ U'ᵀ W^½`,
/// solved in the column-scaled space), in the parameters' units (mm, rad).
fn solve_scaled(f: &Factored, obs: &Observations) -> Vec<f64> {
    let y_used = DVector::from_iterator(f.used.len(), f.used.iter().map(|&i| obs.deviation[i]));
    (f.estimator() * &y_used).iter().copied().collect()
}

/// The weighted residual sum of squares `Σ w_i (y_i − (A x)_i)²` over the `used` points (mm²),
/// `sqrt_w[r]` being `√w` of the `r`-th used point.
fn weighted_residual_sum(used: &[usize], sqrt_w: &[f64], measured: &[f64], fitted: &[f64]) -> f64 {
    let mut wss = 0.0;
    for (r, &i) in used.iter().enumerate() {
        let e = measured[i] - fitted[i];
        wss += sqrt_w[r].powi(2) * e * e;
    }
    wss
}

/// σ of unit weight (mm), where it comes from, and the residual degrees of freedom.
#[derive(Debug, Clone, PartialEq)]
struct NoiseSigma {
    /// σ (mm); `None` without residual degree of freedom and without an a priori σ.
    sigma: Option<f64>,
    /// `a_priori`, `a_posteriori` or why there is none.
    source: String,
    /// `n − r`: used points minus solved directions.
    dof: usize,
}

/// σ of unit weight: the a priori σ (mm) if given, else `σ = √(Σ w_i r_i² / (n − r))` (mm) from
/// the weighted residual sum `wss` (mm²), `n` used points and `r` solved directions.
fn noise_sigma(wss: f64, used: usize, kept: usize, a_priori: Option<f64>) -> NoiseSigma {
    let dof = used.saturating_sub(kept);
    let (sigma, source) = match a_priori {
        Some(s) => (Some(s), "a_priori".to_string()),
        None if dof > 0 => (Some((wss / dof as f64).sqrt()), "a_posteriori".to_string()),
        None => (
            None,
            "none: no residual degree of freedom and no a priori sigma".to_string(),
        ),
    };
    NoiseSigma { sigma, source, dof }
}

/// The not-separable groups (the unresolved directions `v_k`, `k ≥ first_unresolved`, of the
/// scaled SVD with their condition indices) and, where there is a covariance (units² of the
/// parameters), the weak groups (std above `weak_limit` typical magnitudes).
fn parameter_groups(
    design: &Design,
    f: &Factored,
    x: &[f64],
    cov: Option<&DMatrix<f64>>,
    opts: &IdentifyOptions,
) -> Vec<Group> {
    let names = design.names();
    let svd = &f.svd;
    let dirs: Vec<(Vec<f64>, f64)> = (f.first_unresolved..design.cols())
        .map(|k| {
            (
                svd.v.column(k).iter().copied().collect(),
                svd.condition_index(k),
            )
        })
        .collect();
    let mut groups = not_separable_groups(&names, &svd.scale, &dirs, x, cov, opts.naming_share);
    let typical: Vec<f64> = design.parameters().iter().map(|q| q.typical).collect();
    if let Some(c) = cov {
        groups.extend(weak_groups(
            &names,
            &typical,
            x,
            c,
            opts.weak_limit,
            opts.naming_share,
        ));
    }
    groups
}

/// The status of a parameter: not separable if a not-separable group names it, else weak if a
/// weak group names it or its std `sd` exceeds `weak_limit · typical` (both in the
/// parameter's unit, mm or rad), else identified.
fn status_of(
    name: &str,
    sd: Option<f64>,
    typical: f64,
    groups: &[Group],
    weak_limit: f64,
) -> Status {
    let in_kind = |kind: GroupKind| {
        groups
            .iter()
            .any(|g| g.kind == kind && g.parameters.iter().any(|n| n == name))
    };
    if in_kind(GroupKind::NotSeparable) {
        Status::NotSeparable
    } else if in_kind(GroupKind::Weak) || sd.is_some_and(|s| s > weak_limit * typical) {
        Status::Weak
    } else {
        Status::Identified
    }
}

/// Value, std (`√Cov_jj`, none for a not-separable parameter), unit, status and `t = |x|/std`
/// of each parameter, in design order.
fn parameter_estimates(
    design: &Design,
    x: &[f64],
    cov: Option<&DMatrix<f64>>,
    groups: &[Group],
    weak_limit: f64,
) -> Vec<ParameterEstimate> {
    let mut params = Vec::with_capacity(design.cols());
    for (j, q) in design.parameters().iter().enumerate() {
        let sd = cov.map(|c| c[(j, j)].max(0.0).sqrt());
        let status = status_of(&q.name(), sd, q.typical, groups, weak_limit);
        let std = if status == Status::NotSeparable {
            None
        } else {
            sd
        };
        let t = std.filter(|s| *s > 0.0).map(|s| x[j].abs() / s);
        params.push(ParameterEstimate {
            id: q.id.clone(),
            value: x[j],
            std,
            status,
            t,
            nonzero: status == Status::Identified && t.is_some_and(|t| t >= NONZERO_T),
        });
    }
    params
}

/// The correlation matrix `Cov_ij / (σ_i σ_j)` (none where a parameter is not separable or has
/// no variance) and the covariance as rows (units² of the parameters; zeros without one).
fn correlations(
    cov: Option<&DMatrix<f64>>,
    params: &[ParameterEstimate],
) -> (Vec<Vec<Option<f64>>>, Vec<Vec<f64>>) {
    let p = params.len();
    let mut correlation = vec![vec![None; p]; p];
    let mut covariance = vec![vec![0.0; p]; p];
    if let Some(c) = cov {
        for i in 0..p {
            for j in 0..p {
                covariance[i][j] = c[(i, j)];
                let (si, sj) = (c[(i, i)].sqrt(), c[(j, j)].sqrt());
                let ok = params[i].status != Status::NotSeparable
                    && params[j].status != Status::NotSeparable;
                if ok && si > 0.0 && sj > 0.0 {
                    correlation[i][j] = Some(c[(i, j)] / (si * sj));
                }
            }
        }
    }
    (correlation, covariance)
}

/// The pairs of design columns whose weighted cosine over the used points,
/// `Σ w a_i a_j / √(Σ w a_i² · Σ w a_j²)` (unitless), is at least `limit` in magnitude, in
/// column order; `sqrt_w[r]` is `√w` of the `r`-th used point.
fn column_correlations(
    design: &Design,
    used: &[usize],
    sqrt_w: &[f64],
    limit: f64,
) -> Vec<ColumnCorrelation> {
    let names = design.names();
    let a = design.matrix();
    let p = design.cols();
    let mut column_correlations = Vec::new();
    for i in 0..p {
        for j in (i + 1)..p {
            let (mut dot, mut ni, mut nj) = (0.0, 0.0, 0.0);
            for (r, &k) in used.iter().enumerate() {
                let w = sqrt_w[r].powi(2);
                dot += w * a[(k, i)] * a[(k, j)];
                ni += w * a[(k, i)].powi(2);
                nj += w * a[(k, j)].powi(2);
            }
            if ni > 0.0 && nj > 0.0 {
                let c = dot / (ni * nj).sqrt();
                if c.abs() >= limit {
                    column_correlations.push(ColumnCorrelation {
                        a: names[i].clone(),
                        b: names[j].clone(),
                        cosine: c,
                    });
                }
            }
        }
    }
    column_correlations
}

/// Restates the residual side of an identification (per-point fits, residual statistics, per
/// curve) for the deviations of `obs` and the `fitted` values (mm): used when the fit itself was
/// made on transformed (whitened) data ([`super::correlated`]).
pub(crate) fn restate_residuals(
    id: &mut Identification,
    obs: &Observations,
    fitted: &[f64],
    mape_floor: f64,
) {
    let used: Vec<usize> = (0..obs.len()).filter(|&i| obs.weight(i) > 0.0).collect();
    id.residual = residual_statistics(obs, &used, fitted, mape_floor);
    id.per_curve = per_curve_statistics(obs, &used, fitted, mape_floor);
    id.points = point_fits(obs, fitted);
}

/// Residual statistics (paper 001 eq. 15-17; mm, MAPE in %) over the used points.
fn residual_statistics(
    obs: &Observations,
    used: &[usize],
    fitted: &[f64],
    mape_floor: f64,
) -> ResidualStats {
    let meas: Vec<f64> = used.iter().map(|&i| obs.deviation[i]).collect();
    let fit: Vec<f64> = used.iter().map(|&i| fitted[i]).collect();
    ResidualStats::of(&meas, &fit, mape_floor)
}

/// Residual statistics per curve label over the used points, curves in order of first
/// appearance.
fn per_curve_statistics(
    obs: &Observations,
    used: &[usize],
    fitted: &[f64],
    mape_floor: f64,
) -> Vec<CurveStats> {
    groups_in_order(used.iter().map(|&i| (i, obs.curves[i].as_str())))
        .into_iter()
        .map(|(c, idx)| {
            let m: Vec<f64> = idx.iter().map(|&i| obs.deviation[i]).collect();
            let ft: Vec<f64> = idx.iter().map(|&i| fitted[i]).collect();
            CurveStats {
                curve: c.to_string(),
                stats: ResidualStats::of(&m, &ft, mape_floor),
            }
        })
        .collect()
}

/// Measured, fitted and residual deviation (mm) of every point, used or not.
fn point_fits(obs: &Observations, fitted: &[f64]) -> Vec<PointFit> {
    (0..obs.len())
        .map(|i| PointFit {
            id: obs.ids[i].clone(),
            curve: obs.curves[i].clone(),
            measured: obs.deviation[i],
            fitted: fitted[i],
            residual: obs.deviation[i] - fitted[i],
            used: obs.weight(i) > 0.0,
        })
        .collect()
}

/// The points left out of the fit (weight 0), with the reason.
fn excluded_points(obs: &Observations) -> Vec<ExcludedPoint> {
    (0..obs.len())
        .filter(|&i| obs.weight(i) <= 0.0)
        .map(|i| ExcludedPoint {
            id: obs.ids[i].clone(),
            reason: "weight 0".to_string(),
        })
        .collect()
}

/// Notes: what was fixed and why (rank and condition of the scaled design, the unresolved
/// directions, too few points, the σ the covariance is scaled with, in mm).
fn notes(f: &Factored, p: usize, opts: &IdentifyOptions, noise: &NoiseSigma) -> Vec<String> {
    let svd = &f.svd;
    let mut notes = vec![format!(
        "columns scaled to unit length (weighted); numerical rank {} of {} with threshold max(n,p)*eps*s1 = {:.3e}; \
         condition number of the scaled design {:.4}",
        svd.rank,
        p,
        svd.rank_tolerance,
        svd.condition()
    )];
    if f.first_unresolved < p {
        notes.push(format!(
            "{} direction(s) with condition index >= {} (or below the rank threshold) are not separated; \
             each is fixed by setting its named combination to 0 in the scaled space (minimum norm within \
             its group, parameters outside the group unconstrained); only the estimable combinations of \
             those groups carry a std",
            p - f.first_unresolved,
            opts.condition_index_limit
        ));
    }
    if f.used.len() < p {
        notes.push(format!(
            "only {} points for {} parameters: at most {} directions can be determined",
            f.used.len(),
            p,
            f.used.len()
        ));
    }
    let (sigma_source, dof) = (&noise.source, noise.dof);
    notes.push(match noise.sigma {
        Some(s) => format!("covariance scaled with sigma = {s:.4e} mm ({sigma_source}, {dof} dof)"),
        None => {
            "no covariance: as many kept directions as points and no a priori sigma".to_string()
        }
    });
    notes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::identify::Parameter;

    /// `σ = √(wss / (n − r))`: wss = 8 mm², 6 points, 2 solved directions → dof 4, σ = √2 mm
    /// (closed form, to rounding 1e-15 mm).
    #[test]
    fn noise_sigma_is_the_root_of_the_residual_per_degree_of_freedom() {
        let s = noise_sigma(8.0, 6, 2, None);
        assert_eq!((s.dof, s.source.as_str()), (4, "a_posteriori"));
        assert_near!(s.sigma.unwrap(), 2f64.sqrt(), 1e-15);
        let given = noise_sigma(8.0, 6, 2, Some(0.003));
        assert_eq!(
            (given.sigma, given.source.as_str()),
            (Some(0.003), "a_priori")
        );
        let none = noise_sigma(8.0, 2, 2, None);
        assert_eq!((none.sigma, none.dof), (None, 0));
    }

    /// Columns `a = (1, 1, 0)`, `b = (1, 0, 0)` with weights `(4, 1, 1)`: `Σ w a b = 4`,
    /// `Σ w a² = 5`, `Σ w b² = 4`, cosine `4/√20 = 2/√5` (closed form, 1e-15); the weighted
    /// residual sum of `y − ŷ = (0.5, −1, 2)` over the same weights is `4·0.25 + 1 + 4 = 6` mm².
    #[test]
    fn column_cosine_and_residual_sum_are_weighted() {
        // Two columns of the caller's own (a user's names and unit).
        let user = |n: &str| Parameter::user(n, crate::machine::Unit::Mm, 0.01);
        let design = Design::try_new(
            vec![user("A"), user("B")],
            DMatrix::from_column_slice(3, 2, &[1.0, 1.0, 0.0, 1.0, 0.0, 0.0]),
        )
        .unwrap();
        let used = [0, 1, 2];
        let sqrt_w = [2.0, 1.0, 1.0];
        let c = column_correlations(&design, &used, &sqrt_w, 0.7);
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].a.as_str(), c[0].b.as_str()), ("A", "B"));
        assert_near!(c[0].cosine, 2.0 / 5f64.sqrt(), 1e-15);
        assert!(column_correlations(&design, &used, &sqrt_w, 0.95).is_empty());
        let wss = weighted_residual_sum(&used, &sqrt_w, &[0.5, 0.0, 2.0], &[0.0, 1.0, 0.0]);
        assert_near!(wss, 6.0, 1e-15);
    }

    /// The estimator built a point at a time is, bit for bit, the one built direction by
    /// direction over every point (the loops it replaces), and solves the fit: `M·y` equals the
    /// least-squares solution of a full-rank design (normal equations, to 1e-12 relative).
    /// Four nearly orthogonal columns `cos(jπt)`, `j = 0..3` (every direction resolved), 40 points
    /// with unequal weights.
    #[test]
    fn the_estimator_by_points_is_the_estimator_by_directions() {
        let user = |n: &str| Parameter::user(n, crate::machine::Unit::Mm, 0.01);
        let n = 40;
        let a = DMatrix::from_fn(n, 4, |i, j| {
            let t = i as f64 / n as f64;
            (std::f64::consts::PI * j as f64 * t).cos()
        });
        let design =
            Design::try_new(vec![user("A"), user("B"), user("C"), user("D")], a.clone()).unwrap();
        let y: Vec<f64> = (0..n).map(|i| ((i * 13) % 7) as f64 * 1e-3).collect();
        let obs = Observations::plain(y.clone())
            .with_weights((0..n).map(|i| 1.0 + (i % 3) as f64).collect());
        let f = Factored::new(&design, &obs, &IdentifyOptions::default()).unwrap();
        let m = f.estimator();
        let mut by_directions = DMatrix::<f64>::zeros(4, n);
        for k in 0..f.kept {
            let s = f.s_red[k];
            for j in 0..4 {
                let c = f.basis_xi[(j, k)] / (s * f.svd.scale[j]);
                for r in 0..n {
                    by_directions[(j, r)] += c * f.u_red[(r, k)] * f.sqrt_w[r];
                }
            }
        }
        assert!(m
            .iter()
            .zip(by_directions.iter())
            .all(|(p, q)| p.to_bits() == q.to_bits()));
        // the weighted normal equations' solution
        let w = DMatrix::from_diagonal(&DVector::from_iterator(n, (0..n).map(|i| obs.weight(i))));
        let x = (a.transpose() * &w * &a)
            .lu()
            .solve(&(a.transpose() * &w * DVector::from_vec(y.clone())))
            .unwrap();
        let got = &m * DVector::from_vec(y);
        for j in 0..4 {
            assert_near!(got[j], x[j], 1e-12 * x.amax());
        }
    }

    /// A std above `weak_limit · typical` makes a parameter weak; a group naming it wins.
    #[test]
    fn status_follows_the_std_and_the_groups() {
        assert_eq!(
            status_of("EX0B", Some(0.002), 0.01, &[], 0.25),
            Status::Identified
        );
        assert_eq!(
            status_of("EX0B", Some(0.003), 0.01, &[], 0.25),
            Status::Weak
        );
        assert_eq!(status_of("EX0B", None, 0.01, &[], 0.25), Status::Identified);
    }
}
