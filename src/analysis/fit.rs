//! One part through the stages after its points are known: what the CLI, the page and
//! `validate` all run.

use crate::effects::prepared::Prepared;
use crate::final_fit::correct::{basis_of, Basis, Correction, EffectsChoice};
use crate::identify::refine::{apply_refinement, RefineReport};
use crate::identify::{identify_factored, Design, Identification, IdentifyOptions, Observations};
use crate::numerics::parallel::join;

use super::diagnosis::{diagnose_modelled, Diagnosis};
use super::error::AnalysisError;
use super::final_answer::{baseline_spread, final_answer, refine_with, FinalInput, Fitted};
use super::options::AnalysisOptions;
use super::outliers::outliers_of;
use super::points::design_of_points;
use super::progress::{silent, Progress, Sink, Stage};
use super::report::{BaselineFit, Outliers};
use super::session::PointsModel;

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
/// points ([`design_of_points`]), the outlier test and the diagnosis ([`diagnose_on_machine`]), the
/// baseline identification and its exact-model refinement, and the final answer fitted with
/// what the diagnosis found. `prepared` are the settings of `opts` (machine, L0, branch, mode),
/// `at` the model of the points on them ([`PointsModel`]); `deviations` (mm) and `ids` follow
/// its points; `opts.noise_sigma` is the CMM's share of σ, a floor (`None`: σ estimated),
/// `opts.noise_mpe` is not read here.
///
/// [`diagnose_on_machine`]: super::diagnose_on_machine
pub fn fit_points(
    prepared: &Prepared,
    at: &PointsModel,
    deviations: &[f64],
    ids: &[String],
    opts: &AnalysisOptions,
) -> Result<PointsFit, AnalysisError> {
    fit_points_with(prepared, at, deviations, ids, opts, &mut silent)
}

/// [`fit_points`], each [`Stage`] from the design on reported to `progress` as it begins.
pub fn fit_points_with(
    prepared: &Prepared,
    at: &PointsModel,
    deviations: &[f64],
    ids: &[String],
    opts: &AnalysisOptions,
    progress: Sink,
) -> Result<PointsFit, AnalysisError> {
    progress(Progress::of(Stage::Design));
    let (design, columns) = design_of_points(prepared, at, opts)?;
    progress(Progress::of(Stage::Diagnose));
    let modelled = diagnose_modelled(prepared, at, deviations, opts);
    let obs = Observations::new(ids.to_vec(), at.labels(), deviations.to_vec())
        .excluding(&modelled.excluded);
    let mut iopts = IdentifyOptions::default();
    // With the CMM's share given, the std use the total σ the diagnosis found: that share, or
    // with the part's own scatter added ([`crate::measurement::noise::NoiseEstimate`]).
    if let Some(s) = opts.noise_sigma {
        let total = modelled
            .diagnosis
            .report()
            .map_or(s, |r| r.structure.noise.used);
        iopts = iopts.with_sigma(total);
    }
    let outliers = outliers_of(&modelled, ids, opts.keep_outliers);
    let diagnosis = modelled.diagnosis;
    // the candidates at the shapes the diagnosis fitted (a backlash's lag, a warm-up)
    let shaped = modelled
        .model
        .as_deref()
        .map_or_else(Vec::new, |m| match diagnosis.report() {
            Some(r) => crate::gap::which::at_fitted_shapes(
                &m.candidates,
                &r.candidates,
                r.pair
                    .as_ref()
                    .filter(|_| r.verdict.finding.with().is_some()),
            ),
            None => m.candidates.clone(),
        });
    let verdict = diagnosis.report().map(|r| &r.verdict);
    let mut input = FinalInput {
        candidates: &shaped,
        design: &design,
        observations: &obs,
        model: modelled.model.as_deref(),
        verdict,
        noise_sigma: diagnosis.report().map(|r| r.structure.noise.used),
        unavailable: &modelled.unavailable,
        spread: None,
    };
    // When the final answer will be the baseline (verdict `none`), the model spread about it
    // needs nothing of the baseline's identification: it is computed beside it (the
    // identification and its refinement are mostly one thread's work, issue 31); the verdict
    // it is computed with, when it is
    let spread_beside = verdict.filter(|_| {
        opts.effects == EffectsChoice::Auto
            && input.model.is_some()
            && basis_of(verdict, &modelled.unavailable, &opts.effects) == Basis::Baseline
    });
    progress(Progress::of(Stage::Identify));
    let (baseline, spread) = join(
        opts.threads,
        || -> Result<_, AnalysisError> {
            let (mut identification, factored) = identify_factored(&design, &obs, &iopts)?;
            let refinement = if opts.refine {
                let plain = Fitted::Plain(Some(&factored));
                let r = refine_with(prepared, at, &design, &obs, &identification, &iopts, plain)?;
                apply_refinement(&mut identification, &r, "");
                Some(r)
            } else {
                None
            };
            Ok((identification, refinement))
        },
        || spread_beside.map(|v| baseline_spread(&input, v, opts.threads)),
    );
    let (identification, refinement) = baseline?;
    input.spread = spread;
    progress(Progress::of(Stage::FinalFit));
    let (final_design, final_id, final_refinement, correction) = final_answer(
        input,
        &identification,
        refinement.as_ref(),
        prepared,
        at,
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
