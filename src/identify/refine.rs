//! Non-linear refinement of a linear identification with the exact model (Levenberg-Marquardt).
//!
//! The design matrix is the linearisation of eq. 12 at ξ = 0 (paper 000 eq. 13-14). The exact
//! model `f(x)` (deviations at the design rows, mm, and its Jacobian `∂f/∂x`) is given as a
//! closure. **Where it matters**: the linearisation error at the linear solution `x̂`,
//! `e_lin = rms_i (f(x̂) - f(0) - A x̂)_i`, is compared with the noise σ of the identification;
//! only if `e_lin > 0.1 σ` (default fraction) can the non-linearity move the estimate by a
//! noticeable part of its own std, and LM is run. s-shape.md: exact and linearised eq. 12 differ
//! by < 0.1 µm at the magnitudes of real machines, against σ ≈ 1.5 µm, so LM normally is skipped
//! and the report says so.
//!
//! **Where the linearisation no longer holds** (errors orders of magnitude above a real machine's):
//! when `e_lin` exceeds [`NONLINEAR_WARN_FRACTION`] (1 %) of the modelled deviation
//! `rms_i (f(x̂) - f(0))_i`, the report carries a [`RefineReport::warning`] saying so, and whether
//! the exact-model values replace the linear ones (LM converged), are unreliable (LM failed), or
//! the linear ones are kept (the difference is below the noise threshold).
//!
//! LM works in the solved subspace only: `x = x̂ + K z` with `K = D⁻¹ N V'` ([`Factored::kept_basis`]),
//! so the combinations the part cannot separate stay fixed as in the linear solution instead of
//! drifting. Residual `r(z) = W^½ (f(x(z)) - y)` over the used points; Jacobian `W^½ (∂f/∂x) K`.

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Dyn, Owned};
use serde::{Deserialize, Serialize};

use super::report::NONZERO_T;
use super::{
    Design, Factored, Identification, IdentifyError, IdentifyOptions, Observations, ScaledSvd,
    Status,
};

/// Deviations of the exact model at every design row (mm) and its Jacobian (rows x p).
pub type ModelOutput = Result<(Vec<f64>, DMatrix<f64>), ModelError>;

/// Why an exact model could not be evaluated, or gave what the refinement cannot use, with the
/// values involved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// The machine's kinematics or the defect at the points failed.
    #[error(transparent)]
    Sensitivity(#[from] crate::sensitivity::SensitivityError),
    /// The model returned a wrong number of deviations, or non-finite ones.
    #[error(
        "returned {found} deviations (finite values expected) for {points} points and {parameters} parameters"
    )]
    Shape {
        found: usize,
        points: usize,
        parameters: usize,
    },
    /// An evaluation during the minimisation returned a wrong number of deviations, or
    /// non-finite ones.
    #[error("returned {found} deviations (finite values expected) for {points} points")]
    Deviations { found: usize, points: usize },
    /// The Jacobian has the wrong shape.
    #[error("returned a {rows}x{cols} Jacobian for {points} points and {parameters} parameters")]
    Jacobian {
        rows: usize,
        cols: usize,
        points: usize,
        parameters: usize,
    },
    /// A whitened model: the inner model's deviations do not match the whitener.
    #[error("{found} deviations for a {expected}-point whitener")]
    Whitener { found: usize, expected: usize },
    /// The minimiser ended without an evaluation or a Jacobian at its solution.
    #[error("no {0} at the solution")]
    NotEvaluated(&'static str),
}

/// The exact model: deviations at every design row (mm) and the Jacobian (rows x p). Any
/// closure `Fn(&[f64]) -> ModelOutput` is one; implement the trait directly when the
/// deviations alone are much cheaper than the Jacobian (the linearisation check needs only them).
pub trait ExactModel {
    /// Deviations (mm) at the design rows for the parameters `x`.
    fn deviation(&self, x: &[f64]) -> Result<Vec<f64>, ModelError>;
    /// `∂ deviation / ∂x` (rows x p).
    fn jacobian(&self, x: &[f64]) -> Result<DMatrix<f64>, ModelError>;
}

impl<F: Fn(&[f64]) -> ModelOutput> ExactModel for F {
    fn deviation(&self, x: &[f64]) -> Result<Vec<f64>, ModelError> {
        self(x).map(|(f, _)| f)
    }
    fn jacobian(&self, x: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        self(x).map(|(_, j)| j)
    }
}

/// The linear model (eq. 13) and the exact one (eq. 12) disagreeing at the estimate by more than
/// this fraction of the modelled deviation (RMS over the used points) gives a warning.
pub const NONLINEAR_WARN_FRACTION: f64 = 0.01;

/// Options of [`refine`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RefineOptions {
    /// Run LM when the linearisation error exceeds this fraction of σ (default 0.1).
    pub linearisation_fraction: f64,
    /// Run LM whatever the linearisation error.
    pub force: bool,
    /// LM patience (evaluations per parameter + 1, default 100).
    pub patience: usize,
}

impl Default for RefineOptions {
    fn default() -> Self {
        RefineOptions {
            linearisation_fraction: 0.1,
            force: false,
            patience: 100,
        }
    }
}

impl RefineOptions {
    /// Always run LM.
    pub fn forced(mut self) -> Self {
        self.force = true;
        self
    }
}

/// What the refinement did (STYLE rule 5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RefineReport {
    /// Whether LM was run.
    pub performed: bool,
    /// Why it was run or skipped.
    pub reason: String,
    /// `rms(f(x̂) - f(0) - A x̂)` over the used points (mm).
    pub linearisation_error_rms: f64,
    /// σ of the identification (mm) the error was compared with.
    pub sigma: Option<f64>,
    /// LM termination reason (`not run` when skipped).
    pub termination: String,
    /// Whether LM reported success.
    pub success: bool,
    /// Residual evaluations.
    pub evaluations: usize,
    /// `½ Σ w r²` at the end (mm²).
    pub cost: f64,
    /// Unweighted residual RMS at the end (mm).
    pub residual_rms: f64,
    /// Parameter names, values, std (design order).
    pub names: Vec<String>,
    pub values: Vec<f64>,
    pub std: Vec<Option<f64>>,
    /// Covariance (design order).
    pub covariance: Vec<Vec<f64>>,
    /// Condition number of the column-scaled reduced Jacobian.
    pub condition: f64,
    /// Rank of the reduced Jacobian (= kept directions when all is well).
    pub rank: usize,
    /// `rms(f(x̂) - f(0))` over the used points: the deviation the exact model gives the linear
    /// estimate (mm).
    pub modelled_rms: f64,
    /// Set when the linearisation does not hold at the estimate (`linearisation_error_rms` >
    /// [`NONLINEAR_WARN_FRACTION`] x `modelled_rms`): what that means for the values.
    pub warning: Option<String>,
}

/// The warning of a report whose linearisation error is `lin_err` against `modelled` (mm):
/// `None` below [`NONLINEAR_WARN_FRACTION`].
fn nonlinear_warning(lin_err: f64, modelled: f64, outcome: &str) -> Option<String> {
    (lin_err > NONLINEAR_WARN_FRACTION * modelled).then(|| {
        format!(
            "the linearised model (paper 000 eq. 13) differs from the exact eq. 12 by {lin_err:.3e} mm RMS at the estimate, {:.1} % of the modelled deviation {modelled:.3e} mm (limit {:.0} %): the errors are too large for the linear identification; {outcome}",
            100.0 * lin_err / modelled.max(f64::MIN_POSITIVE),
            100.0 * NONLINEAR_WARN_FRACTION
        )
    })
}

struct Problem<'a> {
    /// Behind a trait object: one instance of the minimiser for every model (the page's wasm
    /// held one per model type, 9 kB each).
    model: &'a dyn ExactModel,
    x0: Vec<f64>,
    basis: DMatrix<f64>,
    used: &'a [usize],
    sqrt_w: &'a [f64],
    y: Vec<f64>,
    z: DVector<f64>,
    cache: Option<Vec<f64>>,
    error: std::cell::RefCell<Option<ModelError>>,
}

impl Problem<'_> {
    fn x_of(&self, z: &DVector<f64>) -> Vec<f64> {
        let dx = &self.basis * z;
        self.x0.iter().zip(dx.iter()).map(|(a, b)| a + b).collect()
    }
    fn fail(&self, e: ModelError) {
        self.error.replace(Some(e));
    }
    fn evaluate(&mut self) {
        let x = self.x_of(&self.z);
        self.cache = match self.model.deviation(&x) {
            Ok(f) if f.len() == self.y.len() && f.iter().all(|v| v.is_finite()) => Some(f),
            Ok(f) => {
                self.fail(ModelError::Deviations {
                    found: f.len(),
                    points: self.y.len(),
                });
                None
            }
            Err(e) => {
                self.fail(e);
                None
            }
        };
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, z: &DVector<f64>) {
        self.z.copy_from(z);
        self.evaluate();
    }
    fn params(&self) -> DVector<f64> {
        self.z.clone()
    }
    fn residuals(&self) -> Option<DVector<f64>> {
        let f = self.cache.as_ref()?;
        Some(DVector::from_iterator(
            self.used.len(),
            self.used
                .iter()
                .enumerate()
                .map(|(r, &i)| self.sqrt_w[r] * (f[i] - self.y[i])),
        ))
    }
    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let x = self.x_of(&self.z);
        let j = match self.model.jacobian(&x) {
            Ok(j) if j.nrows() == self.y.len() && j.ncols() == x.len() => j,
            Ok(j) => {
                self.fail(ModelError::Jacobian {
                    rows: j.nrows(),
                    cols: j.ncols(),
                    points: self.y.len(),
                    parameters: x.len(),
                });
                return None;
            }
            Err(e) => {
                self.fail(e);
                return None;
            }
        };
        let ju = DMatrix::from_fn(self.used.len(), j.ncols(), |r, c| {
            self.sqrt_w[r] * j[(self.used[r], c)]
        });
        Some(ju * &self.basis)
    }
}

/// Refines `linear` (from [`super::identify`] on the same design, observations and options)
/// with the exact model, where the linearisation error matters (see the module docs).
pub fn refine<F>(
    design: &Design,
    obs: &Observations,
    linear: &Identification,
    model: F,
    opts: &RefineOptions,
    id_opts: &IdentifyOptions,
) -> Result<RefineReport, IdentifyError>
where
    F: ExactModel,
{
    let f = Factored::new(design, obs, id_opts)?;
    refine_dyn(design, obs, linear, &f, &model, opts, id_opts)
}

/// [`refine`] of the fit whose factored problem is `f` ([`Factored::new`] of the same `design`,
/// `obs` and `id_opts`, as [`crate::identify::identify_factored`] returns it):
/// the same report, without factorising it again.
pub fn refine_factored<F>(
    design: &Design,
    obs: &Observations,
    linear: &Identification,
    f: &Factored,
    model: F,
    opts: &RefineOptions,
    id_opts: &IdentifyOptions,
) -> Result<RefineReport, IdentifyError>
where
    F: ExactModel,
{
    refine_dyn(design, obs, linear, f, &model, opts, id_opts)
}

/// [`refine`] on a model behind a trait object (one instance for every model type).
fn refine_dyn(
    design: &Design,
    obs: &Observations,
    linear: &Identification,
    f: &Factored,
    model: &dyn ExactModel,
    opts: &RefineOptions,
    id_opts: &IdentifyOptions,
) -> Result<RefineReport, IdentifyError> {
    let names = design.names();
    let p = design.cols();
    let x0 = linear.values();
    if x0.len() != p {
        return Err(IdentifyError::LengthMismatch {
            what: "linear solution",
            found: x0.len(),
            expected: p,
        });
    }
    let n = design.rows();
    let check = |v: Vec<f64>| {
        if v.len() != n || v.iter().any(|x| !x.is_finite()) {
            Err(IdentifyError::Model(ModelError::Shape {
                found: v.len(),
                points: n,
                parameters: p,
            }))
        } else {
            Ok(v)
        }
    };
    let f0 = check(
        model
            .deviation(&vec![0.0; p])
            .map_err(IdentifyError::Model)?,
    )?;
    let fx = check(model.deviation(&x0).map_err(IdentifyError::Model)?)?;
    let ax = design.predict(&x0);
    let lin_err = (f
        .used
        .iter()
        .map(|&i| (fx[i] - f0[i] - ax[i]).powi(2))
        .sum::<f64>()
        / f.used.len() as f64)
        .sqrt();
    let modelled_rms =
        (f.used.iter().map(|&i| (fx[i] - f0[i]).powi(2)).sum::<f64>() / f.used.len() as f64).sqrt();
    let sigma = linear.sigma;
    let threshold = opts.linearisation_fraction * sigma.unwrap_or(0.0);
    let needed = lin_err > threshold;
    let base_rms = (f
        .used
        .iter()
        .map(|&i| (obs.deviation[i] - fx[i]).powi(2))
        .sum::<f64>()
        / f.used.len() as f64)
        .sqrt();
    if !(needed || opts.force) || f.kept == 0 {
        let reason = if f.kept == 0 {
            "no identifiable direction: nothing to refine".to_string()
        } else {
            format!(
                "skipped: linearisation error {lin_err:.3e} mm <= {} x sigma = {threshold:.3e} mm",
                opts.linearisation_fraction
            )
        };
        return Ok(RefineReport {
            performed: false,
            reason,
            linearisation_error_rms: lin_err,
            sigma,
            termination: "not run".to_string(),
            success: true,
            evaluations: 0,
            cost: 0.5
                * f.used
                    .iter()
                    .enumerate()
                    .map(|(r, &i)| (f.sqrt_w[r] * (obs.deviation[i] - fx[i])).powi(2))
                    .sum::<f64>(),
            residual_rms: base_rms,
            names,
            values: x0,
            std: linear.parameters.0.iter().map(|q| q.std).collect(),
            covariance: linear.covariance.clone(),
            condition: linear.condition_used,
            rank: linear.rank_used,
            modelled_rms,
            warning: nonlinear_warning(
                lin_err,
                modelled_rms,
                "the linear values are kept (the exact-model refinement was not run)",
            ),
        });
    }
    let reason = if needed {
        format!(
            "run: linearisation error {lin_err:.3e} mm > {} x sigma = {threshold:.3e} mm",
            opts.linearisation_fraction
        )
    } else {
        format!("run on request (linearisation error {lin_err:.3e} mm)")
    };
    let basis = f.kept_basis();
    let mut problem = Problem {
        model,
        x0: x0.clone(),
        basis: basis.clone(),
        used: &f.used,
        sqrt_w: &f.sqrt_w,
        y: obs.deviation.clone(),
        z: DVector::zeros(f.kept),
        cache: None,
        error: std::cell::RefCell::new(None),
    };
    problem.evaluate();
    let (problem, report) = LevenbergMarquardt::new()
        .with_patience(opts.patience)
        .minimize(problem);
    if let Some(e) = problem.error.borrow().clone() {
        return Err(IdentifyError::Model(e));
    }
    let x = problem.x_of(&problem.z);
    let fv = problem
        .cache
        .clone()
        .ok_or(IdentifyError::Model(ModelError::NotEvaluated("evaluation")))?;
    let jz = problem
        .jacobian()
        .ok_or(IdentifyError::Model(ModelError::NotEvaluated("Jacobian")))?;
    let nu = f.used.len();
    let residual_rms = (f
        .used
        .iter()
        .map(|&i| (obs.deviation[i] - fv[i]).powi(2))
        .sum::<f64>()
        / nu as f64)
        .sqrt();
    let wss: f64 = f
        .used
        .iter()
        .enumerate()
        .map(|(r, &i)| (f.sqrt_w[r] * (obs.deviation[i] - fv[i])).powi(2))
        .sum();
    let dof = nu.saturating_sub(f.kept);
    let s = id_opts
        .sigma
        .or((dof > 0).then(|| (wss / dof as f64).sqrt()));
    let js = ScaledSvd::new(&jz);
    let mut covariance = vec![vec![0.0; p]; p];
    let mut std = vec![None; p];
    if let Some(s) = s {
        // Cov_z = σ² D_z⁻¹ V S⁻² Vᵀ D_z⁻¹ over the rank; Cov_x = K Cov_z Kᵀ.
        let r = f.kept;
        let mut cz = DMatrix::zeros(r, r);
        for k in 0..js.rank {
            let v = js.v.column(k);
            let s2 = js.singular[k].powi(2);
            for a in 0..r {
                for b in 0..r {
                    cz[(a, b)] += s * s * v[a] * v[b] / s2 / (js.scale[a] * js.scale[b]);
                }
            }
        }
        let cx = &basis * cz * basis.transpose();
        for a in 0..p {
            for b in 0..p {
                covariance[a][b] = cx[(a, b)];
            }
            std[a] = Some(cx[(a, a)].max(0.0).sqrt());
        }
    }
    let success = report.termination.was_successful();
    let outcome = if success {
        format!(
            "the values are the exact-model refinement's (Levenberg-Marquardt: {:?})",
            report.termination
        )
    } else {
        format!(
            "the exact-model refinement did not converge ({:?}): the values are unreliable",
            report.termination
        )
    };
    Ok(RefineReport {
        performed: true,
        reason,
        linearisation_error_rms: lin_err,
        sigma,
        termination: format!("{:?}", report.termination),
        success,
        evaluations: report.number_of_evaluations,
        cost: report.objective_function,
        residual_rms,
        names,
        values: x,
        std,
        covariance,
        condition: js.condition(),
        rank: js.rank,
        modelled_rms,
        warning: nonlinear_warning(lin_err, modelled_rms, &outcome),
    })
}

/// Writes a refinement into the identification it refined: its linearisation warning as a
/// `WARNING:` note, and, when it ran and converged, the refined values (and the stds of the
/// separable parameters) with a note saying so (`what`: where the exact model was evaluated).
pub fn apply_refinement(identification: &mut Identification, r: &RefineReport, what: &str) {
    if let Some(w) = &r.warning {
        identification.notes.push(format!("WARNING: {w}"));
    }
    if r.performed && r.success {
        for (j, p) in identification.parameters.0.iter_mut().enumerate() {
            p.value = r.values[j];
            if p.status != Status::NotSeparable {
                p.std = r.std[j];
            }
            // t and the non-zero flag follow the refined value and std (as `identify` sets them)
            p.t = p.std.filter(|s| *s > 0.0).map(|s| p.value.abs() / s);
            p.nonzero = p.status == Status::Identified && p.t.is_some_and(|t| t >= NONZERO_T);
        }
        identification.notes.push(format!(
            "values refined with the exact eq. 12{what}: {}",
            r.reason
        ));
    }
}
