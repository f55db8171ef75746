//! The signatures and point metadata of the built-in S-shape points, from the geometry.

use crate::effects::data::{Candidate, Family, NamedColumns, PointMeta};
use crate::effects::effect::{warm_up_basis, SignatureModel};
use nalgebra::DMatrix;
use std::sync::Arc;

use crate::effects::family::{LagBasis, Members};
use crate::effects::path_model::PathModel;
use crate::effects::EffectPoint;
use crate::effects::GapError;
use crate::machine::{AxisName, AxisValues, ErrorParam};
use crate::numerics::order::argsort;
use crate::numerics::parallel::{join, map, Threads};
use crate::parameter::{Effect, ParamId, Shape};
use crate::part::points::MeasurementPoint;
use crate::part::{SShape, Surface};
use crate::sensitivity::reversal::{
    backlash_gains, grid_places_with, lagged_columns_at, GridPlace, GridSpots, Lag,
};
use crate::sensitivity::servo::{RateTable, ServoColumns, RATE_TABLE_POINTS};
use crate::sensitivity::SensitivityOptions;
use crate::toolpath::envelope::{points_deviation_on, FlankPath};
use crate::toolpath::tip_length::{PassLengths, TipLength};

/// Effect points (point, normal, h, s) of measurement points.
pub fn effect_points(part: &SShape, points: &[MeasurementPoint]) -> Vec<EffectPoint> {
    let (a, b) = (
        TipLength::new(part, Surface::A),
        TipLength::new(part, Surface::B),
    );
    effect_points_on(points, &PassLengths::Tables(part, [&a, &b]))
}

/// [`effect_points`] with the tool-tip path lengths of A and B already tabulated.
fn effect_points_on(points: &[MeasurementPoint], lengths: &PassLengths) -> Vec<EffectPoint> {
    points
        .iter()
        .map(|m| {
            let s = match m.surface {
                Surface::A => lengths.at(0, m.u),
                Surface::B => lengths.total(0) + lengths.at(1, m.u),
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
    /// The points and the baseline design, shared with the model rebuilt with a backlash's
    /// take-up ([`PartModel::with_take_up`]: 43 MB at 200,000 points not copied).
    pub points: Arc<Vec<PointMeta>>,
    pub baseline: Arc<NamedColumns>,
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
        Arc::make_mut(&mut c.signature).matrix.fill(0.0);
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
        signature: Arc::new(NamedColumns::from_columns(
            effect.parameter_ids(),
            &columns,
        )?),
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
        c_table_sign, index_signatures, machine_z_columns, MotionParams,
    };
    use crate::sensitivity::defect::{jacobian_rows_and_gains, SensitivityMatrix};
    let chain_axes: Vec<AxisName> = opts.chain.axes().map(|a| a.name).collect();
    // the point-wise work in blocks of points, shared out between the threads as each becomes
    // free (issue 31: two fixed halves left one thread alone for a tenth of the model): every
    // column is computed point by point, so the blocks change no number
    let jobs = point_jobs(points.len(), threads);
    // a dense scan's servo rates from a table of the paths, once for every block
    let rate_table = if points.len() >= RATE_TABLE_POINTS {
        Some(RateTable::new(part, opts, threads)?)
    } else {
        None
    };
    // ... and its path lengths from the passes' series (1,664 speed evaluations a pass: 13
    // knot spans × 8 pieces × 16 nodes, where the points' lengths take five each:
    // [`PassLengths`]), the two passes' side by side
    let [la, lb] = path.lengths();
    let series = (points.len() >= LENGTH_SERIES_POINTS).then(|| {
        let (a, b) = join(threads, || la.series(part), || lb.series(part));
        [a, b]
    });
    let lengths = match &series {
        Some(s) => PassLengths::Series(s),
        None => PassLengths::Tables(part, [la, lb]),
    };
    let pieces = map(threads, &jobs, |r| -> Result<Piece, GapError> {
        let (points, q) = (&points[r.clone()], &q[r.clone()]);
        // the location errors and the error motions from one Jacobian a point, and the gains
        // (∂x/∂q)·N of every axis of the chain at the same pose (the chain's factors and
        // products once; each column as it would be alone): the servo signatures read them
        // all, the backlash columns those of the lags' axes
        let motion_params = MotionParams::new();
        let all: Vec<ErrorParam> = errors
            .iter()
            .chain(&motion_params.params)
            .cloned()
            .collect();
        let (m, gains) = jacobian_rows_and_gains(part, points, q, opts, &all, &chain_axes)?;
        let sens = SensitivityMatrix {
            ids: points.iter().map(|p| p.id).collect(),
            curves: points.iter().map(|p| p.curve.name().to_string()).collect(),
            errors: errors.to_vec(),
            values: m.columns(0, errors.len()).into_owned(),
        };
        let (scale, motions) = motion_params.columns(
            &m.columns(errors.len(), motion_params.params.len())
                .into_owned(),
        );
        let eps = effect_points_on(points, &lengths);
        let flank = |i: usize| FlankPath::with_table(part, Surface::BOTH[i], &path.pose_tables[i]);
        let envelope = points_deviation_on(&[flank(0), flank(1)], points, 0.0)?
            .iter()
            .map(|d| d.deviation)
            .collect();
        let servo = crate::sensitivity::servo::servo_signatures_with(
            part,
            points,
            opts,
            &gains,
            rate_table.as_ref(),
        )?;
        Ok(Piece {
            design: Design {
                sens,
                eps,
                envelope,
                scale,
                motions,
            },
            gains,
            servo,
            // where each point falls on the passes' grid, shared by every lag
            places: grid_places_with(&lengths, points),
        })
    });
    let mut designs: Vec<Design> = Vec::new();
    let mut axis_parts: Option<(Vec<Vec<f64>>, ServoColumns)> = None;
    let mut places: Vec<GridPlace> = Vec::with_capacity(points.len());
    for piece in pieces {
        let Piece {
            design,
            gains: g,
            servo: s,
            places: p,
        } = piece?;
        designs.push(design);
        places.extend(p);
        axis_parts = Some(match axis_parts {
            None => (g, s),
            Some((mut all_g, mut all_s)) => {
                append_columns(&mut all_g, g);
                append_columns(&mut all_s.lag, s.lag);
                all_s.common.extend(s.common);
                (all_g, all_s)
            }
        })
    }
    let (Some(design), Some((all_gains, servo))) = (Design::concat(designs), axis_parts) else {
        unreachable!("point_jobs has a job of each kind")
    };
    let Design {
        sens,
        eps,
        envelope,
        scale,
        motions,
    } = design;
    let baseline = NamedColumns::try_new(
        sens.errors.iter().map(|e| ParamId::Machine(*e)).collect(),
        sens.values.clone(),
    )?;
    // the backlash columns at the reference lag and at each lag of the family, from the gains
    // computed once; beside them (on another thread when there is one) what depends on the
    // points alone: the probing and drift families and the points' metadata (with the grid's
    // sites, about 0.15 s of one thread after the jobs at 200,000 points in a profile, issue 31)
    let axes = &path.lags[0].axes;
    let (grid, (probing, drift, meta)) = join(
        threads,
        || -> Result<_, GapError> {
            let spots = GridSpots::of_on(&places, threads);
            let gains: Vec<Vec<f64>> = axes
                .iter()
                .map(|a| match chain_axes.iter().position(|c| c == a) {
                    Some(k) => Ok(all_gains[k].clone()),
                    None => backlash_gains(part, points, q, &[*a], opts).map(|mut g| g.remove(0)),
                })
                .collect::<Result<_, _>>()?;
            let backlash = lagged_columns_at(&path.lags, &spots, &gains);
            Ok((spots, gains, backlash))
        },
        || {
            (
                crate::effects::nuisance::probing(&eps),
                crate::effects::nuisance::drift(&eps),
                point_meta(points, &eps),
            )
        },
    );
    let (spots, gains, backlash) = grid?;
    let named = |cols: Vec<Vec<f64>>| axes.iter().copied().zip(cols).collect::<Vec<_>>();
    let backlash = named(backlash);
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
    // each candidate's columns on its own: side by side on the threads
    let effects = Effect::on_chain(&opts.chain);
    let candidates = map(threads, &effects, |&e| candidate(e, &model))
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;
    let mut nuisance = motions;
    nuisance.push(probing);
    nuisance.push(drift);
    Ok(PartModel {
        points: Arc::new(meta),
        baseline: Arc::new(baseline),
        candidates,
        reversals: path.reversals.clone(),
        backlash: basis,
        nuisance,
    })
}

/// From this many points on, [`every_candidate_model`] reads the points' path lengths from the
/// passes' Chebyshev series ([`TipLength::series`], 1e-12 mm from the tables' Gauss–Legendre):
/// the two series cost about the lengths of 670 points to build; fewer points (the built-in 100,
/// the reference's test vectors) keep the tables' own rule.
pub const LENGTH_SERIES_POINTS: usize = 2000;

/// Blocks of points per thread in [`every_candidate_model`]'s jobs: each block's design columns,
/// axis gains and servo columns together (one evaluation of the chain a point for the design
/// rows and the gains), so with sixteen blocks a thread the jobs end within about a sixteenth of
/// a thread's share of each other (four had left one thread alone for 0.15 s at the end of a
/// 200,000-point scan's jobs, a slower core finishing its last block, issue 31).
const BLOCKS_PER_THREAD: usize = 16;

/// The blocks of the point-wise work of [`every_candidate_model`] for `n` points on `threads`
/// threads (one block on one thread: the whole points at once), each a job: its design columns,
/// its axis columns and its places on the reversal grid.
fn point_jobs(n: usize, threads: Threads) -> Vec<std::ops::Range<usize>> {
    let blocks = if threads.get() <= 1 {
        1
    } else {
        (threads.get() * BLOCKS_PER_THREAD).min(n.max(1))
    };
    (0..blocks)
        .map(|b| b * n / blocks..(b + 1) * n / blocks)
        .collect()
}

/// A block's design columns: the location errors', the effect points, the envelope, the scale
/// columns and the error motions' families.
struct Design {
    sens: crate::sensitivity::SensitivityMatrix,
    eps: Vec<EffectPoint>,
    envelope: Vec<f64>,
    scale: crate::effects::machine::AxisColumns,
    motions: Vec<crate::effects::nuisance::Nuisance>,
}

impl Design {
    /// The blocks' rows one after the other, in their order (`None` for no block): each matrix
    /// stacked once (block after block had copied the rows so far again at every block).
    fn concat(blocks: Vec<Design>) -> Option<Design> {
        let mut blocks = blocks.into_iter();
        let mut all = blocks.next()?;
        let rest: Vec<Design> = blocks.collect();
        let stacked = |first: &DMatrix<f64>, next: &dyn Fn(&Design) -> &DMatrix<f64>| {
            stack_rows(
                &std::iter::once(first)
                    .chain(rest.iter().map(next))
                    .collect::<Vec<_>>(),
            )
        };
        all.sens.values = stacked(&all.sens.values, &|d| &d.sens.values);
        for (k, m) in all.motions.iter_mut().enumerate() {
            m.columns = stacked(&m.columns, &|d| &d.motions[k].columns);
        }
        for next in rest {
            all.sens.ids.extend(next.sens.ids);
            all.sens.curves.extend(next.sens.curves);
            all.eps.extend(next.eps);
            all.envelope.extend(next.envelope);
            append_columns(&mut all.scale, next.scale);
        }
        Some(all)
    }
}

/// What a job of [`point_jobs`] computes for its block of points.
struct Piece {
    design: Design,
    gains: Vec<Vec<f64>>,
    servo: ServoColumns,
    places: Vec<GridPlace>,
}

/// Each column of `next` (the rows that follow) appended to the same column of `all`.
fn append_columns<K>(all: &mut [K], next: Vec<K>)
where
    K: ExtendColumn,
{
    for (a, b) in all.iter_mut().zip(next) {
        a.extend_column(b);
    }
}

/// A column, named or not, that the rows of the next block extend.
trait ExtendColumn {
    fn extend_column(&mut self, next: Self);
}

impl ExtendColumn for Vec<f64> {
    fn extend_column(&mut self, next: Self) {
        self.extend(next);
    }
}

impl<N> ExtendColumn for (N, Vec<f64>) {
    fn extend_column(&mut self, next: Self) {
        self.1.extend(next.1);
    }
}

/// The rows of each of `parts` after those of the one before (same columns): column by column,
/// each part's piece of it copied whole (column-major storage), into memory written once.
fn stack_rows(parts: &[&DMatrix<f64>]) -> DMatrix<f64> {
    let cols = parts.first().map_or(0, |m| m.ncols());
    assert!(
        parts.iter().all(|m| m.ncols() == cols),
        "stack_rows: parts of unequal columns"
    );
    let rows: usize = parts.iter().map(|m| m.nrows()).sum();
    let mut data = Vec::with_capacity(rows * cols);
    for j in 0..cols {
        for m in parts {
            data.extend_from_slice(&m.as_slice()[j * m.nrows()..(j + 1) * m.nrows()]);
        }
    }
    DMatrix::from_vec(rows, cols, data)
}
