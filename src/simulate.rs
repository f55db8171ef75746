//! Synthetic measured parts: the deviations a machine with given errors would leave, plus
//! seeded CMM noise (the twin used by `testpiece simulate`, validation and tests).
//!
//! `deviation = A·x + e` (mm; + = material left, - = overcut): `A` is the linearised design of
//! paper 000 eq. 13-14 (the sensitivity stage's matrix at the measured points, optionally with
//! the tool-radius column -1), `x` the errors (rad; mm for `EX0B` and `dR`), `e_i` Gaussian with
//! σ (mm) from a ChaCha8 stream seeded by `seed`, so the same seed gives the same part natively
//! and in wasm.

use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use thiserror::Error;

use nalgebra::DMatrix;

use crate::identify::refine::ModelError;
use crate::identify::{Design, IdentifyError};
use crate::machine::{AxisValues, Branch, ErrorParam, MachineErrors};
use crate::numerics::parallel::{map, Threads};
use crate::parameter::ParamId;
use crate::part::{builtin_points, MeasurementPoint, SShape};
use crate::sensitivity::defect::{axis_values, DefectPoses};
use crate::sensitivity::error_set::error_set;
use crate::sensitivity::{sensitivity_matrix, Mode, SensitivityError, SensitivityOptions};

/// What can go wrong when simulating a part.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimulateError {
    /// An item of an error list is not `NAME=value`.
    #[error("error list item {index} `{text}`: expected NAME=value, e.g. EX0B=0.03")]
    BadItem { index: usize, text: String },
    /// A value does not parse as a finite number.
    #[error("error list item {index}: value `{text}` of {name} is not a finite number")]
    BadValue {
        index: usize,
        name: String,
        text: String,
    },
    /// The same name is given twice.
    #[error("error list: {name} is given twice")]
    Duplicate { name: String },
    /// The noise σ is negative or not finite.
    #[error("noise sigma {0} mm: expected a finite number >= 0")]
    BadNoise(f64),
    /// A name unknown to the design.
    #[error(transparent)]
    Design(#[from] IdentifyError),
    /// The sensitivity stage failed.
    #[error(transparent)]
    Sensitivity(#[from] SensitivityError),
    /// A parameter the machine's exact defect has no term for (an effect's parameter, a part's
    /// term, a user's column): effects are added by their signatures.
    #[error("`{name}` is not a machine error or dR: the exact defect has no term for it")]
    NotAMachineError { name: String },
}

/// Sensitivity options for a mode and a B branch on paper 000's machine.
pub fn sensitivity_options(mode: Mode, branch: Branch) -> SensitivityOptions {
    SensitivityOptions::default()
        .with_mode(mode)
        .with_branch(branch)
}

/// The design of the 100 built-in points (s-shape.md) for a mode and branch: the Figure-19
/// sensitivity matrix (paper 000 eq. 14) of paper 000's location errors (its error set, derived
/// here), with the tool-radius column `dR` if asked.
pub fn builtin_design(
    mode: Mode,
    branch: Branch,
    tool_radius: bool,
) -> Result<Design, SimulateError> {
    let opts = sensitivity_options(mode, branch);
    let part = SShape::iso();
    let points = builtin_points(&part);
    let errors = error_set(&opts.chain, opts.branch)?.params();
    let q = axis_values(&part, &points, &opts)?;
    let m = sensitivity_matrix(&part, &points, &q, &opts, &errors)?;
    let d = Design::from_sensitivity(&m)?;
    Ok(if tool_radius {
        d.with_tool_radius()?
    } else {
        d
    })
}

/// The exact machined defect (eq. 12) at a set of measurement points for a design's parameters
/// (machine errors; every other column, `dR` contributing `-dR`, an effect's parameter its
/// signature column, linear in its value by definition): the model for
/// [`crate::identify::refine::refine`]. The Jacobian of the location
/// errors is a central finite difference of the exact defect (steps 1e-7 rad, 1e-5 mm; eq. 12 is
/// smooth and nearly linear at these magnitudes); that of a linear column is the column.
pub struct ExactDefectModel {
    /// The points' poses on the flank path, solved once (or why they could not be: reported by
    /// every evaluation, as when they were solved at each one).
    poses: Result<DefectPoses, SensitivityError>,
    points: usize,
    params: Vec<ExactColumn>,
    steps: Vec<f64>,
    /// The threads an evaluation's points and the Jacobian's columns are computed on
    /// ([`ExactDefectModel::at_points_on`]).
    threads: Threads,
}

/// How one design column enters the exact model.
enum ExactColumn {
    /// A location error, through eq. 12.
    Location(ErrorParam),
    /// A term linear in its parameter: the deviation per unit (mm), one value per point.
    Linear(Vec<f64>),
}

impl ExactDefectModel {
    /// The model at the 100 built-in points for the columns of `design` (location errors and
    /// `dR`).
    pub fn new(design: &Design, mode: Mode, branch: Branch) -> Result<Self, SimulateError> {
        let part = SShape::iso();
        let points = builtin_points(&part);
        let opts = sensitivity_options(mode, branch);
        let q = axis_values(&part, &points, &opts)?;
        Self::at_points(design, &part, &points, &q, &opts)
    }

    /// The model at any measurement points of `part` (e.g. those of a CMM file, matched by
    /// projection) whose axis values `q` are solved ([`crate::sensitivity::axis_values`] with
    /// the same `opts`).
    pub fn at_points(
        design: &Design,
        part: &SShape,
        points: &[MeasurementPoint],
        q: &[AxisValues],
        opts: &SensitivityOptions,
    ) -> Result<Self, SimulateError> {
        Self::at_points_on(design, part, points, q, opts, Threads::ONE)
    }

    /// [`ExactDefectModel::at_points`], evaluated on `threads` threads: the points of each
    /// evaluation in blocks ([`DefectPoses::on`]), the Jacobian's columns side by side (each
    /// column is its own two evaluations of eq. 12). The same numbers.
    pub fn at_points_on(
        design: &Design,
        part: &SShape,
        points: &[MeasurementPoint],
        q: &[AxisValues],
        opts: &SensitivityOptions,
        threads: Threads,
    ) -> Result<Self, SimulateError> {
        let mut params = Vec::new();
        for (j, p) in design.parameters().iter().enumerate() {
            params.push(match p.id {
                ParamId::Machine(e) => ExactColumn::Location(e),
                _ => ExactColumn::Linear(design.matrix().column(j).iter().copied().collect()),
            });
        }
        // Finite-difference steps: 1e-7 for an angle, 1e-5 mm otherwise (a linear column needs
        // none: its Jacobian is the column).
        let steps = params
            .iter()
            .map(|c| match c {
                ExactColumn::Location(e) if e.is_angular() => 1e-7,
                _ => 1e-5,
            })
            .collect();
        let poses = DefectPoses::on(part, points, q, opts, threads);
        Ok(ExactDefectModel {
            poses,
            points: points.len(),
            params,
            steps,
            threads,
        })
    }

    /// [`ExactModel::deviation`] with the points on `threads` threads.
    ///
    /// [`ExactModel::deviation`]: crate::identify::refine::ExactModel::deviation
    fn deviation_on(&self, x: &[f64], threads: Threads) -> Result<Vec<f64>, ModelError> {
        let mut e = MachineErrors::none();
        let mut linear = vec![0.0; self.points];
        for (p, v) in self.params.iter().zip(x) {
            match p {
                ExactColumn::Location(p) => e = e.with(*p, *v),
                ExactColumn::Linear(c) => {
                    for (l, ci) in linear.iter_mut().zip(c) {
                        *l += v * ci;
                    }
                }
            }
        }
        let d = self
            .poses
            .as_ref()
            .map_err(Clone::clone)?
            .defect_on(&e, threads)?;
        Ok(d.into_iter().zip(linear).map(|(v, l)| v + l).collect())
    }
}

impl crate::identify::refine::ExactModel for ExactDefectModel {
    fn deviation(&self, x: &[f64]) -> Result<Vec<f64>, ModelError> {
        self.deviation_on(x, self.threads)
    }

    fn jacobian(&self, x: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        // each column on its own: a linear term's is its column, a location error's the
        // central difference of eq. 12
        let column = |&c: &usize| -> Result<Vec<f64>, ModelError> {
            if let ExactColumn::Linear(col) = &self.params[c] {
                return Ok(col.clone());
            }
            let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
            xp[c] += self.steps[c];
            xm[c] -= self.steps[c];
            let one = Threads::ONE;
            let (fp, fm) = (self.deviation_on(&xp, one)?, self.deviation_on(&xm, one)?);
            Ok(fp
                .iter()
                .zip(&fm)
                .map(|(p, m)| (p - m) / (2.0 * self.steps[c]))
                .collect())
        };
        let cols: Vec<usize> = (0..x.len()).collect();
        let mut j = DMatrix::zeros(self.points, x.len());
        for (c, col) in map(self.threads, &cols, column).into_iter().enumerate() {
            for (i, v) in col?.into_iter().enumerate().take(self.points) {
                j[(i, c)] = v;
            }
        }
        Ok(j)
    }
}
/// Reads `EX0B=0.03,EA0B=3e-4` (commas or semicolons; spaces ignored; empty gives none): the
/// names as written, each read into a parameter id ([`ParamId::parse`]) by the caller, who
/// knows what they may name (a CLI argument: the chain's errors and `dR`).
pub fn parse_errors(text: &str) -> Result<Vec<(String, f64)>, SimulateError> {
    let mut out: Vec<(String, f64)> = Vec::new();
    for (k, item) in text
        .split([',', ';'])
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .enumerate()
    {
        let index = k + 1;
        let (name, value) = item.split_once('=').ok_or_else(|| SimulateError::BadItem {
            index,
            text: item.to_string(),
        })?;
        let name = name.trim().to_string();
        if name.is_empty() {
            return Err(SimulateError::BadItem {
                index,
                text: item.to_string(),
            });
        }
        let v: f64 = value
            .trim()
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| SimulateError::BadValue {
                index,
                name: name.clone(),
                text: value.trim().to_string(),
            })?;
        if out.iter().any(|(n, _)| *n == name) {
            return Err(SimulateError::Duplicate { name });
        }
        out.push((name, v));
    }
    Ok(out)
}

/// `A·x + e` at the design rows, `x` from `(parameter, value)` pairs (others 0), `e ~ N(0, σ²)`.
pub fn simulate_deviation(
    design: &Design,
    errors: &[(ParamId, f64)],
    noise_sigma: f64,
    seed: u64,
) -> Result<Vec<f64>, SimulateError> {
    check_noise(noise_sigma)?;
    let x = design.vector_from(errors)?;
    let mut y = design.predict(&x);
    add_noise(&mut y, noise_sigma, seed);
    Ok(y)
}

/// The exact machined defect (eq. 12, [`ExactDefectModel`]) at the 100 built-in points for the
/// errors (location errors and `dR`; others 0), plus the same seeded noise as
/// [`simulate_deviation`]. Differs from the linear one by < 0.3 µm at |ξ| ≤ 3e-4 rad.
pub fn simulate_exact(
    mode: Mode,
    branch: Branch,
    errors: &[(ParamId, f64)],
    noise_sigma: f64,
    seed: u64,
) -> Result<Vec<f64>, SimulateError> {
    use crate::identify::refine::ExactModel;
    check_noise(noise_sigma)?;
    let tool_radius = errors.iter().any(|(id, _)| *id == ParamId::ToolRadius);
    let design = builtin_design(mode, branch, tool_radius)?;
    let x = design.vector_from(errors)?;
    let model = ExactDefectModel::new(&design, mode, branch)?;
    let mut y = model
        .deviation(&x)
        .map_err(|e| SimulateError::Design(IdentifyError::Model(e)))?;
    add_noise(&mut y, noise_sigma, seed);
    Ok(y)
}

/// The exact machined defect (eq. 12) at the 100 built-in points on any chain (`opts`: chain,
/// mode, branch) for any of its location errors (`EY0C`, `EX0C`, …: the whole ISO 230-1 list,
/// [`crate::sensitivity::error_set::full_list`]) and `dR` (contributing `-dR`), plus the same
/// seeded noise as [`simulate_deviation`]: the parts of `testpiece simulate --machine`.
pub fn simulate_on(
    opts: &SensitivityOptions,
    errors: &[(ParamId, f64)],
    noise_sigma: f64,
    seed: u64,
) -> Result<Vec<f64>, SimulateError> {
    let part = SShape::iso();
    simulate_at(
        &part,
        &builtin_points(&part),
        opts,
        errors,
        noise_sigma,
        seed,
    )
}

/// [`simulate_on`] at any points of `part` (a scan's, [`crate::part::ScanLayout`]): the exact
/// eq. 12 defect of the location errors, `-dR`, plus the seeded noise in point order.
pub fn simulate_at(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &SensitivityOptions,
    errors: &[(ParamId, f64)],
    noise_sigma: f64,
    seed: u64,
) -> Result<Vec<f64>, SimulateError> {
    check_noise(noise_sigma)?;
    let mut params: Vec<ErrorParam> = Vec::new();
    let mut values = Vec::new();
    let mut d_r = 0.0;
    for (id, v) in errors {
        match id {
            ParamId::ToolRadius => d_r = *v,
            ParamId::Machine(e) => {
                params.push(*e);
                values.push(*v);
            }
            other => {
                return Err(SimulateError::NotAMachineError { name: other.name() });
            }
        }
    }
    let errors = crate::machine::MachineErrors::from_pairs(&params, &values);
    let mut y = crate::sensitivity::defect(part, points, &errors, opts)?;
    for v in y.iter_mut() {
        *v -= d_r;
    }
    add_noise(&mut y, noise_sigma, seed);
    Ok(y)
}

/// A noise σ (mm) must be finite and ≥ 0.
fn check_noise(sigma: f64) -> Result<(), SimulateError> {
    if sigma.is_finite() && sigma >= 0.0 {
        Ok(())
    } else {
        Err(SimulateError::BadNoise(sigma))
    }
}

/// Adds `σ·z`, `z` standard normal from ChaCha8 seeded by `seed`, in row order.
fn add_noise(y: &mut [f64], sigma: f64, seed: u64) {
    if sigma > 0.0 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        for v in y.iter_mut() {
            let z: f64 = StandardNormal.sample(&mut rng);
            *v += sigma * z;
        }
    }
}
