//! The signatures and point metadata of the built-in S-shape points, from the geometry.

use crate::effects::data::{Candidate, NamedColumns, PointMeta};
use crate::effects::effect::SignatureModel;
use crate::effects::EffectPoint;
use crate::effects::GapError;
use crate::parameter::{Effect, ParamId};
use crate::part::points::MeasurementPoint;
use crate::part::{SShape, Surface};
use crate::toolpath::envelope::{points_deviation_on, FlankPath};
use crate::toolpath::tip_length::TipLength;

/// Effect points (point, normal, h, s) of measurement points.
pub fn effect_points(part: &SShape, points: &[MeasurementPoint]) -> Vec<EffectPoint> {
    effect_points_on(
        part,
        points,
        [
            &TipLength::new(part, Surface::A),
            &TipLength::new(part, Surface::B),
        ],
    )
}

/// [`effect_points`] with the tool-tip path lengths of A and B already tabulated.
fn effect_points_on(
    part: &SShape,
    points: &[MeasurementPoint],
    lengths: [&TipLength; 2],
) -> Vec<EffectPoint> {
    points
        .iter()
        .map(|m| {
            let s = match m.surface {
                Surface::A => lengths[0].at(part, m.u),
                Surface::B => lengths[0].total() + lengths[1].at(part, m.u),
            };
            EffectPoint {
                p: m.point,
                n: m.normal,
                h: m.h,
                s,
            }
        })
        .collect()
}

/// Point metadata for the diagnosis; machining order = rank of `s`.
pub fn point_meta(points: &[MeasurementPoint], eps: &[EffectPoint]) -> Vec<PointMeta> {
    let mut idx: Vec<usize> = (0..points.len()).collect();
    idx.sort_by(|&a, &b| eps[a].s.total_cmp(&eps[b].s));
    let mut order = vec![0; points.len()];
    for (k, &i) in idx.iter().enumerate() {
        order[i] = k;
    }
    points
        .iter()
        .zip(eps)
        .zip(order)
        .map(|((m, e), o)| PointMeta {
            id: m.id as u32,
            curve: m.curve.name().to_string(),
            surface: m.surface,
            u: m.u,
            h: m.h,
            s: e.s,
            order: o,
            nz: m.normal.z,
        })
        .collect()
}

/// Everything a diagnosis of measured points of the S-shape needs from the models: point
/// metadata, the baseline (the machine's location errors, `physical` mode), the candidates of
/// effects.md whose physics the machine has ([`Effect::on_chain`]), and the axis reversals along
/// the path.
#[derive(Debug, Clone, PartialEq)]
pub struct PartModel {
    pub points: Vec<PointMeta>,
    pub baseline: NamedColumns,
    pub candidates: Vec<Candidate>,
    pub reversals: Vec<crate::effects::data::Reversal>,
}

impl PartModel {
    /// The deviation (mm, one value per point) that the effects' parameters `values` (an
    /// effect, the index of its parameter, the value in the parameter's unit) leave on this
    /// part: `Σ value · signature column` (effects.md: signatures are per unit of each parameter).
    pub fn effect_deviation(&self, values: &[(Effect, usize, f64)]) -> Result<Vec<f64>, GapError> {
        let mut out = vec![0.0; self.points.len()];
        for &(effect, j, value) in values {
            let c = self
                .candidates
                .iter()
                .find(|c| c.effect == effect)
                .ok_or(GapError::NotModelled(effect))?;
            for (o, s) in out.iter_mut().zip(c.signature.matrix.column(j).iter()) {
                *o += value * s;
            }
        }
        Ok(out)
    }
}

/// Below this largest |signature| (mm of deviation per unit of every parameter of the effect,
/// mm or rad) an effect cannot show on this machine at any plausible size: e.g. the backlash and
/// the scale error of Z on paper 002's tilting table, whose Z moves along the tool axis, which
/// lies in the flank-milled walls (their columns are ~1e-17, rounding).
pub const INVISIBLE_SIGNATURE: f64 = 1e-12;

/// A candidate whose signature is below [`INVISIBLE_SIGNATURE`] gets exact zeros, so that the
/// diagnosis reports it as adding nothing (rank 0) instead of fitting rounding noise, whose
/// column scaling would make it look like a direction of its own.
fn invisible_as_zero(mut c: Candidate) -> Candidate {
    if c.signature
        .matrix
        .iter()
        .all(|v| v.abs() < INVISIBLE_SIGNATURE)
    {
        c.signature.matrix.fill(0.0);
    }
    c
}

/// The model of the given measurement points on paper 000's machine (`physical` mode, signed B).
pub fn part_model(part: &SShape, points: &[MeasurementPoint]) -> Result<PartModel, GapError> {
    part_model_on(
        part,
        points,
        &crate::sensitivity::SensitivityOptions::default(),
    )
}

/// The candidate of `effect` on the signature model: its columns named by its parameters,
/// exact zeros when invisible ([`invisible_as_zero`]).
fn candidate(effect: Effect, model: &SignatureModel) -> Result<Candidate, GapError> {
    let columns = effect
        .signature(model)
        .ok_or(GapError::NotModelled(effect))?;
    Ok(invisible_as_zero(Candidate {
        effect,
        signature: NamedColumns::from_columns(effect.parameter_ids(), &columns)?,
    }))
}

/// The model of the given measurement points on the machine of `opts` (its chain and B branch;
/// the baseline is its location errors in `physical` mode whatever `opts.mode` says, as
/// effects.md defines it). The candidates are those whose physics exists on the chain
/// ([`Effect::on_chain`]), each with its signature derived from the chain.
pub fn part_model_on(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &crate::sensitivity::SensitivityOptions,
) -> Result<PartModel, GapError> {
    let opts = &opts.clone().with_mode(crate::sensitivity::Mode::Physical);
    crate::effects::cache::part_model(part, points, opts, || {
        compute_part_model(part, points, opts)
    })
}

/// [`part_model_on`] computed (not taken from [`crate::effects::cache`]), on the path model of the
/// settings (from the cache), `opts` in `physical` mode.
fn compute_part_model(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &crate::sensitivity::SensitivityOptions,
) -> Result<PartModel, GapError> {
    compute_model(part, points, opts, true)
}

/// The candidates of the machine of `opts` that are its location errors under another name
/// ([`crate::effects::location_equivalent`]), decided on the part's built-in points, once per machine.
pub fn location_equivalents_of(
    part: &SShape,
    opts: &crate::sensitivity::SensitivityOptions,
) -> Result<Vec<(Effect, String)>, GapError> {
    let opts = &opts.clone().with_mode(crate::sensitivity::Mode::Physical);
    crate::effects::location_equivalent::kept_for(&opts.chain, opts.branch, || {
        let m = compute_model(part, &crate::part::builtin_points(part), opts, false)?;
        let typical = opts
            .params()?
            .iter()
            .map(crate::machine::ErrorParam::typical)
            .collect();
        Ok((m.baseline, typical, m.candidates))
    })
    .map(|kept| kept.to_vec())
}

/// The model with every candidate whose physics the chain has ([`Effect::on_chain`]), the
/// location equivalents included (not kept by the cache): what the formulas give, for tests of
/// the physics and for [`crate::effects::location_equivalent`].
pub fn part_model_every_candidate(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &crate::sensitivity::SensitivityOptions,
) -> Result<PartModel, GapError> {
    let opts = &opts.clone().with_mode(crate::sensitivity::Mode::Physical);
    compute_model(part, points, opts, false)
}

/// [`compute_part_model`], with `filter` leaving out the location equivalents.
fn compute_model(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &crate::sensitivity::SensitivityOptions,
    filter: bool,
) -> Result<PartModel, GapError> {
    use crate::effects::machine::{
        backlash_columns, c_table_sign, index_signatures, machine_z_columns, scale_signatures,
    };
    let sens = crate::sensitivity::sensitivity_matrix(part, points, opts)?;
    let baseline = NamedColumns::try_new(
        sens.errors.iter().map(|e| ParamId::Machine(*e)).collect(),
        sens.values.clone(),
    )?;
    let path = crate::effects::cache::path_model(part, opts)?;
    let eps = effect_points_on(part, points, path.lengths());
    let flank = |i: usize| FlankPath::with_table(part, Surface::BOTH[i], &path.pose_tables[i]);
    let envelope: Vec<f64> = points_deviation_on(&[flank(0), flank(1)], points, 0.0)?
        .iter()
        .map(|d| d.deviation)
        .collect();
    let model = SignatureModel {
        s_total: path.s_total(),
        envelope,
        backlash: backlash_columns(&path.lags, part, points, opts)?,
        scale: scale_signatures(part, points, opts)?,
        machine_z: machine_z_columns(part, points, opts)?,
        c_table_sign: c_table_sign(&opts.chain),
        index: index_signatures(part, points, opts)?,
        points: eps,
    };
    let mut candidates = Effect::on_chain(&opts.chain)
        .into_iter()
        .map(|e| candidate(e, &model))
        .collect::<Result<Vec<_>, _>>()?;
    if filter {
        let same = location_equivalents_of(part, opts)?;
        candidates.retain(|c| !same.iter().any(|(e, _)| *e == c.effect));
    }
    Ok(PartModel {
        points: point_meta(points, &model.points),
        baseline,
        candidates,
        reversals: path.reversals.clone(),
    })
}

/// The model of the 100 built-in points.
pub fn builtin_model(part: &SShape) -> Result<PartModel, GapError> {
    part_model(part, &crate::part::builtin_points(part))
}
