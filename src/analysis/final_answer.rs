//! The final answer, refined with the exact model like the baseline.

use crate::effects::builtin::PartModel;
use crate::effects::prepared::Prepared;
use crate::final_fit::correct::{
    correct, shifts, summary, Basis, Correction, CorrectionInput, EffectsChoice, Final,
};
use crate::final_fit::model_spread::model_spread;
use crate::identify::correlated::{whiten, whitened_limit, Whitened, Whitener};
use crate::identify::refine::{apply_refinement, refine, RefineOptions, RefineReport};
use crate::identify::{Design, Identification, IdentifyOptions, Observations};
use crate::identify::{Status, NONZERO_T};
use crate::parameter::Effect;
use crate::simulate::ExactDefectModel;

use super::error::AnalysisError;
use super::options::AnalysisOptions;
use super::session::PointsModel;

/// The exact-model refinement of a fit of `design` (plain, or whitened by `whitener`) at the
/// points of `at`, on the prepared settings (their chain, branch and mode).
pub(super) fn refine_with(
    prepared: &Prepared,
    at: &PointsModel,
    design: &Design,
    obs: &Observations,
    linear: &Identification,
    iopts: &IdentifyOptions,
    whitener: Option<&Whitener>,
) -> Result<RefineReport, AnalysisError> {
    let model = ExactDefectModel::at_points(
        design,
        prepared.part(),
        at.points(),
        at.axis_values()?,
        prepared.options(),
    )?;
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
    r.map_err(AnalysisError::Refine)
}

/// What the final identification starts from.
pub(super) struct FinalInput<'a> {
    pub(super) design: &'a Design,
    pub(super) observations: &'a Observations,
    pub(super) baseline: &'a Identification,
    pub(super) baseline_refinement: Option<&'a RefineReport>,
    pub(super) model: Option<&'a PartModel>,
    /// The model's candidates at the shapes the diagnosis fitted.
    pub(super) candidates: &'a [crate::effects::Candidate],
    pub(super) verdict: Option<&'a crate::gap::verdict::Verdict>,
    /// The part's noise σ of the diagnosis (mm).
    pub(super) noise_sigma: Option<f64>,
    pub(super) unavailable: &'a [(Effect, String)],
}

/// The final answer ([`crate::final_fit::correct`]), refined with the exact model like the baseline.
pub(super) fn final_answer(
    f: FinalInput,
    prepared: &Prepared,
    at: &PointsModel,
    opts: &AnalysisOptions,
    iopts: &IdentifyOptions,
) -> Result<(Design, Identification, Option<RefineReport>, Correction), AnalysisError> {
    let no_points: Vec<crate::effects::PointMeta> = Vec::new();
    let input = CorrectionInput {
        design: f.design,
        observations: f.observations,
        baseline: f.baseline,
        points: f.model.map_or(&no_points, |m| &m.points),
        candidates: f.candidates,
        verdict: f.verdict,
        noise_sigma: f.noise_sigma,
        unavailable: f.unavailable,
        options: iopts,
        decompositions: at.decompositions(),
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
                prepared,
                at,
                &design,
                f.observations,
                &identification,
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
    if opts.effects == EffectsChoice::Auto {
        if let (Some(_), Some(v)) = (f.model, f.verdict) {
            widen_by_model_spread(&f, v, &design, &mut identification, &mut correction);
        }
    }
    Ok((design, identification, refinement, correction))
}

/// The location errors' std widened by what the choice among the candidate models can move
/// them by ([`model_spread`]), about the chosen model's estimate.
fn widen_by_model_spread(
    f: &FinalInput,
    v: &crate::gap::verdict::Verdict,
    design: &Design,
    identification: &mut Identification,
    correction: &mut Correction,
) {
    let obs = f.observations;
    let used: Vec<usize> = (0..obs.len()).filter(|&i| obs.weight(i) > 0.0).collect();
    let a = f.design.matrix();
    let p = a.ncols();
    let added = design.matrix().ncols().saturating_sub(p);
    let chosen = (correction.basis == Basis::Effects && added > 0)
        .then(|| design.matrix().columns(p, added).into_owned());
    let spread = model_spread(
        a,
        &f.design.names(),
        &obs.deviation,
        &used,
        f.candidates,
        chosen.as_ref(),
        v.sigma,
    );
    let mut widened = 0;
    for pe in identification.parameters.0.iter_mut() {
        let (Some(std), Some(extra)) = (pe.std, spread.std.get(&pe.name())) else {
            continue;
        };
        let new = std.hypot(*extra);
        if new > std {
            widened += 1;
        }
        pe.std = Some(new);
        pe.t = Some(pe.value.abs() / new);
        pe.nonzero = pe.status == Status::Identified && pe.t.is_some_and(|t| t >= NONZERO_T);
    }
    if widened > 0 {
        let models: Vec<String> = spread
            .weights
            .iter()
            .map(|(id, w)| format!("{id} {:.0} %", 100.0 * w))
            .collect();
        correction.notes.push(format!(
            "The std include what the choice of model can move each location error by (the \
             fits with each candidate effect, weighted by their evidence: {}).",
            models.join(", ")
        ));
    }
    correction.model_spread = Some(spread);
}
