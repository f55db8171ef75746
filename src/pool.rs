//! Pooled identification: one machine from the points of several measured parts (or repeated
//! measurements of one part), machined on the same machine with the same settings.
//!
//! Model (paper 000 eq. 14 stacked): part `k` with `n_k` matched points has its own design
//! `A_k` (the sensitivity at its own matched `(surface, u, v)`, [`crate::analysis::design_at`])
//! and deviations `y_k` (mm, `(measured − nominal)·N`, + = material left). The machine's location
//! errors `x` are one set shared by every part:
//!
//! ```text
//! [y_1]   [A_1  P_1   0 ] [x  ]
//! [y_2] = [A_2   0   P_2] [z_1] + e,     e ~ N(0, σ² I)
//! [ … ]   [ …           ] [z_2]
//! ```
//!
//! with `z_k` the terms that belong to one part, not to the machine:
//! - `dR[k]` (mm, + = a larger tool; column −1 on part `k`'s rows) when the tool-radius term is
//!   fitted: each part may be cut with another tool or a reground one, so the radius error is a
//!   property of the part's cut, not of the machine;
//! - with `setup_per_part`, the CMM datum alignment of each part (effects.md `setup_error`):
//!   `Rz[k]` (rad, rotation about Z), `Tx[k]`, `Ty[k]` (mm), columns `(ẑ × p)·N = −p_y N_x + p_x N_y`,
//!   `N_x`, `N_y`. Off by default: each part's deviations are already in its own datum frame and
//!   the single-part analysis has no such terms, so pooled and single results stay comparable;
//!   on, it costs three parameters per part and absorbs whatever looks like a rigid-body shift
//!   of one part (e.g. C-axis zero offset, which is identical to `Rz`).
//!
//! No per-part location or offset term is needed otherwise: in `physical` mode each part's origin
//! is set at the reference pose (the tip at the part origin, B = C = 0), which the defect model
//! already subtracts part by part. The stack is solved by [`crate::identify::identify`] (scaled
//! SVD, groups, σ from the pooled residual or the given CMM σ). With `m` parts of the same
//! design the standard deviations shrink by `1/√m`.
//!
//! **Exact refinement** (as for one part, [`crate::identify::refine`]; on unless
//! `refine: false`): the exact model of the stack is, for the rows of part `k`,
//! `f_k(x, z) = d_k(x) + P_k z_k` with `d_k` the exact machined defect (paper 000 eq. 12) at part
//! `k`'s own matched points ([`ExactDefectModel`]) and `P_k z_k` the per-part columns of the
//! stack above. This is sound because the parts share one machine, so one `x` enters every
//! `d_k`, and the per-part terms are the same in both models: `dR[k]` is exactly linear
//! (`−dR`, as in the single-part model); the setup terms are the first-order rigid-body
//! misalignment of the CMM datum (rotation `Rz` ≤ 1e-3 rad: the second-order term
//! `Rz²·|p|/2` ≤ 0.04 µm at 80 mm, kept linear). The Jacobian is `[∂d_k/∂x | P_k]` (finite
//! differences of eq. 12 for the first block, as for one part). LM runs only where the
//! linearisation error exceeds 0.1 σ of the pooled fit, in the subspace the stack determines (so
//! combinations no part separates stay as in the linear solution); a linearisation error above
//! 1 % of the modelled deviation puts a `WARNING:` note on the pooled identification, as for one
//! part.

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::analysis::{
    design_at, measurement_points, sensitivity_options, AnalysisError, AnalysisOptions,
};
use crate::cmm::{read_and_match, ReadOptions};
use crate::effects::prepared::Prepared;
use crate::identify::refine::{
    apply_refinement, refine, ExactModel, ModelError, RefineOptions, RefineReport,
};
use crate::identify::{
    identify, Design, Identification, IdentifyError, IdentifyOptions, Observations, Parameter,
};
use crate::machine::AxisValues;
use crate::parameter::{ParamId, PartTerm};
use crate::part::{MeasurementPoint, SShape};
use crate::simulate::ExactDefectModel;

/// Settings of a pooled identification: those of one analysis plus the per-part setup terms.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(default)]
pub struct PoolOptions {
    #[serde(flatten)]
    pub analysis: AnalysisOptions,
    /// Fit each part's CMM datum alignment (`Rz[k]`, `Tx[k]`, `Ty[k]`).
    pub setup_per_part: bool,
}

/// Failures of a pooled identification.
#[derive(Debug, thiserror::Error)]
pub enum PoolError {
    #[error("pooling needs at least 2 parts, {0} given")]
    TooFew(usize),
    #[error("{name}: {source}")]
    Part {
        name: String,
        #[source]
        source: AnalysisError,
    },
    #[error(
        "{name} has parameters {found:?} but {first} has {expected:?}: pool parts of one machine"
    )]
    Mismatch {
        name: String,
        first: String,
        found: Vec<String>,
        expected: Vec<String>,
    },
    #[error("a known path deviation (budget) belongs to one part's points, not to a pool: analyse the parts one by one")]
    KnownDeviation,
    #[error("pooled identification: {0}")]
    Identify(#[from] IdentifyError),
    #[error("pooled exact-model refinement: {part}: {source}")]
    ExactModel {
        part: String,
        source: crate::simulate::SimulateError,
    },
    #[error("pooled exact-model refinement: {0}")]
    Refine(IdentifyError),
}

/// One part of a pool: its name, design at its own matched points and its observations.
#[derive(Debug, Clone)]
pub struct PoolPart {
    pub name: String,
    /// Design of the machine's parameters at the part's points (without `dR`).
    pub design: Design,
    pub observations: Observations,
    /// Matched feet `(x, y)` and outward normals `(N_x, N_y)` (mm), for the setup columns.
    pub feet: Vec<[f64; 4]>,
    /// The measurement points (surface, `u`, `v`, contact height) of the design rows, for the
    /// exact model of the refinement.
    pub points: Vec<MeasurementPoint>,
    /// Their axis values on the pool's machine (solved once, for the design and the exact
    /// model).
    pub axis_values: Vec<AxisValues>,
    /// Rows the reader excluded at the caller's request.
    pub excluded_rows: usize,
}

/// How one part sits in the pooled fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PooledPart {
    pub name: String,
    /// Its index in the per-part parameter names (`dR[k]`, …), from 1.
    pub index: usize,
    pub points: usize,
    pub excluded_rows: usize,
    /// RMS and mean of the pooled fit's residual on this part's points (mm).
    pub residual_rms: f64,
    pub residual_mean: f64,
}

/// The result of a pooled identification.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PooledIdentification {
    pub version: &'static str,
    pub settings: PoolOptions,
    pub parts: Vec<PooledPart>,
    /// The machine's parameters, shared by every part.
    pub shared: Vec<String>,
    /// The per-part parameters (`dR[k]`, `Rz[k]`, `Tx[k]`, `Ty[k]`).
    pub per_part: Vec<String>,
    /// The identification of the stack (point ids `k:id`), with the exact-model values when the
    /// refinement ran and converged.
    pub identification: Identification,
    /// What the exact-model refinement did (absent when switched off).
    pub refinement: Option<RefineReport>,
}

/// The exact model of the stack (module docs): eq. 12 at each part's points for the shared
/// parameters, plus the per-part columns of the stacked design (linear).
pub struct PooledExactModel {
    /// Each part's exact model over the shared parameters, and its first row in the stack.
    parts: Vec<(ExactDefectModel, usize)>,
    /// The stacked design matrix (its per-part columns are used as they are).
    stacked: DMatrix<f64>,
    shared: usize,
}

impl PooledExactModel {
    /// The model for `parts` stacked as `design` (from [`stack`]).
    pub fn new(parts: &[PoolPart], design: &Design, opts: &PoolOptions) -> Result<Self, PoolError> {
        let sopts = sensitivity_options(&opts.analysis);
        let part = SShape::iso();
        let mut row = 0;
        let mut models = Vec::new();
        for p in parts {
            let m =
                ExactDefectModel::at_points(&p.design, &part, &p.points, &p.axis_values, &sopts)
                    .map_err(|source| PoolError::ExactModel {
                        part: p.name.clone(),
                        source,
                    })?;
            models.push((m, row));
            row += p.design.rows();
        }
        Ok(PooledExactModel {
            parts: models,
            stacked: design.matrix().clone(),
            shared: parts.first().map_or(0, |p| p.design.cols()),
        })
    }

    fn linear_part(&self, x: &[f64]) -> Vec<f64> {
        (0..self.stacked.nrows())
            .map(|i| {
                (self.shared..x.len())
                    .map(|j| self.stacked[(i, j)] * x[j])
                    .sum()
            })
            .collect()
    }
}

impl ExactModel for PooledExactModel {
    fn deviation(&self, x: &[f64]) -> Result<Vec<f64>, ModelError> {
        let mut out = self.linear_part(x);
        for (m, row0) in &self.parts {
            for (i, v) in m.deviation(&x[..self.shared])?.into_iter().enumerate() {
                out[row0 + i] += v;
            }
        }
        Ok(out)
    }

    fn jacobian(&self, x: &[f64]) -> Result<DMatrix<f64>, ModelError> {
        let mut j = self.stacked.clone();
        for (m, row0) in &self.parts {
            let jk = m.jacobian(&x[..self.shared])?;
            for i in 0..jk.nrows() {
                for c in 0..self.shared {
                    j[(row0 + i, c)] = jk[(i, c)];
                }
            }
        }
        Ok(j)
    }
}

/// Reads and matches one file and builds its design (the first stages of
/// [`crate::analysis::analyse`]) on the prepared settings of `opts` ([`crate::analysis::prepare`]).
pub fn pool_part(
    prepared: &Prepared,
    bytes: &[u8],
    name: &str,
    opts: &AnalysisOptions,
) -> Result<PoolPart, PoolError> {
    let wrap = |source: AnalysisError| PoolError::Part {
        name: name.to_string(),
        source,
    };
    let ropts = ReadOptions::default().with_exclude_bad_rows(opts.exclude_bad_rows);
    let matched = read_and_match(bytes, name, &ropts).map_err(|e| wrap(e.into()))?;
    let points = measurement_points(prepared.part(), &matched);
    let plain = AnalysisOptions {
        tool_radius: false,
        ..opts.clone()
    };
    let axis_values = prepared.axis_values(&points).map_err(|e| wrap(e.into()))?;
    let (design, _) = design_at(prepared, &points, &axis_values, &plain).map_err(wrap)?;
    let observations = Observations::new(
        matched.points.iter().map(|p| p.file.id.clone()).collect(),
        points.iter().map(|p| p.curve.name().to_string()).collect(),
        matched.deviations(),
    );
    let feet = matched
        .points
        .iter()
        .map(|p| [p.foot[0], p.foot[1], p.normal[0], p.normal[1]])
        .collect();
    Ok(PoolPart {
        name: name.to_string(),
        design,
        observations,
        feet,
        points,
        axis_values,
        excluded_rows: matched.excluded.len(),
    })
}

/// Stacks the parts' designs and observations with the per-part columns of `opts` (module docs).
/// Returns the stacked design, observations and the names of the per-part parameters.
pub fn stack(
    parts: &[PoolPart],
    opts: &PoolOptions,
) -> Result<(Design, Observations, Vec<String>), PoolError> {
    if parts.len() < 2 {
        return Err(PoolError::TooFew(parts.len()));
    }
    let first = &parts[0];
    let shared: Vec<Parameter> = first.design.parameters().to_vec();
    for p in &parts[1..] {
        if p.design.ids() != first.design.ids() {
            return Err(PoolError::Mismatch {
                name: p.name.clone(),
                first: first.name.clone(),
                found: p.design.names(),
                expected: first.design.names(),
            });
        }
    }
    let mut params = shared.clone();
    let mut per_part = Vec::new();
    let mut terms = Vec::new();
    if opts.analysis.tool_radius {
        terms.push(PartTerm::ToolRadius);
    }
    if opts.setup_per_part {
        terms.extend([
            PartTerm::SetupRotation,
            PartTerm::SetupShiftX,
            PartTerm::SetupShiftY,
        ]);
    }
    for part in 1..=parts.len() {
        for &term in &terms {
            params.push(Parameter::new(
                ParamId::PerPart { part, term },
                term.typical(),
            ));
        }
    }
    per_part.extend(params[shared.len()..].iter().map(Parameter::name));
    let n: usize = parts.iter().map(|p| p.design.rows()).sum();
    let per = per_part.len() / parts.len();
    let mut m = DMatrix::zeros(n, params.len());
    let (mut ids, mut curves, mut dev) = (Vec::new(), Vec::new(), Vec::new());
    let mut row = 0;
    for (k, p) in parts.iter().enumerate() {
        let a = p.design.matrix();
        let col0 = shared.len() + k * per;
        for i in 0..a.nrows() {
            for j in 0..a.ncols() {
                m[(row + i, j)] = a[(i, j)];
            }
            let mut c = col0;
            if opts.analysis.tool_radius {
                m[(row + i, c)] = -1.0;
                c += 1;
            }
            if opts.setup_per_part {
                let [x, y, nx, ny] = p.feet[i];
                m[(row + i, c)] = -y * nx + x * ny;
                m[(row + i, c + 1)] = nx;
                m[(row + i, c + 2)] = ny;
            }
        }
        let o = &p.observations;
        ids.extend(o.ids.iter().map(|id| format!("{}:{id}", k + 1)));
        curves.extend(o.curves.iter().cloned());
        dev.extend(o.deviation.iter().copied());
        row += a.nrows();
    }
    let design = Design::try_new(params, m)?;
    Ok((design, Observations::new(ids, curves, dev), per_part))
}

/// Identifies one machine from several parts already read ([`pool_part`]).
pub fn identify_parts(
    parts: &[PoolPart],
    opts: &PoolOptions,
) -> Result<PooledIdentification, PoolError> {
    let (design, obs, per_part) = stack(parts, opts)?;
    let mut iopts = IdentifyOptions::default();
    if let Some(s) = opts.analysis.noise_sigma {
        if !(s.is_finite() && s > 0.0) {
            return Err(PoolError::Part {
                name: "settings".into(),
                source: crate::settings::NoiseError::BadSigma(s).into(),
            });
        }
        iopts = iopts.with_sigma(s);
    }
    let mut identification = identify(&design, &obs, &iopts)?;
    let refinement = if opts.analysis.refine {
        let model = PooledExactModel::new(parts, &design, opts)?;
        let r = refine(
            &design,
            &obs,
            &identification,
            model,
            &RefineOptions::default(),
            &iopts,
        )
        .map_err(PoolError::Refine)?;
        apply_refinement(&mut identification, &r, " at every part's points");
        Some(r)
    } else {
        None
    };
    identification.notes.push(format!(
        "pooled fit of {} parts ({} points): the machine's parameters are shared; {}",
        parts.len(),
        obs.len(),
        if per_part.is_empty() {
            "no per-part terms".to_string()
        } else {
            format!("per part: {}", per_part.join(", "))
        }
    ));
    let mut out_parts = Vec::new();
    let mut row = 0;
    for (k, p) in parts.iter().enumerate() {
        let n = p.design.rows();
        let r: Vec<f64> = identification.points[row..row + n]
            .iter()
            .map(|q| q.residual)
            .collect();
        let nn = n.max(1) as f64;
        out_parts.push(PooledPart {
            name: p.name.clone(),
            index: k + 1,
            points: n,
            excluded_rows: p.excluded_rows,
            residual_rms: (r.iter().map(|v| v * v).sum::<f64>() / nn).sqrt(),
            residual_mean: r.iter().sum::<f64>() / nn,
        });
        row += n;
    }
    Ok(PooledIdentification {
        version: crate::VERSION,
        settings: opts.clone(),
        parts: out_parts,
        shared: parts[0].design.names(),
        per_part,
        identification,
        refinement,
    })
}

/// Reads, matches and identifies one machine from several CMM files `(bytes, name)` on the
/// prepared settings of `opts.analysis` ([`crate::analysis::prepare`]).
pub fn identify_pooled(
    prepared: &Prepared,
    files: &[(&[u8], &str)],
    opts: &PoolOptions,
) -> Result<PooledIdentification, PoolError> {
    if files.len() < 2 {
        return Err(PoolError::TooFew(files.len()));
    }
    if opts.analysis.known.is_some() {
        return Err(PoolError::KnownDeviation);
    }
    let parts = files
        .iter()
        .map(|(b, n)| pool_part(prepared, b, n, &opts.analysis))
        .collect::<Result<Vec<_>, _>>()?;
    identify_parts(&parts, opts)
}
