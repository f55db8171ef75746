//! The signatures and point metadata of the built-in S-shape points, from the geometry.

use super::path_length::{surface_path_length, surface_path_lengths, total_path_length};
use super::{overcut, pivot, rigid, thermal, tool, EffectPoint};
use crate::gap::catalog::effect_info;
use crate::gap::data::{Candidate, NamedColumns, PointMeta};
use crate::gap::GapError;
use crate::part::points::MeasurementPoint;
use crate::part::{SShape, Surface};

/// Effect points (point, normal, h, s) of measurement points.
pub fn effect_points(part: &SShape, points: &[MeasurementPoint]) -> Vec<EffectPoint> {
    let mut s = vec![0.0; points.len()];
    let a_total = surface_path_length(part, Surface::A, 1.0);
    for (surface, offset) in [(Surface::A, 0.0), (Surface::B, a_total)] {
        let idx: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].surface == surface)
            .collect();
        let us: Vec<f64> = idx.iter().map(|&i| points[i].u).collect();
        for (k, len) in surface_path_lengths(part, surface, &us)
            .into_iter()
            .enumerate()
        {
            s[idx[k]] = offset + len;
        }
    }
    points
        .iter()
        .zip(s)
        .map(|(m, s)| EffectPoint {
            p: m.point,
            n: m.normal,
            h: m.h,
            s,
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

fn candidate(id: &str, columns: Vec<Vec<f64>>) -> Result<Candidate, GapError> {
    let info = effect_info(id).ok_or_else(|| GapError::UnknownEffect(id.to_string()))?;
    let names = info.parameters.iter().map(|(n, _)| n.to_string()).collect();
    Ok(Candidate {
        id: id.to_string(),
        signature: NamedColumns::from_columns(names, &columns)?,
    })
}

/// The candidates computed from the geometry: `tool_radius`, `tool_taper`, `overcut` (given the
/// envelope deviations at the points), `thermal_drift`, `setup_error`, `c_index`, `pivot_length`.
pub fn geometric_candidates(
    part: &SShape,
    eps: &[EffectPoint],
    envelope: &[f64],
) -> Result<Vec<Candidate>, GapError> {
    let s_total = total_path_length(part);
    Ok(vec![
        candidate("tool_radius", tool::tool_radius(eps))?,
        candidate("tool_taper", tool::tool_taper(eps))?,
        candidate("overcut", overcut::overcut(envelope))?,
        candidate("thermal_drift", thermal::thermal_drift(eps, s_total))?,
        candidate("setup_error", rigid::setup_error(eps))?,
        candidate("c_index", rigid::c_index(eps))?,
        candidate("pivot_length", pivot::pivot_length(eps))?,
    ])
}

/// Everything a diagnosis of measured points of the S-shape needs from the models: point
/// metadata, the baseline (the 8 location errors, `physical` mode, signed B), all the candidates
/// of effects.md, and the axis reversals along the path.
#[derive(Debug, Clone)]
pub struct PartModel {
    pub points: Vec<PointMeta>,
    pub baseline: NamedColumns,
    pub candidates: Vec<Candidate>,
    pub reversals: Vec<crate::gap::data::Reversal>,
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

/// The model of the given measurement points on the machine of `opts` (its chain and B branch;
/// the baseline is its location errors in `physical` mode whatever `opts.mode` says, as
/// effects.md defines it). The machine must have the axes the catalogue names (X, Y, Z, B, C):
/// paper 000's B head / C table and paper 002's B-C tilting table; otherwise an error.
pub fn part_model_on(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &crate::sensitivity::SensitivityOptions,
) -> Result<PartModel, GapError> {
    use super::machine::{backlash_columns, reversals, scale_signatures, BACKLASH_AXES};
    if let Some(missing) = BACKLASH_AXES
        .iter()
        .find(|&&a| opts.chain.axis(a).is_none())
    {
        return Err(GapError::Model(format!(
            "the effect catalogue (effects.md) names the axes X, Y, Z, B and C; this machine has \
             no {missing:?} axis"
        )));
    }
    let opts = &opts.clone().with_mode(crate::sensitivity::Mode::Physical);
    let sens = crate::sensitivity::sensitivity_matrix(part, points, opts)
        .map_err(|e| GapError::Model(e.to_string()))?;
    let baseline = NamedColumns::try_new(sens.params.clone(), sens.values.clone())?;
    let eps = effect_points(part, points);
    let envelope: Vec<f64> = crate::toolpath::envelope::points_deviation(part, points, 0.0)
        .map_err(|e| GapError::Model(e.to_string()))?
        .iter()
        .map(|d| d.deviation)
        .collect();
    let geo = geometric_candidates(part, &eps, &envelope)?;
    let scales = scale_signatures(part, points, opts)?;
    let passes = crate::sensitivity::reversal::passes(part, opts)
        .map_err(|e| GapError::Model(e.to_string()))?;
    let backlash = backlash_columns(&passes, part, points, opts)?;
    let take = |id: &str| geo.iter().find(|c| c.id == id).cloned();
    let mut candidates = Vec::new();
    for info in crate::gap::catalog::EFFECTS {
        let c = match info.id {
            "backlash_x" => candidate(info.id, vec![backlash[0].clone()])?,
            "backlash_y" => candidate(info.id, vec![backlash[1].clone()])?,
            "backlash_z" => candidate(info.id, vec![backlash[2].clone()])?,
            "backlash_b" => candidate(info.id, vec![backlash[3].clone()])?,
            "backlash_c" => candidate(info.id, vec![backlash[4].clone()])?,
            "scale_x" => candidate(info.id, vec![scales[0].clone()])?,
            "scale_y" => candidate(info.id, vec![scales[1].clone()])?,
            "scale_z" => candidate(info.id, vec![scales[2].clone()])?,
            id => take(id).ok_or_else(|| GapError::UnknownEffect(id.to_string()))?,
        };
        candidates.push(invisible_as_zero(c));
    }
    Ok(PartModel {
        points: point_meta(points, &eps),
        baseline,
        candidates,
        reversals: reversals(&passes),
    })
}

/// The model of the 100 built-in points.
pub fn builtin_model(part: &SShape) -> Result<PartModel, GapError> {
    part_model(part, &crate::part::builtin_points(part))
}
