//! One measured part through the whole pipeline, as one call: the page's "analyse" action, the
//! CLI's `identify`, and the tests share it (DESIGN.md: file bytes → cmm → part projection →
//! sensitivity → identify → gap → one report).
//!
//! 1. [`crate::cmm::read_and_match`]: every row read (or reported), every point matched to the
//!    nominal S-shape by projection of its own coordinates, deviation `(measured − nominal)·N`
//!    (mm, + = material left, − = overcut).
//! 2. Each matched point becomes a [`MeasurementPoint`] at its own `(surface, u, v)`, labelled with
//!    the nearer measurement curve (Z = 11 or 25 mm) for grouping; its contact height `h` follows
//!    from `v` (s-shape.md).
//! 3. [`crate::sensitivity::sensitivity_matrix`] at those points: the defect per unit of each
//!    location error of the configured machine (paper 000 eq. 14, mode and branch as set),
//!    optionally with the tool-radius column `−1` (`dR`, mm, + = a larger tool).
//! 4. [`crate::identify::identify`]: weighted least squares, rank, groups, uncertainty; then
//!    [`crate::identify::refine::refine`] with the exact eq. 12 at the same points
//!    ([`crate::simulate::ExactDefectModel`]) where the linearisation error exceeds 0.1 σ.
//!    The machine is a setting ([`MachineChoice`]): paper 000's B head / C table (default),
//!    paper 001's A-B head or paper 002's B-C tilting table; each has its own set of location
//!    errors, derived from what the part sees ([`crate::sensitivity::error_set`]; the design's
//!    columns).
//! 5. [`crate::gap::diagnose`] on the same points ([`diagnose_on_machine`]): the baseline of
//!    effects.md (the chosen machine's location errors, `physical` mode, the chosen branch) and
//!    every candidate effect whose physics the machine has ([`Effect::on_chain`]: paper 001's A-B
//!    head has `backlash_a` and `a_index`, no `backlash_c` or `c_index`; paper 002's tilting table
//!    has no `pivot_length`), whatever the identification's own mode; where the residual lies,
//!    which effect, how far it shrinks.
//!
//! Edge cases (tests/edge_*.rs): non-finite or non-positive `l0` and `noise_sigma` are refused
//! with the value; a refinement whose linear and exact models disagree by more than
//! [`crate::identify::refine::NONLINEAR_WARN_FRACTION`] adds a `WARNING:` note to the
//! identification (with `refine: false` that check is not made).

use nalgebra::DMatrix;
use serde::Serialize;

use crate::cmm::{read_and_match, CmmError, MatchedPart, ReadOptions};
use crate::effects::builtin::{part_model, part_model_on, PartModel};
use crate::effects::{Effect, GapError, GapInput};
use crate::final_fit::correct::{
    correct, shifts, summary, Basis, Correction, CorrectionInput, EffectsChoice, Final,
};
use crate::gap::verdict::VerdictId;
use crate::gap::{diagnose, DiagnosisReport};
use crate::identify::correlated::{whiten, whitened_limit, Whitened, Whitener};
use crate::identify::monte_carlo::CmmMpe;
use crate::identify::refine::{apply_refinement, refine, RefineOptions, RefineReport};
use crate::identify::{
    identify, Design, Identification, IdentifyError, IdentifyOptions, Observations, Parameter,
};
use crate::machine::chain::PAPER000_L0;
use crate::machine::Branch;
use crate::measurement::outliers::{find_outliers, outlier_sentence, without_rows, OutlierTest};
use crate::measurement::repeat::{self, LackOfFit, Measurement, PureError, RepeatError};
use crate::part::{Curve, MeasurementPoint, SShape, Surface};
use crate::sensitivity::{sensitivity_matrix, Mode, SensitivityError, SensitivityOptions};
use crate::settings::{CmmNoise, MachineChoice, NoiseError, NoiseKind};
use crate::simulate::{ExactDefectModel, SimulateError};

/// Settings of an analysis; `Default` is the spec's default (physical mode, signed B, paper
/// 000's machine with L0 = 499.889 mm, no tool-radius term, rows with problems reject the file).
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[serde(default)]
pub struct AnalysisOptions {
    /// The kinematic chain (default paper 000's B head / C table).
    pub machine: MachineChoice,
    /// `physical` (default) or `paper` (s-shape.md "Errors and machined defect").
    pub mode: Mode,
    /// `signed` (default) or `positive` B branch.
    pub branch: Branch,
    /// Pivot-to-tip length of the machine (mm): B axis to tip on paper 000's machine, A axis to
    /// tip (`ls + lt`) on paper 001's; not used by the tilting table of paper 002.
    pub l0: f64,
    /// Fit the tool-radius error `dR` (mm) with the location errors.
    pub tool_radius: bool,
    /// Exclude the rows the reader lists instead of rejecting the file (shown in every result).
    pub exclude_bad_rows: bool,
    /// CMM standard uncertainty of one deviation (mm, 1σ); `None` uses the residual (or
    /// `noise_mpe`).
    pub noise_sigma: Option<f64>,
    /// The CMM's maximum permissible error `MPE_E = A + L/K` µm (and its `R0`), turned into σ by
    /// [`noise_from_mpe`]; not together with `noise_sigma`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise_mpe: Option<CmmMpe>,
    /// Keep the single-point outliers ([`crate::measurement::outliers`]) in the identification and the
    /// diagnosis (they are still found and named).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub keep_outliers: bool,
    /// Refine with the exact eq. 12 where the linearisation error matters (default on).
    pub refine: bool,
    /// Deviation already explained by the process (the CAM path or NC trace of issue 10, mm per
    /// matched point in file order): subtracted from the measured deviations before the
    /// identification and the gap diagnosis, so it is not blamed on the machine.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub known: Option<KnownDeviation>,
    /// Effects fitted with the location errors in the final answer: `auto` (default, what the
    /// diagnosis names), `none` (the baseline), or ids (`--effects`).
    pub effects: EffectsChoice,
}

/// A deviation the process explains, per matched point (mm, + = material left).
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct KnownDeviation {
    /// What it is, in words (e.g. `NC trace trace.csv`), for the report.
    pub source: String,
    /// One value per matched point, in the order of the file's points.
    pub values: Vec<f64>,
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        Self {
            machine: MachineChoice::Paper000,
            mode: Mode::Physical,
            branch: Branch::Signed,
            l0: PAPER000_L0,
            tool_radius: false,
            exclude_bad_rows: false,
            noise_sigma: None,
            noise_mpe: None,
            keep_outliers: false,
            refine: true,
            known: None,
            effects: EffectsChoice::Auto,
        }
    }
}

/// Failures of an analysis, each with the stage's own message.
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    #[error("{0}")]
    File(#[from] CmmError),
    #[error("sensitivity: {0}")]
    Sensitivity(#[from] SensitivityError),
    #[error("identification: {0}")]
    Identify(#[from] IdentifyError),
    #[error("L0 = {0} mm is not a positive finite length")]
    BadL0(f64),
    #[error(transparent)]
    Noise(#[from] NoiseError),
    #[error("exact model: {0}")]
    Exact(#[from] SimulateError),
    #[error("exact-model refinement: {0}")]
    Refine(String),
    #[error("{0}")]
    Correction(GapError),
    #[error("{0}")]
    Repeat(#[from] RepeatError),
    #[error("the CMM noise is given twice: {given} and {repeats} repeat measurements of the part; give the figure or the repeats")]
    SigmaAndRepeats { given: String, repeats: usize },
    #[error(
        "known deviation ({what}): {values} values for {points} matched points, or not finite"
    )]
    Known {
        what: String,
        values: usize,
        points: usize,
    },
}

/// The design at the measured points: one row per point, one column per parameter.
#[derive(Debug, Clone, Serialize)]
pub struct DesignColumns {
    /// Parameter names (`EC0Y` … `EC0B`, then `dR` when fitted).
    pub params: Vec<String>,
    /// `mm` or `rad` per parameter.
    pub units: Vec<String>,
    /// `columns[k][i]`: defect at point `i` per unit of parameter `k` (mm/rad or mm/mm).
    pub columns: Vec<Vec<f64>>,
}

/// Everything one analysis reports.
#[derive(Debug, Clone, Serialize)]
pub struct Analysis {
    pub version: &'static str,
    pub settings: AnalysisOptions,
    /// The file as read and matched: format, points, excluded rows, warnings.
    pub file: MatchedPart,
    /// The measurement points at the matched positions (same order as `file.points`).
    pub points: Vec<MeasurementPoint>,
    /// The design of the final answer: the location errors, then the effect columns fitted
    /// with them (`<id>.<parameter>`), when any.
    pub design: DesignColumns,
    /// The final answer (what every report and export uses): the location errors fitted with
    /// what the diagnosis found ([`crate::final_fit::correct`]).
    pub identification: Identification,
    /// What the exact-model refinement of the final answer did (absent when switched off).
    pub refinement: Option<RefineReport>,
    /// The sim-to-real gap diagnosis, or why it could not be made.
    pub diagnosis: Diagnosis,
    /// How the final answer was obtained: basis, effects included, shift from the baseline.
    pub correction: Correction,
    /// The baseline identification (the location errors alone), as before the diagnosis.
    pub baseline: BaselineFit,
    /// The single-point outliers found, and whether they were left out.
    pub outliers: Outliers,
    /// The σ of the CMM noise the analysis used, and where it came from.
    pub noise: NoiseSource,
    /// Repeat measurements of the part: the pure error and the lack of fit (absent with one
    /// file).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub repeat: Option<RepeatReport>,
}

/// What repeat measurements of the part gave ([`crate::measurement::repeat`]).
#[derive(Debug, Clone, Serialize)]
pub struct RepeatReport {
    /// σ from the differences of the measurements (pure error).
    pub pure_error: PureError,
    /// The lack-of-fit test of the baseline (the location errors alone) against it.
    pub lack_of_fit: LackOfFit,
    /// One sentence for the reports.
    pub summary: String,
}

/// The single-point outliers of an analysis ([`crate::measurement::outliers`]).
#[derive(Debug, Clone, Serialize)]
pub struct Outliers {
    /// Whether the test was made (it needs the diagnosis's part model).
    pub tested: bool,
    /// The test: `points` (`id` as in the file, `curve`, `size` in mm = the deleted residual,
    /// `statistic` = |t|), `rule`, `alpha`, `threshold`, `sigma` (mm), `sigma_source`,
    /// `structured` (points over the bound kept as structure).
    #[serde(flatten)]
    pub test: Option<OutlierTest>,
    /// `true`: the outliers were left out of the identification and the diagnosis (default);
    /// `false`: kept (`keep_outliers`).
    pub excluded: bool,
    /// The verdict of the diagnosis on every point, outliers included (when some were left
    /// out; otherwise the verdict itself).
    pub verdict_all_points: Option<VerdictId>,
    /// One sentence for the reports (empty when there is none).
    pub summary: String,
}

/// The σ of the CMM noise an analysis used.
#[derive(Debug, Clone, Serialize)]
pub struct NoiseSource {
    /// `given` (σ), `mpe` (from the CMM's MPE), `repeat` (σ of the mean of repeat
    /// measurements, from their differences) or `estimated` (from the residual).
    pub source: NoiseKind,
    /// The σ given or from the MPE (mm); `None` when estimated (the diagnosis's own estimate is
    /// `diagnosis.report.verdict.sigma`).
    pub sigma: Option<f64>,
    /// Smallest and largest per-point σ from the MPE (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mpe_range: Option<(f64, f64)>,
    /// One sentence for the reports.
    pub summary: String,
}

/// The σ an analysis uses (checked) and where it came from.
fn noise_source(opts: &AnalysisOptions, lengths: &[f64]) -> Result<NoiseSource, AnalysisError> {
    let noise = CmmNoise::try_new(opts.noise_sigma, opts.noise_mpe.as_ref())?.resolve(lengths);
    let summary = match (noise.sigma, noise.mpe) {
        (Some(med), Some(r)) => format!(
            "Noise: σ = {:.2} µm from the CMM's MPE_E = {} + L/{} µm (R0 = {} µm): \
             σ_i = max(MPE_E(L_i)/√3, R0/1.693) = {:.2}..{:.2} µm over the points \
             (L = distance from the part origin), median used.",
            med * 1e3,
            r.mpe.a_um,
            r.mpe.k_mm,
            r.mpe.r0_um,
            r.lo * 1e3,
            r.hi * 1e3
        ),
        (Some(sigma), None) => format!("Noise: σ = {:.2} µm, as given.", sigma * 1e3),
        (None, _) => "Noise: σ estimated from the residual (no CMM figure given).".to_string(),
    };
    Ok(NoiseSource {
        source: noise.kind,
        sigma: noise.sigma,
        mpe_range: noise.mpe.map(|r| (r.lo, r.hi)),
        summary,
    })
}

/// The baseline identification of an analysis: the location errors alone (`--effects none`).
#[derive(Debug, Clone, Serialize)]
pub struct BaselineFit {
    pub design: DesignColumns,
    pub identification: Identification,
    pub refinement: Option<RefineReport>,
}

/// What an analysis fitted, for further work on the same part (Monte Carlo): the design and
/// the observations of the final identification.
#[derive(Debug, Clone)]
pub struct Fitted {
    pub design: Design,
    pub observations: Observations,
}

impl Analysis {
    /// Distance of each point from the part origin (mm): the length `L` of a CMM's MPE_E.
    pub fn lengths(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.point.norm()).collect()
    }
}

/// The measurement curve (Z = 11 or 25 mm) nearer to height `z` on surface `s`.
pub fn nearest_curve(s: Surface, z: f64) -> Curve {
    let near = |c: &Curve| (c.z() - z).abs();
    Curve::ALL
        .into_iter()
        .filter(|c| c.surface() == s)
        .min_by(|a, b| near(a).total_cmp(&near(b)))
        .unwrap_or(Curve::ALL[0])
}

/// The measurement points of a matched part, at each point's own `(surface, u, v)`.
pub fn measurement_points(part: &SShape, matched: &MatchedPart) -> Vec<MeasurementPoint> {
    matched
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let curve = nearest_curve(p.surface, p.foot[2]);
            let mut m = MeasurementPoint::at(part, i + 1, curve, p.u, p.v);
            m.surface = p.surface;
            m
        })
        .collect()
}

/// The sensitivity settings of an analysis: mode, branch, the chosen chain with its L0.
pub fn sensitivity_options(opts: &AnalysisOptions) -> SensitivityOptions {
    SensitivityOptions::default()
        .with_mode(opts.mode)
        .with_branch(opts.branch)
        .with_chain(opts.machine.chain(opts.l0))
}

/// The effects given to fit (`--effects ID[,ID]`) must exist on the chosen machine
/// ([`Effect::absent_from`]): otherwise [`GapError::NotOnMachine`], naming the machine and why.
pub fn effects_on_machine(opts: &AnalysisOptions) -> Result<(), GapError> {
    let EffectsChoice::Given(effects) = &opts.effects else {
        return Ok(());
    };
    let chain = opts.machine.chain(opts.l0);
    let same = crate::effects::builtin::location_equivalents_of(
        &SShape::iso(),
        &sensitivity_options(opts),
    )?;
    for &effect in effects {
        let located = same
            .iter()
            .find(|(e, _)| *e == effect)
            .map(|(_, r)| r.clone());
        if let Some(reason) = effect.absent_from(&chain).or(located) {
            return Err(GapError::NotOnMachine {
                effect,
                machine: opts.machine.describe().to_string(),
                reason,
            });
        }
    }
    Ok(())
}

/// The sensitivity design at `points` for `opts` (plus the `dR` column when asked).
pub fn design_at(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &AnalysisOptions,
) -> Result<(Design, DesignColumns), AnalysisError> {
    if !(opts.l0.is_finite() && opts.l0 > 0.0) {
        return Err(AnalysisError::BadL0(opts.l0));
    }
    effects_on_machine(opts).map_err(AnalysisError::Correction)?;
    let m = sensitivity_matrix(part, points, &sensitivity_options(opts))?;
    let n = points.len();
    let mut params: Vec<Parameter> = m.params.iter().map(|p| Parameter::named(p)).collect();
    let mut matrix = m.values;
    if opts.tool_radius {
        params.push(Parameter::named(crate::identify::TOOL_RADIUS));
        matrix = matrix.insert_column(params.len() - 1, -1.0);
    }
    debug_assert_eq!(matrix.nrows(), n);
    let design = Design::try_new(params, DMatrix::from(matrix))?;
    let columns = columns_of(&design);
    Ok((design, columns))
}

/// The named columns of a design, as the reports carry them.
pub fn columns_of(design: &Design) -> DesignColumns {
    let m = design.matrix();
    DesignColumns {
        params: design.names(),
        units: design.parameters().iter().map(|p| p.unit.clone()).collect(),
        columns: (0..m.ncols())
            .map(|k| m.column(k).iter().copied().collect())
            .collect(),
    }
}

/// The gap diagnosis (effects.md) of deviations at `points`, on paper 000's machine.
pub fn diagnose_points(
    part: &SShape,
    points: &[MeasurementPoint],
    deviations: &[f64],
    noise_sigma: Option<f64>,
) -> Result<DiagnosisReport, GapError> {
    diagnose_model(&part_model(part, points)?, deviations, noise_sigma)
}

/// The gap diagnosis of an analysis, or why it could not be made (JSON: `status` = `made` or
/// `not_made`).
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Diagnosis {
    Made {
        /// The machine whose errors and axes the diagnosis used (the identification's).
        machine: MachineChoice,
        report: Box<DiagnosisReport>,
    },
    NotMade {
        /// The diagnosis stage's message.
        reason: String,
    },
}

impl Diagnosis {
    /// The report, when the diagnosis was made.
    pub fn report(&self) -> Option<&DiagnosisReport> {
        match self {
            Diagnosis::Made { report, .. } => Some(report),
            Diagnosis::NotMade { .. } => None,
        }
    }
    /// The report, or the reason it could not be made.
    pub fn into_report(self) -> Result<DiagnosisReport, String> {
        match self {
            Diagnosis::Made { report, .. } => Ok(*report),
            Diagnosis::NotMade { reason } => Err(reason),
        }
    }
}

/// The gap diagnosis on the machine the analysis identifies: its own location errors as the
/// baseline, its own candidates ([`Effect::on_chain`]) with their signatures derived from its
/// chain, its own axes for backlash, scale and reversals.
pub fn diagnose_on_machine(
    part: &SShape,
    points: &[MeasurementPoint],
    deviations: &[f64],
    opts: &AnalysisOptions,
) -> Diagnosis {
    diagnose_modelled(part, points, deviations, opts).diagnosis
}

/// A diagnosis with the part model it used, for the final identification.
struct Modelled {
    diagnosis: Diagnosis,
    /// The part model (points, candidates' signatures), when it could be built.
    model: Option<PartModel>,
    /// Effects the machine does not have ([`Effect::left_out`]), and why.
    unavailable: Vec<(Effect, String)>,
    /// The outlier test (when the model could be built) and the rows left out.
    outliers: Option<OutlierTest>,
    excluded: Vec<usize>,
    /// The verdict on every point, when outliers were left out.
    verdict_all_points: Option<VerdictId>,
}

fn diagnose_modelled(
    part: &SShape,
    points: &[MeasurementPoint],
    deviations: &[f64],
    opts: &AnalysisOptions,
) -> Modelled {
    let mut outliers = None;
    let mut excluded = Vec::new();
    let mut verdict_all_points = None;
    // The outliers of the part (named, and left out unless kept), then the diagnosis.
    let mut run = |m: &PartModel| -> Result<DiagnosisReport, GapError> {
        let input = input_of(m, deviations, opts.noise_sigma);
        let test = find_outliers(&input);
        let drop = if opts.keep_outliers {
            Vec::new()
        } else {
            test.indices()
        };
        let sentence = outlier_sentence(&test, opts.keep_outliers);
        outliers = Some(test);
        let all = diagnose(&input)?;
        let mut report = if drop.is_empty() {
            all
        } else {
            verdict_all_points = Some(all.verdict.id());
            diagnose(&without_rows(&input, &drop))?
        };
        if !sentence.is_empty() {
            report.summary = format!("{}\nOutliers: {sentence}\n", report.summary.trim_end());
        }
        if let Some(v) = verdict_all_points {
            report.summary = format!(
                "{}With every point, outliers included, the verdict would be `{v}`.\n",
                report.summary
            );
        }
        excluded = drop;
        Ok(report)
    };
    let made = part_model_on(part, points, &sensitivity_options(opts))
        .and_then(|m| run(&m).map(|report| (report, m)));
    let mut unavailable = Effect::left_out(&opts.machine.chain(opts.l0));
    if let Ok(same) =
        crate::effects::builtin::location_equivalents_of(part, &sensitivity_options(opts))
    {
        unavailable.extend(same);
    }
    match made {
        Ok((report, model)) => Modelled {
            diagnosis: Diagnosis::Made {
                machine: opts.machine,
                report: Box::new(report),
            },
            model: Some(model),
            unavailable,
            outliers,
            excluded,
            verdict_all_points,
        },
        Err(e) => Modelled {
            diagnosis: Diagnosis::NotMade {
                reason: e.to_string(),
            },
            model: None,
            unavailable,
            outliers,
            excluded: Vec::new(),
            verdict_all_points: None,
        },
    }
}

/// The diagnosis's input for a part model and deviations.
fn input_of(m: &PartModel, deviations: &[f64], noise_sigma: Option<f64>) -> GapInput {
    GapInput {
        deviations: deviations.to_vec(),
        points: m.points.clone(),
        baseline: m.baseline.clone(),
        candidates: m.candidates.clone(),
        noise_sigma,
        reversals: m.reversals.clone(),
    }
}

fn diagnose_model(
    m: &PartModel,
    deviations: &[f64],
    noise_sigma: Option<f64>,
) -> Result<DiagnosisReport, GapError> {
    diagnose(&input_of(m, deviations, noise_sigma))
}

/// The measured deviations minus the known ones (issue 10), checked point for point.
fn minus_known(
    mut deviations: Vec<f64>,
    known: Option<&KnownDeviation>,
) -> Result<Vec<f64>, AnalysisError> {
    if let Some(k) = known {
        if k.values.len() != deviations.len() || k.values.iter().any(|v| !v.is_finite()) {
            return Err(AnalysisError::Known {
                what: k.source.clone(),
                values: k.values.len(),
                points: deviations.len(),
            });
        }
        for (d, v) in deviations.iter_mut().zip(&k.values) {
            *d -= v;
        }
    }
    Ok(deviations)
}

/// The sentence the reports carry when a known deviation was subtracted.
fn known_note(k: &KnownDeviation) -> String {
    let max = k.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    format!(
        "The deviation explained by the {} (max |{:.1}| µm) was subtracted from the measurement before the identification and the gap diagnosis: it is not blamed on the machine.",
        k.source,
        max * 1e3
    )
}

/// Reads, matches, identifies and diagnoses one CMM file.
pub fn analyse(
    bytes: &[u8],
    name: &str,
    opts: &AnalysisOptions,
) -> Result<Analysis, AnalysisError> {
    analyse_fitted(bytes, name, opts).map(|(a, _)| a)
}

/// [`analyse`] of the mean of several measurements of one part (the first file, then its
/// repeats: the same point ids measured again). The CMM noise is the pure error of their
/// differences ([`crate::measurement::repeat`]), so neither σ nor an MPE may be given with them; the
/// points, their order and the excluded rows are the first file's.
pub fn analyse_repeats(
    files: &[(&[u8], &str)],
    opts: &AnalysisOptions,
) -> Result<Analysis, AnalysisError> {
    analyse_parts(files, opts).map(|(a, _)| a)
}

/// [`analyse`], and what it fitted.
pub fn analyse_fitted(
    bytes: &[u8],
    name: &str,
    opts: &AnalysisOptions,
) -> Result<(Analysis, Fitted), AnalysisError> {
    analyse_parts(&[(bytes, name)], opts)
}

/// The files read, matched and combined: the first file, its deviations replaced by the mean of
/// the repeats when there are some, and their pure error.
fn read_parts(
    files: &[(&[u8], &str)],
    opts: &AnalysisOptions,
) -> Result<(MatchedPart, Option<PureError>), AnalysisError> {
    let ropts = ReadOptions::default().with_exclude_bad_rows(opts.exclude_bad_rows);
    let mut parts = files
        .iter()
        .map(|(bytes, name)| read_and_match(bytes, name, &ropts))
        .collect::<Result<Vec<_>, _>>()?;
    if parts.len() < 2 {
        return Ok((parts.remove(0), None));
    }
    if opts.noise_sigma.is_some() || opts.noise_mpe.is_some() {
        return Err(AnalysisError::SigmaAndRepeats {
            given: match (opts.noise_sigma, &opts.noise_mpe) {
                (Some(s), _) => format!("σ = {s} mm"),
                (None, Some(m)) => format!("MPE = {} + L/{} µm", m.a_um, m.k_mm),
                (None, None) => unreachable!("checked above"),
            },
            repeats: parts.len(),
        });
    }
    let ids: Vec<Vec<String>> = parts
        .iter()
        .map(|p| p.points.iter().map(|q| q.file.id.clone()).collect())
        .collect();
    let feet: Vec<Vec<[f64; 3]>> = parts
        .iter()
        .map(|p| p.points.iter().map(|q| q.foot).collect())
        .collect();
    let deviations: Vec<Vec<f64>> = parts.iter().map(MatchedPart::deviations).collect();
    let measurements: Vec<Measurement> = (0..parts.len())
        .map(|k| Measurement {
            name: &parts[k].name,
            ids: &ids[k],
            positions: &feet[k],
            deviations: &deviations[k],
        })
        .collect();
    let pe = repeat::pure_error(&measurements)?;
    let mut first = parts.remove(0);
    for (q, m) in first.points.iter_mut().zip(&pe.mean) {
        q.deviation = *m;
    }
    Ok((first, Some(pe)))
}

/// [`analyse_repeats`], and what it fitted: one file (`files.len() == 1`) is [`analyse_fitted`].
pub fn analyse_parts(
    files: &[(&[u8], &str)],
    opts: &AnalysisOptions,
) -> Result<(Analysis, Fitted), AnalysisError> {
    if let Some(s) = opts.noise_sigma {
        if !(s.is_finite() && s > 0.0) {
            return Err(NoiseError::BadSigma(s).into());
        }
    }
    let part = SShape::iso();
    let (matched, pure) = read_parts(files, opts)?;
    let points = measurement_points(&part, &matched);
    let noise = match &pure {
        Some(pe) => NoiseSource {
            source: NoiseKind::Repeat,
            sigma: Some(pe.sigma_mean),
            mpe_range: None,
            // written with the lack of fit, once the baseline is fitted (below)
            summary: String::new(),
        },
        None => noise_source(
            opts,
            &points.iter().map(|p| p.point.norm()).collect::<Vec<_>>(),
        )?,
    };
    // The options the stages see: σ given or from the MPE.
    let opts_in = opts;
    let opts = &AnalysisOptions {
        noise_sigma: noise.sigma,
        noise_mpe: None,
        ..opts.clone()
    };
    let deviations = minus_known(matched.deviations(), opts.known.as_ref())?;
    let ids: Vec<String> = matched.points.iter().map(|p| p.file.id.clone()).collect();
    let PointsFit {
        diagnosis,
        outliers,
        baseline,
        design: final_design,
        identification: mut final_id,
        refinement: final_refinement,
        correction,
        observations: obs,
    } = fit_points(&part, &points, &deviations, &ids, opts)?;
    let mut diagnosis = diagnosis;
    let BaselineFit {
        design: columns,
        mut identification,
        refinement,
    } = baseline;
    let mut noise = noise;
    let repeat = pure.map(|pe| {
        let used: Vec<f64> = identification
            .points
            .iter()
            .filter(|p| p.used)
            .map(|p| p.residual)
            .collect();
        let rss: f64 = used.iter().map(|r| r * r).sum();
        let lack_of_fit = repeat::lack_of_fit(&pe, rss, used.len(), identification.rank_used);
        let summary = repeat::sentence(&pe, &lack_of_fit);
        noise.summary = summary.clone();
        RepeatReport {
            pure_error: pe,
            lack_of_fit,
            summary,
        }
    });
    if let Some(k) = &opts.known {
        let note = known_note(k);
        identification.notes.push(note.clone());
        final_id.notes.push(note.clone());
        if let Diagnosis::Made { report, .. } = &mut diagnosis {
            report.summary = format!("{}\n{note}", report.summary.trim_end());
        }
    }
    for id in [&mut identification, &mut final_id] {
        name_outliers(id, &outliers);
        if noise.source.is_derived() {
            id.notes.push(noise.summary.clone());
        }
    }
    if noise.source.is_derived() {
        if let Diagnosis::Made { report, .. } = &mut diagnosis {
            report.summary = format!("{}\n{}\n", report.summary.trim_end(), noise.summary);
        }
    }
    let analysis = Analysis {
        diagnosis,
        version: crate::VERSION,
        settings: opts_in.clone(),
        outliers,
        noise,
        repeat,
        file: matched,
        points,
        design: columns_of(&final_design),
        identification: final_id,
        refinement: final_refinement,
        correction,
        baseline: BaselineFit {
            design: columns,
            identification,
            refinement,
        },
    };
    Ok((
        analysis,
        Fitted {
            design: final_design,
            observations: obs,
        },
    ))
}

/// The outliers of a diagnosis, named by the file's point ids.
fn outliers_of(m: &Modelled, ids: &[String], kept: bool) -> Outliers {
    let test = m.outliers.clone().map(|mut t| {
        for o in &mut t.points {
            o.id = ids[o.index].clone();
        }
        // `structured` holds the metadata ids (1-based rows): the file's ids instead.
        t.structured = t
            .structured
            .iter()
            .filter_map(|s| s.parse::<usize>().ok())
            .filter_map(|k| ids.get(k.wrapping_sub(1)).cloned())
            .collect();
        t
    });
    let summary = test
        .as_ref()
        .map_or(String::new(), |t| outlier_sentence(t, kept));
    Outliers {
        tested: test.is_some(),
        excluded: !kept && test.as_ref().is_some_and(|t| !t.points.is_empty()),
        verdict_all_points: m
            .verdict_all_points
            .or(m.diagnosis.report().map(|r| r.verdict.id())),
        test,
        summary,
    }
}

/// The reason an outlier left out of `id` is listed under `points_excluded`.
fn name_outliers(id: &mut Identification, outliers: &Outliers) {
    if !outliers.excluded {
        return;
    }
    let Some(t) = &outliers.test else { return };
    for x in &mut id.points_excluded {
        if let Some(o) = t.points.iter().find(|o| o.id == x.id) {
            x.reason = format!(
                "outlier: {:+.1} µm from the fit without it, |t| = {:.1} > {:.2} (Bonferroni α = {} over the points; a chip, dirt or a probing error)",
                o.size * 1e3,
                o.statistic.abs(),
                t.threshold,
                t.alpha
            );
        }
    }
}

/// What one part's points and deviations give through the stages after the reading: the
/// outliers, the diagnosis, the baseline and the final answer ([`fit_points`]).
#[derive(Debug, Clone)]
pub struct PointsFit {
    pub diagnosis: Diagnosis,
    pub outliers: Outliers,
    /// The baseline identification (the location errors alone, refined when the options say).
    pub baseline: BaselineFit,
    /// The final answer's design, identification, refinement and how it was obtained.
    pub design: Design,
    pub identification: Identification,
    pub refinement: Option<RefineReport>,
    pub correction: Correction,
    /// The observations of the final answer (outliers left out with weight 0).
    pub observations: Observations,
}

/// One part through the stages after its points are known, as the CLI, the page and the
/// benchmark of the diagnosis (`validate`) all run it: the design of the location errors at the
/// points ([`design_at`]), the outlier test and the diagnosis ([`diagnose_on_machine`]), the
/// baseline identification and its exact-model refinement, and the final answer fitted with
/// what the diagnosis found. `deviations` (mm) and `ids` follow `points`; `opts.noise_sigma` is
/// the σ to use (`None`: estimated), `opts.noise_mpe` is not read here.
pub fn fit_points(
    part: &SShape,
    points: &[MeasurementPoint],
    deviations: &[f64],
    ids: &[String],
    opts: &AnalysisOptions,
) -> Result<PointsFit, AnalysisError> {
    let (design, columns) = design_at(part, points, opts)?;
    let modelled = diagnose_modelled(part, points, deviations, opts);
    let obs = Observations::new(
        ids.to_vec(),
        points.iter().map(|p| p.curve.name().to_string()).collect(),
        deviations.to_vec(),
    )
    .excluding(&modelled.excluded);
    let mut iopts = IdentifyOptions::default();
    if let Some(s) = opts.noise_sigma {
        iopts = iopts.with_sigma(s);
    }
    let mut identification = identify(&design, &obs, &iopts)?;
    let refinement = if opts.refine {
        let r = refine_with(&design, &obs, &identification, points, opts, &iopts, None)?;
        apply_refinement(&mut identification, &r, "");
        Some(r)
    } else {
        None
    };
    let outliers = outliers_of(&modelled, ids, opts.keep_outliers);
    let diagnosis = modelled.diagnosis;
    let (final_design, final_id, final_refinement, correction) = final_answer(
        FinalInput {
            design: &design,
            observations: &obs,
            baseline: &identification,
            baseline_refinement: refinement.as_ref(),
            points,
            model: modelled.model.as_ref(),
            verdict: diagnosis.report().map(|r| &r.verdict),
            unavailable: &modelled.unavailable,
        },
        opts,
        &iopts,
    )?;
    Ok(PointsFit {
        diagnosis,
        outliers,
        baseline: BaselineFit {
            design: columns,
            identification,
            refinement,
        },
        design: final_design,
        identification: final_id,
        refinement: final_refinement,
        correction,
        observations: obs,
    })
}

/// The exact-model refinement of a fit of `design` (plain, or whitened by `whitener`).
fn refine_with(
    design: &Design,
    obs: &Observations,
    linear: &Identification,
    points: &[MeasurementPoint],
    opts: &AnalysisOptions,
    iopts: &IdentifyOptions,
    whitener: Option<&Whitener>,
) -> Result<RefineReport, AnalysisError> {
    let model = ExactDefectModel::at_points(design, points.to_vec(), sensitivity_options(opts))?;
    let r = match whitener {
        None => refine(design, obs, linear, model, &RefineOptions::default(), iopts),
        Some(w) => {
            let (wd, wobs) = whiten(design, obs, w)?;
            let model = Whitened { model, whitener: w };
            let limit = whitened_limit(design, &wd, iopts);
            refine(
                &wd,
                &wobs,
                linear,
                model,
                &RefineOptions::default(),
                &iopts
                    .clone()
                    .with_sigma(1.0)
                    .with_condition_index_limit(limit),
            )
        }
    };
    r.map_err(|e| AnalysisError::Refine(e.to_string()))
}

/// What the final identification starts from.
struct FinalInput<'a> {
    design: &'a Design,
    observations: &'a Observations,
    baseline: &'a Identification,
    baseline_refinement: Option<&'a RefineReport>,
    points: &'a [MeasurementPoint],
    model: Option<&'a PartModel>,
    verdict: Option<&'a crate::gap::verdict::Verdict>,
    unavailable: &'a [(Effect, String)],
}

/// The final answer ([`crate::final_fit::correct`]), refined with the exact model like the baseline.
fn final_answer(
    f: FinalInput,
    opts: &AnalysisOptions,
    iopts: &IdentifyOptions,
) -> Result<(Design, Identification, Option<RefineReport>, Correction), AnalysisError> {
    let no_candidates: Vec<crate::effects::Candidate> = Vec::new();
    let no_points: Vec<crate::effects::PointMeta> = Vec::new();
    let input = CorrectionInput {
        design: f.design,
        observations: f.observations,
        baseline: f.baseline,
        points: f.model.map_or(&no_points, |m| &m.points),
        candidates: f.model.map_or(&no_candidates, |m| &m.candidates),
        verdict: f.verdict,
        unavailable: f.unavailable,
        options: iopts,
    };
    let fin = correct(&input, &opts.effects).map_err(AnalysisError::Correction)?;
    let Final {
        design,
        mut identification,
        whitener,
        mut correction,
    } = fin;
    let refinement = match correction.basis {
        Basis::Baseline => f.baseline_refinement.cloned(),
        _ if opts.refine => {
            let r = refine_with(
                &design,
                f.observations,
                &identification,
                f.points,
                opts,
                iopts,
                whitener.as_ref(),
            )?;
            apply_refinement(&mut identification, &r, "");
            if r.performed && r.success {
                correction.shift = shifts(f.baseline, &identification);
                correction.summary = summary(&correction, f.baseline, &identification);
            }
            Some(r)
        }
        _ => None,
    };
    Ok((design, identification, refinement, correction))
}

#[cfg(test)]
mod tests {
    use super::*;

    const CLEAN: &str = include_str!("../tests/data/reference/examples/example_clean.csv");

    #[test]
    fn the_clean_example_matches_the_builtin_points_and_their_design() {
        let a = analyse(
            CLEAN.as_bytes(),
            "example_clean.csv",
            &AnalysisOptions::default(),
        )
        .unwrap();
        assert_eq!(a.points.len(), 100);
        let part = SShape::iso();
        let builtin = crate::part::builtin_points(&part);
        // The file's points are the built-in ones written with 6 decimals: the projection finds
        // the same (u, v) to the rounding of the file (5e-7 mm over |dS/du| ≈ 650 mm).
        for (p, q) in a.points.iter().zip(&builtin) {
            assert_eq!(p.curve, q.curve);
            assert!(
                (p.u - q.u).abs() < 1e-8,
                "id {}: u {} vs {}",
                q.id,
                p.u,
                q.u
            );
            assert!((p.h - q.h).abs() < 1e-6);
        }
        assert_eq!(a.design.params.len(), 8);
        assert_eq!(a.identification.points_used, 100);
    }

    #[test]
    fn tool_radius_term_adds_a_minus_one_column() {
        let o = AnalysisOptions {
            tool_radius: true,
            ..Default::default()
        };
        let a = analyse(CLEAN.as_bytes(), "example_clean.csv", &o).unwrap();
        assert_eq!(a.design.params.last().map(String::as_str), Some("dR"));
        assert!(a.design.columns[8].iter().all(|&v| v == -1.0));
    }

    #[test]
    fn the_examples_get_their_keyed_verdicts_through_the_whole_pipeline() {
        // Keys: tests/data/reference/examples/*.key.json (`accept`).
        for (file, text, accept) in [
            ("example_clean.csv", CLEAN, &["none"][..]),
            (
                "example_tool_radius.csv",
                include_str!("../tests/data/reference/examples/example_tool_radius.csv"),
                &["tool_radius", "tool_taper"][..],
            ),
            (
                "example_backlash_c.csv",
                include_str!("../tests/data/reference/examples/example_backlash_c.csv"),
                &["backlash_c"][..],
            ),
        ] {
            let a = analyse(text.as_bytes(), file, &AnalysisOptions::default()).unwrap();
            let d = a.diagnosis.report().unwrap();
            assert!(
                accept.contains(&d.verdict.id().as_str()),
                "{file}: {}",
                d.verdict.id()
            );
            assert!(d.summary.starts_with("Verdict: "), "{file}: {}", d.summary);
        }
    }

    #[test]
    fn each_machine_analyses_the_clean_example_with_its_own_error_set() {
        // The three chains of the page; each design has one column per error of the chain's
        // set (sensitivity::error_set) and a finite fit at all 100 points.
        for m in [
            MachineChoice::Paper000,
            MachineChoice::Paper001,
            MachineChoice::Paper002,
        ] {
            let o = AnalysisOptions {
                machine: m,
                ..Default::default()
            };
            let a = analyse(CLEAN.as_bytes(), "example_clean.csv", &o).unwrap();
            let set = crate::sensitivity::error_set::error_set(&m.chain(o.l0), o.branch).unwrap();
            assert_eq!(a.design.params, set.kept, "{m:?}");
            assert_eq!(a.identification.points_used, 100);
            assert!(a.identification.residual.rms.is_finite(), "{m:?}");
        }
    }

    #[test]
    fn a_known_deviation_is_subtracted_before_identification() {
        // Subtracting the measured deviation itself leaves nothing for the machine: every
        // fitted value and residual is 0, and the reports say what was subtracted.
        let base = analyse(CLEAN.as_bytes(), "c.csv", &AnalysisOptions::default()).unwrap();
        let o = AnalysisOptions {
            known: Some(KnownDeviation {
                source: "test path".into(),
                values: base.file.deviations(),
            }),
            ..Default::default()
        };
        let a = analyse(CLEAN.as_bytes(), "c.csv", &o).unwrap();
        assert!(a
            .identification
            .points
            .iter()
            .all(|p| p.measured.abs() < 1e-15));
        assert!(a.identification.residual.max_abs < 1e-12);
        assert!(a
            .identification
            .notes
            .iter()
            .any(|n| n.contains("test path")));
        // a known shift moves the fit's input by exactly that shift
        let o = AnalysisOptions {
            known: Some(KnownDeviation {
                source: "shift".into(),
                values: vec![0.001; 100],
            }),
            refine: false,
            ..Default::default()
        };
        let b = analyse(CLEAN.as_bytes(), "c.csv", &o).unwrap();
        for (p, q) in b
            .identification
            .points
            .iter()
            .zip(&base.identification.points)
        {
            crate::assert_near!(p.measured, q.measured - 0.001, 1e-15);
        }
        let bad = AnalysisOptions {
            known: Some(KnownDeviation {
                source: "short".into(),
                values: vec![0.0; 3],
            }),
            ..Default::default()
        };
        let e = analyse(CLEAN.as_bytes(), "c.csv", &bad).unwrap_err();
        assert!(
            e.to_string().contains("3 values for 100 matched points"),
            "{e}"
        );
    }

    #[test]
    fn bad_settings_are_named() {
        let o = AnalysisOptions {
            l0: -1.0,
            ..Default::default()
        };
        let e = analyse(CLEAN.as_bytes(), "x.csv", &o).unwrap_err();
        assert_eq!(e.to_string(), "L0 = -1 mm is not a positive finite length");
    }
}
