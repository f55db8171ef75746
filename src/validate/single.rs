//! The withheld-effect benchmark (`testpiece validate`): simulated parts whose answer is known,
//! diagnosed with the effect withheld from the baseline.
//!
//! Each case is a linear twin of a measured part (the sensitivity and signature columns are
//! linear in their parameters; the exact eq. 12 differs by < 0.2 µm at these magnitudes,
//! s-shape.md): `y = A ξ + S_e θ + ε`, with
//! - machine errors `ξ`: angles uniform in ±3e-4 rad, `EX0B` uniform in ±0.03 mm;
//! - one effect `e` of effects.md (a random direction in its parameter space for multi-parameter
//!   effects), or none, or an effect outside the list: a **waviness** `a·sin(2π s/λ + φ)` along
//!   the tool path (λ uniform in [`WAVE_MIN_MM`]..[`WAVE_MAX_MM`]: with 25 points per curve about
//!   25 mm apart along the path, a shorter waviness is sampled at under 6 points per period and
//!   cannot be told from noise by any test on these points) or a **local bump** `a·exp(−½((s − s₀)/w)²)`
//!   (w uniform in 10..30 mm, s₀ anywhere on the path);
//! - the magnitude set so that the RMS of the part the baseline cannot absorb is
//!   `ρ · 2.5σ` with `ρ` log-uniform in [0.3, 6] (below and above the detection limit);
//! - Gaussian noise `ε`, σ = 1.5 µm;
//! - with `spikes` (`--spikes`), a single-point fault on every case: one point drawn uniformly,
//!   its deviation moved by ±[`SPIKE_MIN_MM`]..[`SPIKE_MAX_MM`] (a chip, dirt, a probing error).
//!
//! Every case is then analysed exactly as a user's file is: [`crate::analysis::fit_points`], the
//! function the CLI and the page run once a file's points are matched, with the model's
//! settings (machine, L0, branch; σ estimated, or the simulated σ with `known_sigma`): the
//! outlier test ([`crate::measurement::outliers`]; the points it names are left out), the
//! diagnosis with the axis reversals of the chain, the baseline fit of the location errors with
//! its exact-model refinement, and the final answer of [`crate::final_fit::correct`] for the
//! verdict (the location errors fitted with the named effect, by generalised least squares with
//! the structure's covariance when `unexplained`, the baseline when `none`), refined likewise.
//! The report counts how often a spike is named and how often another point is; the baseline
//! and the final answer are compared with the simulated `ξ` ([`super::parameter_error`]: largest
//! error in typical units, coverage by 2 std), per case and summarised per group of expected
//! verdict and per effect.
//!
//! [`validate_with`] replaces the linear machine part `A ξ` by any model of it (the CLI's
//! `--exact`: the exact eq. 12 defect of [`crate::simulate::ExactDefectModel`]).
//!
//! Expected verdict: the effect when `ρ > 1` (detectable), `none` when `ρ ≤ 1` or no effect,
//! `unexplained` for a detectable out-of-list effect. A verdict counts as correct when it is the
//! expected id, or when the expected id is listed as equivalent, or when the two are
//! near-equivalent on this part ([`crate::gap::equivalence::EQUIVALENT_COS`]); exact hits are counted
//! too. Cases are assigned in turn: each effect of the list, `none` twice, waviness, bump.

use crate::machine::{Branch, Unit};
use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::parameter_error::{answer_error, AnswerError, ErrorComparison};
use super::ValidateError;
use crate::analysis::{fit_points, sensitivity_options, AnalysisOptions, Diagnosis, PointsModel};
use crate::effects::data::{Candidate, NamedColumns, PointMeta};
use crate::effects::prepared::Prepared;
use crate::effects::GapError;
use crate::final_fit::correct::Basis;
use crate::gap::diagnose::DiagnoseOptions;
use crate::gap::equivalence::near_equivalent_pairs;
use crate::gap::location::DETECT_FACTOR;
use crate::gap::verdict::VerdictId;
use crate::identify::solve::{hstack, rms, Factor};
use crate::identify::{Design, Parameter};
use crate::numerics::random::Sampler;
use crate::parameter::{Effect, ParamId};
use crate::part::{MeasurementPoint, SShape};
use crate::sensitivity::Mode;
use std::sync::Arc;

use super::shapes::{self, Shape, ShapeColumns};

/// Smallest simulated spike (mm).
pub const SPIKE_MIN_MM: f64 = 0.025;
/// Largest simulated spike (mm).
pub const SPIKE_MAX_MM: f64 = 0.040;

pub use super::shapes::{WAVE_MAX_MM, WAVE_MIN_MM};

/// The part a validation simulates: points, baseline design and candidate signatures.
#[derive(Debug, Clone)]
pub struct ValidationModel {
    /// The part and its measurement points, and the settings of the analysis every simulated
    /// part goes through ([`crate::analysis::fit_points`], as the CLI and the page run it).
    pub part: SShape,
    pub measured: Vec<MeasurementPoint>,
    pub settings: AnalysisOptions,
    /// The prepared settings and the measured points' model on them, built once for every
    /// simulated part (as a session keeps them for the files of one design).
    pub prepared: Prepared,
    pub at: Arc<PointsModel>,
    pub points: Vec<PointMeta>,
    pub baseline: NamedColumns,
    pub candidates: Vec<Candidate>,
    /// The columns of the machine-made out-of-list shapes (empty: those shapes are skipped).
    pub shapes: ShapeColumns,
}

impl ValidationModel {
    /// The model of `points` of the part on paper 000's machine (physical mode, signed B), with
    /// every out-of-list shape's columns.
    pub fn at(part: &SShape, points: &[MeasurementPoint]) -> Result<Self, GapError> {
        Self::on(part, points, &AnalysisOptions::default())
    }

    /// The model of `points` of the part on the machine of `settings` (its chain with its L0,
    /// its branch; `physical` mode): that machine's baseline (its location errors) and its
    /// candidates ([`Effect::on_chain`]), with every out-of-list shape's columns the chain has.
    /// Every simulated part is analysed with `settings` (σ estimated unless the validation
    /// passes the simulated one).
    pub fn on(
        part: &SShape,
        points: &[MeasurementPoint],
        settings: &AnalysisOptions,
    ) -> Result<Self, GapError> {
        let settings = AnalysisOptions {
            mode: Mode::Physical,
            ..settings.clone()
        };
        let prepared = Prepared::new(part.clone(), sensitivity_options(&settings))?;
        Self::with_prepared(prepared, points, &settings)
    }

    /// [`ValidationModel::on`] with the settings already prepared (`prepared`: those of
    /// `settings` in `physical` mode, on the part to simulate).
    pub fn with_prepared(
        prepared: Prepared,
        points: &[MeasurementPoint],
        settings: &AnalysisOptions,
    ) -> Result<Self, GapError> {
        let settings = AnalysisOptions {
            mode: Mode::Physical,
            ..settings.clone()
        };
        let at = PointsModel::new(&prepared, points);
        let m = at.part_model()?.clone();
        let shapes = ShapeColumns::at(
            prepared.part(),
            points,
            at.axis_values()?,
            prepared.options(),
        )?;
        Ok(Self {
            part: prepared.part().clone(),
            measured: points.to_vec(),
            settings,
            points: Arc::unwrap_or_clone(m.points),
            baseline: Arc::unwrap_or_clone(m.baseline),
            candidates: m.candidates,
            shapes,
            prepared,
            at: Arc::new(at),
        })
    }

    /// The same model without the out-of-list shapes (their cases are skipped).
    pub fn without_shapes(self) -> Self {
        Self {
            shapes: ShapeColumns::default(),
            ..self
        }
    }

    /// The location errors' design: the baseline's columns with the machine's location errors
    /// (their units and typical sizes from their kinds, [`Parameter::of_error`]).
    pub fn location_design(&self) -> Result<Design, GapError> {
        let errors = self.prepared.errors();
        Ok(Design::try_new(
            errors.iter().map(Parameter::of_error).collect(),
            self.baseline.matrix.clone(),
        )?)
    }

    /// Whether two candidates are near-equivalent on this part (their unabsorbed signatures
    /// span nearly the same directions, [`near_equivalent_pairs`]): the diagnosis may name
    /// either, so a validation counts either as right.
    pub fn near_equivalence(&self) -> impl Fn(Effect, Effect) -> bool {
        let pairs = near_equivalent_pairs(&crate::gap::equivalence::unabsorbed_spans(
            &self.baseline,
            &self.candidates,
        ));
        move |x: Effect, y: Effect| {
            pairs
                .iter()
                .any(|e| (e.a == x && e.b == y) || (e.a == y && e.b == x))
        }
    }
}

/// Options of a validation run.
#[derive(Debug, Clone, Copy)]
pub struct ValidateOptions {
    pub cases: usize,
    pub seed: u64,
    /// Simulated CMM noise (mm).
    pub noise_sigma: f64,
    /// Range of the angular location errors (± rad).
    pub angle_range: f64,
    /// Range of the length location errors (`EX0B`, ± mm).
    pub length_range: f64,
    /// Range of `ρ` = unabsorbed RMS / (k σ).
    pub ratio_min: f64,
    pub ratio_max: f64,
    /// Pass the simulated σ to the diagnosis as the CMM repeatability (default: estimate it).
    pub known_sigma: bool,
    /// `k` of the `k σ` detection rule that sizes the effects (default [`DETECT_FACTOR`], the
    /// diagnosis's own: the cases are analysed with the product's settings, the pairs with this
    /// `k`).
    pub detect_factor: f64,
    /// Add a single-point spike of 25-40 µm at a random point of every case.
    pub spikes: bool,
    /// Noise σ drawn per case uniformly in `noise_sigma..noise_max` (mm) instead of
    /// `noise_sigma` for all.
    pub noise_max: Option<f64>,
    /// The out-of-list shapes, in turn.
    pub shapes: &'static [Shape],
}

impl Default for ValidateOptions {
    fn default() -> Self {
        Self {
            cases: 200,
            seed: 1,
            noise_sigma: 0.0015,
            angle_range: 3e-4,
            length_range: 0.03,
            ratio_min: 0.3,
            ratio_max: 6.0,
            known_sigma: false,
            detect_factor: DETECT_FACTOR,
            spikes: false,
            noise_max: None,
            shapes: &Shape::STANDARD,
        }
    }
}

impl ValidateOptions {
    pub fn with_cases(mut self, n: usize) -> Self {
        self.cases = n;
        self
    }
    pub fn with_seed(mut self, s: u64) -> Self {
        self.seed = s;
        self
    }
    /// The diagnosis options of the cases (default α, this `k`).
    pub fn diagnose_options(&self) -> DiagnoseOptions {
        DiagnoseOptions {
            detect_factor: self.detect_factor,
            ..DiagnoseOptions::default()
        }
    }
    pub fn with_known_sigma(mut self, k: bool) -> Self {
        self.known_sigma = k;
        self
    }
    pub fn with_spikes(mut self, s: bool) -> Self {
        self.spikes = s;
        self
    }
    /// σ uniform in `lo..hi` (mm) per case.
    pub fn with_noise_range(mut self, lo: f64, hi: f64) -> Self {
        self.noise_sigma = lo;
        self.noise_max = Some(hi);
        self
    }
    pub fn with_shapes(mut self, shapes: &'static [Shape]) -> Self {
        self.shapes = shapes;
        self
    }
    pub fn with_ratio(mut self, lo: f64, hi: f64) -> Self {
        self.ratio_min = lo;
        self.ratio_max = hi;
        self
    }
    pub fn with_angle_range(mut self, r: f64) -> Self {
        self.angle_range = r;
        self
    }
}

/// What a simulated case carries (JSON: the effect id, `none`, or the shape's name).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Truth {
    Effect(Effect),
    None,
    /// Out of the list ([`super::shapes`]).
    Shape(Shape),
}

impl Truth {
    pub fn as_str(self) -> &'static str {
        match self {
            Truth::Effect(e) => e.id(),
            Truth::None => "none",
            Truth::Shape(s) => s.as_str(),
        }
    }
}

impl std::fmt::Display for Truth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.as_str())
    }
}

impl Serialize for Truth {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

/// One simulated case and its diagnosis.
#[derive(Debug, Clone, Serialize)]
pub struct CaseResult {
    pub case: usize,
    pub truth: Truth,
    pub parameters: BTreeMap<String, f64>,
    /// `ρ`: RMS of the unabsorbed part over k σ.
    pub ratio: f64,
    pub detectable: bool,
    pub expected: VerdictId,
    pub verdict: VerdictId,
    pub equivalent: Vec<Effect>,
    pub correct: bool,
    pub exact: bool,
    pub rms_before: f64,
    pub rms_after: f64,
    /// Residual RMS when the true effect is fitted (mm).
    pub achievable_rms_after: f64,
    /// σ of the simulated noise (mm).
    pub sigma: f64,
    /// σ the diagnosis used (mm).
    pub sigma_used: f64,
    /// Baseline residual structure beyond noise found by the diagnosis (mm).
    pub structure_rms: f64,
    /// What the final answer was fitted with (by the verdict).
    pub basis: Basis,
    /// The baseline's location errors against the true `ξ` (typical units, 2-std coverage).
    pub baseline_error: AnswerError,
    /// The final answer's location errors against the true `ξ`.
    pub final_error: AnswerError,
    /// The spike added (point id, mm), with `spikes`.
    pub spike: Option<(u32, f64)>,
    /// Ids of the points the outlier test named (left out of the diagnosis).
    pub outliers: Vec<u32>,
}

/// Accuracy of one group of cases.
#[derive(Debug, Clone, Serialize, Default)]
pub struct Accuracy {
    pub cases: usize,
    pub correct: usize,
    pub exact: usize,
    pub rate: f64,
}

impl Accuracy {
    fn add(&mut self, c: &CaseResult) {
        self.cases += 1;
        self.correct += usize::from(c.correct);
        self.exact += usize::from(c.exact);
        self.rate = self.correct as f64 / self.cases as f64;
    }
}

/// What the outlier test did over the cases.
#[derive(Debug, Clone, Serialize, Default)]
pub struct OutlierCounts {
    /// Cases with a spike.
    pub spiked: usize,
    /// Cases whose spike was named.
    pub spike_named: usize,
    /// Cases where a point other than the spike was named.
    pub other_named: usize,
    /// Cases expected `none` (with a spike when `spikes`): verdict `none` and the spike named.
    pub none_cases: usize,
    pub none_and_named: usize,
}

/// Per-effect figures.
#[derive(Debug, Clone, Serialize)]
pub struct EffectRow {
    pub effect: Effect,
    pub detectable: Accuracy,
    pub undetectable: Accuracy,
    /// Parameter magnitude (each parameter alone) whose unabsorbed RMS is k σ.
    pub detection_limit: BTreeMap<String, f64>,
    /// Mean shrink `1 − rms_after/rms_before` over detectable cases, achieved by the verdict
    /// and achievable by fitting the true effect.
    pub shrink_achieved: f64,
    pub shrink_achievable: f64,
    /// Location errors against the truth over the detectable cases of this effect, baseline and
    /// final answer.
    pub parameter_error: ErrorComparison,
}

/// Location errors against the truth per group of expected verdict.
#[derive(Debug, Clone, Serialize, Default)]
pub struct ParameterErrors {
    /// Expected = an effect of the list (detectable single effects).
    pub detectable: ErrorComparison,
    /// Expected `unexplained` (detectable out-of-list effects).
    pub unexplained: ErrorComparison,
    /// Expected `none` (no effect, or one below the detection limit).
    pub none: ErrorComparison,
}

/// The validation report.
#[derive(Debug, Clone, Serialize)]
pub struct ValidationReport {
    pub cases: usize,
    pub seed: u64,
    pub noise_sigma: f64,
    pub known_sigma: bool,
    /// Detectable effects of the list: verdict = the effect (or an equivalent).
    pub detectable: Accuracy,
    /// No effect, or an effect below the detection limit: verdict `none`.
    pub none_or_undetectable: Accuracy,
    /// Detectable effects outside the list: verdict `unexplained`.
    pub out_of_list: Accuracy,
    pub per_effect: Vec<EffectRow>,
    /// How often the outlier test named points.
    pub outliers: OutlierCounts,
    /// `confusion[expected][verdict]` = count.
    pub confusion: BTreeMap<String, BTreeMap<String, usize>>,
    /// The final answer's and the baseline's location errors against the truth, per group.
    pub parameter_error: ParameterErrors,
    pub results: Vec<CaseResult>,
}

/// The machine part of a simulated deviation for the location errors `ξ` (baseline order), mm.
pub type MachinePart<'a> = dyn Fn(&DVector<f64>) -> Result<DVector<f64>, GapError> + 'a;

/// The machine part of the built-in points by the exact eq. 12 defect of
/// [`crate::simulate::ExactDefectModel`] (paper 000's machine, physical mode, signed B), for
/// [`validate_with`].
pub fn exact_machine_part(params: &[ParamId]) -> Result<Box<MachinePart<'static>>, ValidateError> {
    use crate::identify::refine::ExactModel;
    let design = crate::simulate::builtin_design(Mode::Physical, Branch::Signed, false)?;
    let exact = crate::simulate::ExactDefectModel::new(&design, Mode::Physical, Branch::Signed)?;
    let params = params.to_vec();
    Ok(Box::new(move |xi: &DVector<f64>| {
        let pairs: Vec<(ParamId, f64)> = params.iter().cloned().zip(xi.iter().copied()).collect();
        let x = design.vector_from(&pairs)?;
        let d = exact.deviation(&x)?;
        Ok(DVector::from_vec(d))
    }))
}

/// The machine part of `points` (those of `model`) by the exact eq. 12 defect of
/// [`crate::simulate::ExactDefectModel`] on the chain and branch of `opts` (`physical` mode),
/// the location errors `ξ` in the order of `model.baseline`, for [`validate_with`]: the
/// `--exact` of any machine ([`exact_machine_part`] is paper 000's).
pub fn exact_machine_part_on(
    model: &ValidationModel,
    points: Vec<crate::part::MeasurementPoint>,
    opts: &crate::sensitivity::SensitivityOptions,
) -> Result<Box<MachinePart<'static>>, ValidateError> {
    use crate::identify::refine::ExactModel;
    let design = model.location_design()?;
    let opts = opts.clone().with_mode(crate::sensitivity::Mode::Physical);
    let q = crate::sensitivity::axis_values(&model.part, &points, &opts)
        .map_err(|e| ValidateError::from(crate::simulate::SimulateError::from(e)))?;
    let exact =
        crate::simulate::ExactDefectModel::at_points(&design, &model.part, &points, &q, &opts)?;
    Ok(Box::new(move |xi: &DVector<f64>| {
        let d = exact.deviation(xi.as_slice())?;
        Ok(DVector::from_vec(d))
    }))
}

/// Random machine errors: lengths (a parameter in mm: `EX0B`, `EY0C`, `EZ0B`) uniform in
/// ±`length_range` mm, the others (angles) in ±`angle_range` rad; the unit is the parameter's
/// ([`ParamId::unit`]).
pub fn machine_errors(
    params: &[ParamId],
    opts: &ValidateOptions,
    rng: &mut Sampler,
) -> DVector<f64> {
    DVector::from_iterator(
        params.len(),
        params.iter().map(|p| {
            let r = if p.unit() == Unit::Mm {
                opts.length_range
            } else {
                opts.angle_range
            };
            rng.uniform(-r, r)
        }),
    )
}

/// Parameters of candidate `c` in a random direction of its parameter space, scaled so that the
/// part of its effect the baseline (`base`) cannot absorb has an RMS over the points of
/// `unabsorbed_rms` (mm).
pub fn effect_parameters(
    c: &Candidate,
    base: &Factor,
    unabsorbed_rms: f64,
    rng: &mut Sampler,
) -> DVector<f64> {
    let s = &c.signature.matrix;
    let dir = DVector::from_iterator(
        s.ncols(),
        (0..s.ncols()).map(|j| rng.normal() / s.column(j).norm().max(1e-300)),
    );
    let un = base.unabsorbed_vec(&(s * &dir)).norm() / (s.nrows() as f64).sqrt();
    let scale = if un > 0.0 { unabsorbed_rms / un } else { 0.0 };
    dir * scale
}

/// Runs the benchmark on the linear twin (machine part `A ξ`).
pub fn validate(
    model: &ValidationModel,
    opts: &ValidateOptions,
) -> Result<ValidationReport, ValidateError> {
    let a = model.baseline.matrix.clone();
    validate_with(model, opts, &move |xi: &DVector<f64>| Ok(&a * xi))
}

/// Runs the benchmark with the machine part of each simulated part given by `machine` (e.g. the
/// exact eq. 12 defect of [`crate::simulate::ExactDefectModel`]); the diagnosis still fits the
/// linear baseline, so its verdicts are checked against the model it does not use.
pub fn validate_with(
    model: &ValidationModel,
    opts: &ValidateOptions,
    machine: &MachinePart,
) -> Result<ValidationReport, ValidateError> {
    let n = model.points.len();
    let a = &model.baseline.matrix;
    let base = Factor::new(a, None);
    let near = model.near_equivalence();
    let s_path: Vec<f64> = model.points.iter().map(|p| p.s).collect();
    let kinds = model.candidates.len() + 2 + opts.shapes.len();
    let location = model.location_design()?;
    let ids: Vec<String> = model.measured.iter().map(|p| p.id.to_string()).collect();
    let mut rng = Sampler::new(opts.seed);
    let mut results = Vec::with_capacity(opts.cases);
    for case in 0..opts.cases {
        let kind = case % kinds;
        let xi = machine_errors(&model.baseline.params, opts, &mut rng);
        let ratio = rng.log_uniform(opts.ratio_min, opts.ratio_max);
        let sigma = match opts.noise_max {
            Some(hi) => rng.uniform(opts.noise_sigma, hi),
            None => opts.noise_sigma,
        };
        let limit = opts.detect_factor * sigma;
        let mut parameters = BTreeMap::new();
        let (truth, effect, design): (Truth, DVector<f64>, Option<DMatrix<f64>>) =
            if kind < model.candidates.len() {
                let c = &model.candidates[kind];
                let s = &c.signature.matrix;
                let theta = effect_parameters(c, &base, ratio * limit, &mut rng);
                for (j, name) in c.effect.parameter_names().into_iter().enumerate() {
                    parameters.insert(name, theta[j]);
                }
                (Truth::Effect(c.effect), s * &theta, Some(s.clone()))
            } else if kind < model.candidates.len() + 2 {
                (Truth::None, DVector::zeros(n), None)
            } else {
                let shape = opts.shapes[kind - model.candidates.len() - 2];
                match shapes::draw(shape, &s_path, &model.shapes, &mut rng) {
                    Some((unit, params)) => {
                        for (k, v) in params {
                            parameters.insert(k, v);
                        }
                        let un = base.unabsorbed_vec(&unit).norm() / (n as f64).sqrt();
                        let amp = if un > 0.0 {
                            // a gouge always removes material
                            let sign = if shape == Shape::Gouge {
                                1.0
                            } else {
                                rng.sign()
                            };
                            sign * ratio * limit / un
                        } else {
                            0.0
                        };
                        parameters.insert("amplitude".into(), amp);
                        (Truth::Shape(shape), unit * amp, None)
                    }
                    None => (Truth::None, DVector::zeros(n), None),
                }
            };
        let noise = DVector::from_iterator(n, (0..n).map(|_| sigma * rng.normal()));
        let mut y = machine(&xi)? + &effect + &noise;
        let spike = if opts.spikes {
            let i = ((rng.unit() * n as f64) as usize).min(n - 1);
            let size = rng.sign() * rng.uniform(SPIKE_MIN_MM, SPIKE_MAX_MM);
            y[i] += size;
            Some((i, size))
        } else {
            None
        };
        let un_true = base.unabsorbed_vec(&effect).norm() / (n as f64).sqrt();
        let true_ratio = un_true / limit;
        let detectable = truth != Truth::None && true_ratio > 1.0;
        let expected = match truth {
            _ if !detectable => VerdictId::Noise,
            Truth::Effect(e) => VerdictId::Effect(e),
            _ => VerdictId::Unexplained,
        };
        // The part as a user's file would give it, through the analysis the CLI and the page
        // run: outliers, diagnosis, baseline (refined on the exact model) and final answer.
        let settings = AnalysisOptions {
            noise_sigma: opts.known_sigma.then_some(sigma),
            ..model.settings.clone()
        };
        let fit = fit_points(&model.prepared, &model.at, y.as_slice(), &ids, &settings)
            .map_err(|source| ValidateError::Analysis { case, source })?;
        let report = match &fit.diagnosis {
            Diagnosis::Made { report, .. } => report,
            Diagnosis::NotMade { reason } => {
                return Err(ValidateError::NotDiagnosed {
                    case,
                    reason: reason.clone(),
                })
            }
        };
        let named: Vec<usize> = match (&fit.outliers.test, fit.outliers.excluded) {
            (Some(t), true) => t.points.iter().map(|o| o.index).collect(),
            _ => Vec::new(),
        };
        let v = &report.verdict;
        let exact = v.id() == expected;
        let correct = exact
            || match (v.id(), expected) {
                (VerdictId::Effect(got), VerdictId::Effect(want)) => {
                    v.finding.equivalent().contains(&want) || near(got, want)
                }
                // an out-of-list shape that the named effects absorb to below the limit on
                // these points: no test on them can tell the two apart
                (VerdictId::Effect(_), VerdictId::Unexplained) => {
                    absorbed_by(model, a, &v.finding.effects(), &effect) < limit
                }
                _ => false,
            };
        let achievable_rms_after = match &design {
            Some(s) => {
                let f = Factor::new(&hstack(a, s), None);
                rms(f.unabsorbed_vec(&y).as_slice())
            }
            None => v.rms_before,
        };
        results.push(CaseResult {
            case,
            truth,
            parameters,
            ratio: true_ratio,
            detectable,
            expected,
            verdict: v.id(),
            equivalent: v.finding.equivalent().to_vec(),
            correct,
            exact,
            rms_before: v.rms_before,
            rms_after: v.rms_after,
            achievable_rms_after,
            sigma,
            sigma_used: v.sigma,
            structure_rms: report.structure.structure_rms,
            basis: fit.correction.basis,
            baseline_error: answer_error(location.parameters(), &xi, &fit.baseline.identification),
            final_error: answer_error(location.parameters(), &xi, &fit.identification),
            spike: spike.map(|(i, size)| (model.points[i].id, size)),
            outliers: named.iter().map(|&i| model.points[i].id).collect(),
        });
    }
    Ok(summarise(model, opts, &base, results))
}

/// RMS (mm) of what is left of `shape` once the baseline `a` and the signatures of `effects` are
/// fitted to it.
fn absorbed_by(
    model: &ValidationModel,
    a: &DMatrix<f64>,
    effects: &[Effect],
    shape: &DVector<f64>,
) -> f64 {
    let mut x = a.clone();
    for e in effects {
        if let Some(c) = model.candidates.iter().find(|c| c.effect == *e) {
            x = hstack(&x, &c.signature.matrix);
        }
    }
    rms(Factor::new(&x, None).unabsorbed_vec(shape).as_slice())
}

fn summarise(
    model: &ValidationModel,
    opts: &ValidateOptions,
    base: &Factor,
    results: Vec<CaseResult>,
) -> ValidationReport {
    let n = model.points.len() as f64;
    let limit = opts.detect_factor * opts.noise_sigma;
    let mut detectable = Accuracy::default();
    let mut none_or_undetectable = Accuracy::default();
    let mut out_of_list = Accuracy::default();
    let mut confusion: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
    let mut outliers = OutlierCounts::default();
    for r in &results {
        let spike_named = r.spike.is_some_and(|(id, _)| r.outliers.contains(&id));
        if r.spike.is_some() {
            outliers.spiked += 1;
            outliers.spike_named += usize::from(spike_named);
        }
        outliers.other_named += usize::from(
            r.outliers
                .iter()
                .any(|id| r.spike.is_none_or(|(s, _)| s != *id)),
        );
        if r.expected == VerdictId::Noise {
            outliers.none_cases += 1;
            outliers.none_and_named += usize::from(
                r.correct && (r.spike.is_none() && r.outliers.is_empty() || spike_named),
            );
        }
        *confusion
            .entry(r.expected.to_string())
            .or_default()
            .entry(r.verdict.to_string())
            .or_default() += 1;
        match r.expected {
            VerdictId::Noise => none_or_undetectable.add(r),
            VerdictId::Unexplained => out_of_list.add(r),
            VerdictId::Effect(_) => detectable.add(r),
        }
    }
    let per_effect = model
        .candidates
        .iter()
        .map(|c| {
            let mut det = Accuracy::default();
            let mut und = Accuracy::default();
            let (mut sa, mut sb, mut k) = (0.0, 0.0, 0.0);
            for r in results
                .iter()
                .filter(|r| r.truth == Truth::Effect(c.effect))
            {
                if r.detectable {
                    det.add(r);
                    if r.rms_before > 0.0 {
                        sa += 1.0 - r.rms_after / r.rms_before;
                        sb += 1.0 - r.achievable_rms_after / r.rms_before;
                        k += 1.0;
                    }
                } else {
                    und.add(r);
                }
            }
            let u = base.unabsorbed(&c.signature.matrix);
            let detection_limit = c
                .effect
                .parameter_names()
                .into_iter()
                .enumerate()
                .map(|(j, name)| {
                    let un = u.column(j).norm() / n.sqrt();
                    (name, if un > 0.0 { limit / un } else { f64::INFINITY })
                })
                .collect();
            EffectRow {
                effect: c.effect,
                detectable: det,
                undetectable: und,
                detection_limit,
                shrink_achieved: if k > 0.0 { sa / k } else { f64::NAN },
                shrink_achievable: if k > 0.0 { sb / k } else { f64::NAN },
                parameter_error: errors_where(&results, |r| {
                    r.detectable && r.truth == Truth::Effect(c.effect)
                }),
            }
        })
        .collect();
    let parameter_error = ParameterErrors {
        detectable: errors_where(&results, |r| matches!(r.expected, VerdictId::Effect(_))),
        unexplained: errors_where(&results, |r| r.expected == VerdictId::Unexplained),
        none: errors_where(&results, |r| r.expected == VerdictId::Noise),
    };
    ValidationReport {
        cases: results.len(),
        seed: opts.seed,
        noise_sigma: opts.noise_sigma,
        known_sigma: opts.known_sigma,
        detectable,
        none_or_undetectable,
        out_of_list,
        per_effect,
        outliers,
        confusion,
        parameter_error,
        results,
    }
}

/// Baseline and final errors over the cases that satisfy `keep`.
fn errors_where(results: &[CaseResult], keep: impl Fn(&CaseResult) -> bool) -> ErrorComparison {
    ErrorComparison::of(
        results
            .iter()
            .filter(|r| keep(r))
            .map(|r| (&r.baseline_error, &r.final_error)),
    )
}

/// `largest b / f   coverage b / f` of a comparison (typical units, %).
fn error_cells(c: &ErrorComparison) -> String {
    format!(
        "{:>5.2} / {:<5.2}  {:>5.1} / {:<5.1} %",
        c.baseline.median_largest_error,
        c.final_answer.median_largest_error,
        100.0 * c.baseline.coverage,
        100.0 * c.final_answer.coverage
    )
}

/// A plain-text table of a validation report.
pub fn table(r: &ValidationReport) -> String {
    let mut s = format!(
        "validate: {} cases, seed {}, σ = {} µm ({})\n",
        r.cases,
        r.seed,
        r.noise_sigma * 1e3,
        if r.known_sigma {
            "given to the diagnosis"
        } else {
            "estimated by the diagnosis"
        }
    );
    s += &format!(
        "detectable effects named: {}/{} = {:.1} % (exact {})\n",
        r.detectable.correct,
        r.detectable.cases,
        100.0 * r.detectable.rate,
        r.detectable.exact
    );
    s += &format!(
        "none on none/undetectable: {}/{} = {:.1} %\n",
        r.none_or_undetectable.correct,
        r.none_or_undetectable.cases,
        100.0 * r.none_or_undetectable.rate
    );
    s += &format!(
        "unexplained on out-of-list: {}/{} = {:.1} %\n",
        r.out_of_list.correct,
        r.out_of_list.cases,
        100.0 * r.out_of_list.rate
    );
    let o = &r.outliers;
    if o.spiked > 0 {
        s += &format!(
            "spike (25-40 µm at one point) named: {}/{} = {:.1} %; none with the spike named on none/undetectable: {}/{} = {:.1} %\n",
            o.spike_named,
            o.spiked,
            100.0 * o.spike_named as f64 / o.spiked as f64,
            o.none_and_named,
            o.none_cases,
            100.0 * o.none_and_named as f64 / o.none_cases.max(1) as f64
        );
    }
    s += &format!(
        "cases where another point was named an outlier: {}/{}\n",
        o.other_named, r.cases
    );
    s += "location errors against the truth (largest error: median over the cases of max |value - true| \
          in typical units, 1e-4 rad and 0.01 mm; coverage: share of the location errors within 2 std \
          of the true value), baseline / final answer:\n";
    s += "group                  cases  largest error   coverage\n";
    for (name, g) in [
        ("detectable effects", &r.parameter_error.detectable),
        ("unexplained", &r.parameter_error.unexplained),
        ("none", &r.parameter_error.none),
    ] {
        s += &format!("{name:22} {:>5}  {}\n", g.cases, error_cells(g));
    }
    s += "effect          detectable  none-if-below  shrink achieved/achievable  \
          largest error   coverage         detection limit\n";
    for e in &r.per_effect {
        let lim: Vec<String> = e
            .detection_limit
            .iter()
            .map(|(k, v)| format!("{k}={v:.2e}"))
            .collect();
        if e.detectable.cases == 0 && e.detection_limit.iter().all(|(_, v)| v.is_infinite()) {
            // An effect invisible on the machine (its signature is exactly zero there): every
            // part carrying it is a clean part.
            s += &format!(
                "{:15}   —          {:>3}/{:<3}        invisible on this machine: its parts are clean parts\n",
                e.effect, e.undetectable.correct, e.undetectable.cases,
            );
            continue;
        }
        s += &format!(
            "{:15} {:>3}/{:<3}      {:>3}/{:<3}        {:>5.3} / {:<5.3}             {}  {}\n",
            e.effect,
            e.detectable.correct,
            e.detectable.cases,
            e.undetectable.correct,
            e.undetectable.cases,
            e.shrink_achieved,
            e.shrink_achievable,
            error_cells(&e.parameter_error),
            lim.join(" ")
        );
    }
    s += "confusion (expected -> verdict: count)\n";
    for (exp, row) in &r.confusion {
        let cells: Vec<String> = row.iter().map(|(v, c)| format!("{v}:{c}")).collect();
        s += &format!("  {exp:15} -> {}\n", cells.join(" "));
    }
    s
}
