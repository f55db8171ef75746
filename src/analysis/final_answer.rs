//! The final answer, refined with the exact model like the baseline.

use crate::effects::builtin::PartModel;
use crate::effects::prepared::Prepared;
use crate::final_fit::correct::{
    correct, shifts, summary, Basis, Correction, CorrectionInput, EffectsChoice, Final,
};
use crate::final_fit::model_spread::{model_spread, Answer, ModelSpread};
use crate::identify::correlated::{whiten, whitened_limit, Whitened, Whitener};
use crate::identify::refine::{
    apply_refinement, refine, refine_factored, RefineOptions, RefineReport,
};
use crate::identify::{Design, Factored, Identification, IdentifyOptions, Observations};
use crate::identify::{Status, NONZERO_T};
use crate::numerics::parallel::Threads;
use crate::numerics::stats;
use crate::parameter::Effect;
use crate::simulate::ExactDefectModel;
use nalgebra::DMatrix;

use super::error::AnalysisError;
use super::options::AnalysisOptions;
use super::session::PointsModel;

/// How a fit to refine was made: plainly (with its factored problem when it was kept,
/// [`crate::identify::identify_factored`]), or whitened.
pub(super) enum Fitted<'a> {
    Plain(Option<&'a Factored>),
    Whitened(&'a Whitener),
}

/// The exact-model refinement of a fit of `design` (plain, or whitened) at the points of `at`,
/// on the prepared settings (their chain, branch and mode).
pub(super) fn refine_with(
    prepared: &Prepared,
    at: &PointsModel,
    design: &Design,
    obs: &Observations,
    linear: &Identification,
    iopts: &IdentifyOptions,
    fitted: Fitted,
) -> Result<RefineReport, AnalysisError> {
    let model = ExactDefectModel::at_points_on(
        design,
        prepared.part(),
        at.points(),
        at.axis_values()?,
        prepared.options(),
        at.threads(),
    )?;
    let r = match fitted {
        Fitted::Plain(None) => refine(design, obs, linear, model, &RefineOptions::default(), iopts),
        Fitted::Plain(Some(f)) => refine_factored(
            design,
            obs,
            linear,
            f,
            model,
            &RefineOptions::default(),
            iopts,
        ),
        Fitted::Whitened(w) => {
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
    pub(super) model: Option<&'a PartModel>,
    /// The model's candidates at the shapes the diagnosis fitted.
    pub(super) candidates: &'a [crate::effects::Candidate],
    pub(super) verdict: Option<&'a crate::gap::verdict::Verdict>,
    /// The part's noise σ of the diagnosis (mm).
    pub(super) noise_sigma: Option<f64>,
    pub(super) unavailable: &'a [(Effect, String)],
    /// The model spread about the baseline answer, when it was computed beforehand
    /// ([`baseline_spread`]: beside the baseline identification).
    pub(super) spread: Option<ModelSpread>,
}

/// The final answer ([`crate::final_fit::correct`]), refined with the exact model like the baseline.
/// `baseline` is the baseline identification (after its refinement), `baseline_refinement`
/// its refinement.
pub(super) fn final_answer(
    mut f: FinalInput,
    baseline: &Identification,
    baseline_refinement: Option<&RefineReport>,
    prepared: &Prepared,
    at: &PointsModel,
    opts: &AnalysisOptions,
    iopts: &IdentifyOptions,
) -> Result<(Design, Identification, Option<RefineReport>, Correction), AnalysisError> {
    let no_points: Vec<crate::effects::PointMeta> = Vec::new();
    let input = CorrectionInput {
        design: f.design,
        observations: f.observations,
        baseline,
        points: f.model.map_or(&no_points, |m| &m.points),
        candidates: f.candidates,
        verdict: f.verdict,
        noise_sigma: f.noise_sigma,
        unavailable: f.unavailable,
        options: iopts,
        decompositions: at.decompositions(),
        threads: opts.threads,
    };
    let fin = correct(&input, &opts.effects).map_err(AnalysisError::Correction)?;
    let Final {
        design,
        mut identification,
        whitener,
        mut correction,
    } = fin;
    let refinement = match correction.basis {
        Basis::Baseline => baseline_refinement.cloned(),
        _ if opts.refine => {
            let fitted = match whitener.as_ref() {
                Some(w) => Fitted::Whitened(w),
                None => Fitted::Plain(None),
            };
            let r = refine_with(
                prepared,
                at,
                &design,
                f.observations,
                &identification,
                iopts,
                fitted,
            )?;
            apply_refinement(&mut identification, &r, "");
            if r.performed && r.success {
                correction.shift = shifts(baseline, &identification);
                correction.summary = summary(&correction, baseline, &identification);
            }
            Some(r)
        }
        _ => None,
    };
    if opts.effects == EffectsChoice::Auto {
        if let (Some(_), Some(v)) = (f.model, f.verdict) {
            // the spread computed beforehand is the baseline answer's: the one [`correct`] took
            let spread = match f.spread.take() {
                Some(s) if correction.basis == Basis::Baseline => s,
                _ => {
                    let p = f.design.matrix().ncols();
                    let added = design.matrix().ncols().saturating_sub(p);
                    let chosen = (correction.basis == Basis::Effects && added > 0)
                        .then(|| design.matrix().columns(p, added).into_owned());
                    spread_of(&f, v, chosen.as_ref(), whitener.as_ref(), opts.threads)
                }
            };
            widen_by_model_spread(&f, v, spread, &mut identification, &mut correction);
        }
    }
    Ok((design, identification, refinement, correction))
}

/// The model spread ([`model_spread`]) about the answer of the location errors plus `chosen`
/// (the columns the answer adds to them; none for the baseline), in the problem whitened by
/// `whitener` when the answer has a correlated error.
fn spread_of(
    f: &FinalInput,
    v: &crate::gap::verdict::Verdict,
    chosen: Option<&DMatrix<f64>>,
    whitener: Option<&Whitener>,
    threads: Threads,
) -> ModelSpread {
    let obs = f.observations;
    let used: Vec<usize> = (0..obs.len()).filter(|&i| obs.weight(i) > 0.0).collect();
    model_spread(
        f.design.matrix(),
        &f.design.names(),
        &obs.deviation,
        &used,
        f.candidates,
        f.model.map_or(&[][..], |m| &m.nuisance[..]),
        Answer { chosen, whitener },
        v.sigma,
        threads,
    )
}

/// The model spread about the baseline answer, which needs nothing of the baseline's own
/// identification: computed beside it when the final answer is known to be the baseline
/// ([`crate::final_fit::correct::basis_of`]), the same numbers as after it.
pub(super) fn baseline_spread(
    f: &FinalInput,
    v: &crate::gap::verdict::Verdict,
    threads: Threads,
) -> ModelSpread {
    spread_of(f, v, None, None, threads)
}

/// Confidence of the band within which the residual's RMS is taken as noise (the baseline's
/// σ a posteriori, [`noise_share`]).
const NOISE_BAND: f64 = 0.95;

/// The factor on the baseline's std that states them at the part's noise (issue 29 item 3).
///
/// The baseline's std use σ a posteriori, the residual's RMS, which holds whatever structure
/// the location errors leave: an effect below the detection limit counted a second time as
/// white noise (it is a bias, and [`model_spread`] accounts for it). The std are stated at
/// `σ_s = max(σ, min(σ_post, σ·q))`: the residual's RMS where it is within the two-sided
/// [`NOISE_BAND`] of a χ² with the residual's dof about the diagnosis's σ (`q² = χ²_{0.975}/dof`;
/// it estimates the same noise with more dof), never beyond it, never below the noise σ. The
/// named and `unexplained` answers keep theirs (their residual is the named effect's or holds
/// the structure's covariance).
fn noise_share(basis: Basis, post: Option<f64>, dof: usize, sigma: f64) -> f64 {
    match (basis, post) {
        (Basis::Baseline, Some(post)) if post > 0.0 && sigma > 0.0 => {
            let dof = dof.max(1) as f64;
            let q = (stats::chi2_isf(0.5 * (1.0 - NOISE_BAND), dof) / dof).sqrt();
            post.min(sigma * q).max(sigma) / post
        }
        _ => 1.0,
    }
}

/// The identification's covariance stated at the part's noise (`rescale²`, [`noise_share`])
/// plus the model spread's second moment on the location errors (`names`, its order), and the
/// correlations from it; the std are widened by the caller.
fn widen_covariance(
    identification: &mut Identification,
    names: &[String],
    spread: &ModelSpread,
    rescale: f64,
) {
    let order = identification.names();
    let n = order.len();
    let cov = &mut identification.covariance;
    if cov.len() != n || spread.covariance.len() != names.len() {
        return;
    }
    let at: Vec<Option<usize>> = names
        .iter()
        .map(|name| order.iter().position(|o| o == name))
        .collect();
    for row in cov.iter_mut() {
        for c in row.iter_mut() {
            *c *= rescale * rescale;
        }
    }
    for (a, ia) in at.iter().enumerate() {
        for (b, ib) in at.iter().enumerate() {
            if let (Some(i), Some(j)) = (ia, ib) {
                cov[*i][*j] += spread.covariance[a][b];
            }
        }
    }
    for i in 0..n {
        for j in 0..n {
            if let Some(r) = identification.correlation[i][j].as_mut() {
                let d = (cov[i][i] * cov[j][j]).sqrt();
                if d > 0.0 {
                    *r = cov[i][j] / d;
                }
            }
        }
    }
}

/// The location errors' std widened by what the choice among the candidate models can move
/// them by ([`model_spread`]), about the answer's estimate; the baseline's first stated at the
/// part's noise ([`noise_share`]).
fn widen_by_model_spread(
    f: &FinalInput,
    v: &crate::gap::verdict::Verdict,
    spread: ModelSpread,
    identification: &mut Identification,
    correction: &mut Correction,
) {
    let rescale = noise_share(
        correction.basis,
        identification.sigma,
        identification.dof,
        v.sigma,
    );
    widen_covariance(identification, &f.design.names(), &spread, rescale);
    if let (true, Some(post)) = (rescale < 1.0, identification.sigma) {
        correction.notes.push(format!(
            "The std are stated at σ = {:.2} µm, the part's noise: the residual's RMS ({:.2} µm) \
             holds structure below the detection limit, a bias of the location errors that the \
             spread over the candidate models carries, not noise.",
            post * rescale * 1e3,
            post * 1e3
        ));
    }
    let mut widened = 0;
    for pe in identification.parameters.0.iter_mut() {
        let (Some(std), Some(extra)) = (pe.std, spread.std.get(&pe.name())) else {
            continue;
        };
        let std = std * rescale;
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
             fits with each candidate effect and with shapes no candidate names: a probe's \
             lobing, the part drifting on the CMM, the axes' error motions; weighted by their \
             evidence: {}).",
            models.join(", ")
        ));
    }
    correction.model_spread = Some(spread);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// σ a posteriori within the χ² band of the noise σ stands; beyond it, the band's edge;
    /// below the noise σ, the noise σ; answers other than the baseline keep theirs.
    #[test]
    fn the_baseline_std_are_stated_at_the_noise() {
        // 100 dof: χ²₀.₉₇₅(100) = 129.561 (table), q = √1.29561 = 1.13825
        let q = 1.138_25;
        assert_near!(
            noise_share(Basis::Baseline, Some(2.0), 100, 1.0),
            q / 2.0,
            1e-5
        );
        assert_near!(
            noise_share(Basis::Baseline, Some(1.05), 100, 1.0),
            1.0,
            1e-12
        );
        assert_near!(
            noise_share(Basis::Baseline, Some(0.9), 100, 1.0),
            1.0 / 0.9,
            1e-12
        );
        assert_near!(noise_share(Basis::Effects, Some(2.0), 100, 1.0), 1.0, 0.0);
        assert_near!(noise_share(Basis::Baseline, None, 100, 1.0), 1.0, 0.0);
    }
}
