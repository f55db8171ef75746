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
