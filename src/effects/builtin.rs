//! The signatures and point metadata of the built-in S-shape points, from the geometry.

use crate::effects::data::{Candidate, Family, NamedColumns, PointMeta};
use crate::effects::effect::{warm_up_basis, SignatureModel};
use std::sync::Arc;

use crate::effects::family::{LagBasis, Members};
use crate::effects::path_model::PathModel;
use crate::effects::EffectPoint;
use crate::effects::GapError;
use crate::machine::{AxisName, AxisValues, ErrorParam};
use crate::numerics::order::argsort;
use crate::numerics::parallel::{join, Threads};
use crate::parameter::{Effect, ParamId, Shape};
use crate::part::points::MeasurementPoint;
use crate::part::{SShape, Surface};
use crate::sensitivity::reversal::{backlash_gains, grid_spots, lagged_columns_at, Lag};
use crate::sensitivity::SensitivityOptions;
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
                second: m.surface == Surface::B,
            }
        })
        .collect()
}

/// Point metadata for the diagnosis; machining order = rank of `s`.
pub fn point_meta(points: &[MeasurementPoint], eps: &[EffectPoint]) -> Vec<PointMeta> {
    let s: Vec<f64> = eps[..points.len()].iter().map(|e| e.s).collect();
    let idx = argsort(&s);
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
    /// What the backlash candidates' families are made of, to rebuild them with the play's
    /// take-up ([`PartModel::with_take_up`]).
    pub backlash: LagBasis,
    /// Shapes no candidate names, for the model spread ([`crate::effects::nuisance`]).
    pub nuisance: Vec<crate::effects::nuisance::Nuisance>,
}

/// The profiled parameter of a backlash family rebuilt with the play's take-up: the lost motion
/// whose take-up a member has (the axis's unit), 0 for the member switched at the reversal.
pub fn take_up_shape(axis: AxisName, b: f64) -> Shape {
    Shape {
        name: "take_up",
        unit: Effect::Backlash(axis).parameters()[0].1.clone(),
        reference: 0.0,
        grid: vec![0.0, b],
    }
}

impl PartModel {
    /// This model with the family of the backlash candidates of the axes in `lost` (axis, lost
    /// motion `b` in its unit) holding, beside each lag's member switched at the reversal, the
    /// same lag with the play's take-up of `b` ([`crate::sensitivity::take_up`]), the take-up a
    /// profiled parameter of the family ([`take_up_shape`]). `path` is the path model this model
    /// was built on. Their signature at the reference lag, axes with `b ≤ 0` and every other
    /// candidate are kept as they are.
    pub fn with_take_up(
        &self,
        path: &PathModel,
        lost: &[(AxisName, f64)],
    ) -> Result<PartModel, GapError> {
        let axes = &path.lags[0].axes;
        let b: Vec<f64> = axes
            .iter()
            .map(|a| {
                lost.iter()
                    .find(|(x, _)| x == a)
                    .map_or(0.0, |(_, b)| b.max(0.0))
            })
            .collect();
        let mut out = self.clone();
        if b.iter().all(|&b| b <= 0.0) {
            return Ok(out);
        }
        // each lag switched at the reversal (its first order, as it was) and with the take-up
        // (PathModel::taken_up's order; only the axes with a lost motion): the take-up is
        // profiled out, so the lag's interval holds every lag either explains
        let lags: Vec<[Lag; 2]> = path
            .first_order()
            .zip(path.taken_up(&b))
            .flat_map(|(switched, taken)| [switched.clone(), taken])
            .collect();
        let basis = LagBasis {
            lags: Arc::new(lags),
            ..self.backlash.clone()
        };
        for c in out.candidates.iter_mut() {
            let Effect::Backlash(axis) = c.effect else {
                continue;
            };
            let Some(i) = axes.iter().position(|&a| a == axis) else {
                continue;
            };
            if b[i] <= 0.0 || c.family.is_none() {
                continue;
            }
            c.family = match (c.effect.shape(), basis.members(axis)) {
                (Some(shape), Some(members)) => Some(Family {
                    shape,
                    profiled: Some(take_up_shape(axis, b[i])),
                    members: Members::Lagged(members),
                }),
                _ => None,
            };
        }
        Ok(out)
    }

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
        // an invisible effect is invisible at every shape: one shape, all zeros
        c.family = None;
    }
    c
}

/// The candidate of `effect` on the signature model: its columns named by its parameters,
/// exact zeros when invisible ([`invisible_as_zero`]).
fn candidate(effect: Effect, model: &SignatureModel) -> Result<Candidate, GapError> {
    let columns = effect
        .signature(model)
        .ok_or(GapError::NotModelled(effect))?;
    let family = match (effect, effect.shape(), &model.backlash_family) {
        (Effect::ThermalDrift, Some(shape), _) => Some(Family {
            shape,
            profiled: effect.profiled(),
            members: Members::WarmUp(warm_up_basis(model)),
        }),
        (Effect::Backlash(axis), Some(shape), Some(basis)) => {
            basis.members(axis).map(|members| Family {
                shape,
                profiled: effect.profiled(),
                members: Members::Lagged(members),
            })
        }
        _ => None,
    };
    Ok(invisible_as_zero(Candidate {
        effect,
        signature: NamedColumns::from_columns(effect.parameter_ids(), &columns)?,
        family,
    }))
}

/// The model of `points` (axis values `q`, [`crate::sensitivity::axis_values`]) on the machine of
/// `opts` in `physical` mode, on the path model `path` of the same settings, with the location
/// errors `errors` as the baseline and every candidate whose physics the chain has
/// ([`Effect::on_chain`]), each with its signature derived from the chain: what
/// [`crate::effects::prepared::Prepared::part_model`] filters.
pub(crate) fn every_candidate_model(
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
    errors: &[ErrorParam],
    path: &PathModel,
    threads: Threads,
) -> Result<PartModel, GapError> {
    use crate::effects::machine::{
        c_table_sign, index_signatures, machine_z_columns, scale_and_motions,
    };
    // two halves of about the same cost, side by side when `threads` allows (issue 31): the
    // design's columns, the envelope, the path lengths and the scale columns; the axes' gains
    // with the servo signatures and the points' places on the reversal grid
    let (first, second) = join(
        threads,
        || -> Result<_, GapError> {
            let sens = crate::sensitivity::sensitivity_matrix(part, points, q, opts, errors)?;
            let eps = effect_points_on(part, points, path.lengths());
            let flank =
                |i: usize| FlankPath::with_table(part, Surface::BOTH[i], &path.pose_tables[i]);
            let envelope: Vec<f64> = points_deviation_on(&[flank(0), flank(1)], points, 0.0)?
                .iter()
                .map(|d| d.deviation)
                .collect();
            let (scale, motions) = scale_and_motions(part, points, q, opts)?;
            Ok((sens, eps, envelope, scale, motions))
        },
        || -> Result<_, GapError> {
            // the gains (∂x/∂q)·N of every axis of the chain, once: the servo signatures read
            // them all, the backlash columns those of the lags' axes
            let chain_axes: Vec<AxisName> = opts.chain.axes().map(|a| a.name).collect();
            let all_gains = backlash_gains(part, points, q, &chain_axes, opts)?;
            let servo =
                crate::sensitivity::servo::servo_signatures_with(part, points, opts, &all_gains)?;
            // where each point falls on the passes' grid, shared by every lag (the passes'
            // lengths)
            let spots = grid_spots(&path.lags, part, points);
            Ok((chain_axes, all_gains, servo, spots))
        },
    );
    let (sens, eps, envelope, scale, motions) = first?;
    let (chain_axes, all_gains, servo, spots) = second?;
    let baseline = NamedColumns::try_new(
        sens.errors.iter().map(|e| ParamId::Machine(*e)).collect(),
        sens.values.clone(),
    )?;
    // the backlash columns at the reference lag and at each lag of the family, from the gains
    // computed once
    let axes = &path.lags[0].axes;
    let gains: Vec<Vec<f64>> = axes
        .iter()
        .map(|a| match chain_axes.iter().position(|c| c == a) {
            Some(k) => Ok(all_gains[k].clone()),
            None => backlash_gains(part, points, q, &[*a], opts).map(|mut g| g.remove(0)),
        })
        .collect::<Result<_, _>>()?;
    let named = |cols: Vec<Vec<f64>>| axes.iter().copied().zip(cols).collect::<Vec<_>>();
    let backlash = named(lagged_columns_at(&path.lags, &spots, &gains));
    // what the backlash families' members are computed from (also kept for the take-up rounds)
    let basis = LagBasis {
        lags: path.settling.clone(),
        spots: Arc::new(spots),
        gains: named(gains),
    };
    let model = SignatureModel {
        s_total: path.s_total(),
        envelope,
        backlash,
        backlash_family: Some(basis.clone()),
        servo: servo.lag,
        servo_common: servo.common,
        scale,
        machine_z: machine_z_columns(q, opts),
        c_table_sign: c_table_sign(&opts.chain),
        index: index_signatures(points, q, opts)?,
        points: eps,
    };
    let candidates = Effect::on_chain(&opts.chain)
        .into_iter()
        .map(|e| candidate(e, &model))
        .collect::<Result<Vec<_>, _>>()?;
    let mut nuisance = motions;
    nuisance.push(crate::effects::nuisance::probing(&model.points));
    nuisance.push(crate::effects::nuisance::drift(&model.points));
    Ok(PartModel {
        points: point_meta(points, &model.points),
        baseline,
        candidates,
        reversals: path.reversals.clone(),
        backlash: basis,
        nuisance,
    })
}
