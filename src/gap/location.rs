//! WHERE the residual lies: per curve, per region of the S, per lean of the wall, near axis
//! reversals, and as trends against contact height, machining order and tool-path length; and
//! whether it is noise or structure.
//!
//! Structure test: with `σ` the noise of [`crate::measurement::noise::NoiseEstimate`] (one
//! estimator that structure cannot inflate, the CMM's share as a floor), the excess of the
//! residual variance over noise is `structure_rms = √max(0, RSS/(n − rank) − σ²)`; the residual
//! is *structured* when `structure_rms > 2.5 σ` (the decision rule of effects.md), or when σ̂
//! itself is more than noise can plausibly be (`implausible`: then the point-to-point variation
//! is structure, whatever its size against σ̂). With σ estimated from differences,
//! this is a variance-ratio test of the von Neumann kind (white noise has `Var r = γ(1)`); the
//! runs / lag-1 / Ljung–Box tests (independent of σ) and `χ² = RSS/σ²` are reported as supporting
//! evidence. The factor `k` (2.5) is [`crate::gap::DiagnoseOptions::detect_factor`].
//!
//! Each group of points is a typed [`Group`] (curve, region of the S, lean of the wall, axis
//! reversal with its axis, path position and nearest point), with the flags a page needs to draw
//! it without re-deciding anything: `concentrated` (more than [`CONCENTRATED`] times its share of
//! the residual) and, for a reversal, `of_verdict` (its axis is that of a named backlash) and
//! `marked` (either).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::effects::data::{curve_sequences, PointMeta, Reversal};
use crate::gap::regions::{Lean, Region};
use crate::identify::solve::{max_abs, rms};
use crate::machine::AxisName;
use crate::measurement::noise::{self, NoiseEstimate, Randomness};
use crate::numerics::stats;

/// Factor of σ above which an effect (or structure) counts (effects.md); the default of
/// [`crate::gap::DiagnoseOptions::detect_factor`].
pub const DETECT_FACTOR: f64 = 2.5;

/// A group holding more than this multiple of its share of the residual sum of squares is where
/// the residual is concentrated.
pub const CONCENTRATED: f64 = 1.5;

/// What a group of points is (JSON: `group` = `curve`, `region`, `lean` or `reversal`, with the
/// group's own fields beside it).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "group", rename_all = "snake_case")]
pub enum Group {
    /// The points of one measurement curve (`A_Z11`, …).
    Curve { curve: String },
    /// The points of one band of `u` along the S.
    Region { region: Region },
    /// The points where the wall leans one way.
    Lean { lean: Lean },
    /// The points within ±[`REVERSAL_WINDOW_MM`] of tool path of an axis reversal.
    Reversal {
        axis: AxisName,
        /// Tool-tip path length of the reversal from the start of A (mm).
        s: f64,
        /// Id of the point whose generating pose is nearest the reversal along the path.
        nearest: u32,
        /// The axis is that of a named backlash (the verdict or its pair).
        of_verdict: bool,
        /// `of_verdict` or `concentrated`: the reversals worth marking on a plot.
        marked: bool,
    },
}

impl Group {
    /// The group's name as the summary and the CSV exports write it (`A_Z11`, `turn_1`,
    /// `open_angle`, `C@672.3`).
    pub fn name(&self) -> String {
        match self {
            Group::Curve { curve } => curve.clone(),
            Group::Region { region } => region.name().into(),
            Group::Lean { lean } => lean.name().into(),
            Group::Reversal { axis, s, .. } => format!("{axis:?}@{s:.1}"),
        }
    }
}

/// Half-width (mm of tool-tip path) of the window around an axis reversal.
pub const REVERSAL_WINDOW_MM: f64 = 10.0;

/// Residual statistics of one group of points.
#[derive(Debug, Clone, Serialize)]
pub struct WhereEntry {
    #[serde(flatten)]
    pub group: Group,
    /// The group's name ([`Group::name`]).
    pub name: String,
    pub n: usize,
    /// RMS of the residual in the group (mm).
    pub rms: f64,
    pub max_abs: f64,
    pub mean: f64,
    /// Share of the total residual sum of squares divided by the share of points (1 = average).
    pub concentration: f64,
    /// `concentration > CONCENTRATED`.
    pub concentrated: bool,
    /// Ids of the group's points (as in the file), so that a page or report can highlight them.
    pub ids: Vec<u32>,
}

/// A linear trend of the residual against one variable.
#[derive(Debug, Clone, Serialize)]
pub struct Trend {
    /// `contact_height` (mm), `order` (points), `path_length` (mm).
    pub against: String,
    /// Slope (mm per unit of the variable).
    pub slope: f64,
    pub std: f64,
    /// Two-sided p-value of the slope (normal approximation).
    pub p_value: f64,
    /// Residual change over the range of the variable (mm).
    pub change_over_range: f64,
}

/// The WHERE part of a diagnosis.
#[derive(Debug, Clone, Serialize)]
pub struct WhereReport {
    pub entries: Vec<WhereEntry>,
    pub trends: Vec<Trend>,
    pub noise: NoiseEstimate,
    pub randomness_per_curve: BTreeMap<String, Randomness>,
    pub randomness: Randomness,
    /// Ljung–Box whiteness test along the curves (independent of σ).
    pub ljung_box: noise::LjungBox,
    pub chi2: f64,
    pub chi2_dof: usize,
    pub chi2_p: f64,
    /// RMS of the residual in excess of noise (mm).
    pub structure_rms: f64,
    /// `structure_rms > 2.5 σ`.
    pub structured: bool,
    /// The curve or region where the residual is most concentrated, if markedly so
    /// (> [`CONCENTRATED`]).
    pub concentrated_in: Option<String>,
    /// Its index in `entries`.
    pub concentrated_entry: Option<usize>,
    /// The axes of the named backlash effects (their reversals are `of_verdict`).
    pub verdict_axes: Vec<AxisName>,
}

impl WhereReport {
    /// Flags the reversals of `axes` (those of a named backlash) as `of_verdict` and `marked`.
    pub fn mark_verdict_axes(&mut self, axes: &[AxisName]) {
        self.verdict_axes = axes.to_vec();
        for e in &mut self.entries {
            if let Group::Reversal {
                axis,
                of_verdict,
                marked,
                ..
            } = &mut e.group
            {
                *of_verdict = axes.contains(axis);
                *marked = *of_verdict || e.concentrated;
            }
        }
    }
}

fn entry(
    group: Group,
    idx: &[usize],
    points: &[PointMeta],
    r: &[f64],
    total_ss: f64,
) -> WhereEntry {
    let vals: Vec<f64> = idx.iter().map(|&i| r[i]).collect();
    let ss: f64 = vals.iter().map(|v| v * v).sum();
    let n = r.len() as f64;
    let concentration = if total_ss > 0.0 && !idx.is_empty() {
        (ss / total_ss) / (idx.len() as f64 / n)
    } else {
        0.0
    };
    WhereEntry {
        name: group.name(),
        group,
        n: idx.len(),
        rms: rms(&vals),
        max_abs: max_abs(&vals),
        mean: if vals.is_empty() {
            0.0
        } else {
            vals.iter().sum::<f64>() / vals.len() as f64
        },
        concentration,
        concentrated: concentration > CONCENTRATED,
        ids: idx.iter().map(|&i| points[i].id).collect(),
    }
}

fn trend(against: &str, x: &[f64], r: &[f64]) -> Trend {
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = r.iter().sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    let sxy: f64 = x.iter().zip(r).map(|(a, b)| (a - mx) * (b - my)).sum();
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let rss: f64 = x
        .iter()
        .zip(r)
        .map(|(a, b)| (b - my - slope * (a - mx)).powi(2))
        .sum();
    let std = if sxx > 0.0 && n > 2.0 {
        (rss / (n - 2.0) / sxx).sqrt()
    } else {
        f64::INFINITY
    };
    let range = x.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - x.iter().cloned().fold(f64::INFINITY, f64::min);
    Trend {
        against: against.into(),
        slope,
        std,
        p_value: if std.is_finite() && std > 0.0 {
            stats::normal_two_sided(slope / std)
        } else {
            1.0
        },
        change_over_range: slope * range,
    }
}

/// Locates the residual `r` (mm) of a fit with `rank` parameters on the part, its noise
/// estimated from `inputs` as well; the residual is structured beyond `detect_factor · σ`.
pub fn locate(
    r: &[f64],
    points: &[PointMeta],
    rank: usize,
    inputs: noise::NoiseInputs,
    reversals: &[Reversal],
    detect_factor: f64,
) -> WhereReport {
    let total_ss: f64 = r.iter().map(|v| v * v).sum();
    let seqs = curve_sequences(points);
    let mut entries = Vec::new();
    for (c, idx) in &seqs {
        entries.push(entry(
            Group::Curve { curve: c.clone() },
            idx,
            points,
            r,
            total_ss,
        ));
    }
    for reg in Region::ALL {
        let idx: Vec<usize> = (0..r.len())
            .filter(|&i| Region::of_u(points[i].u) == reg)
            .collect();
        if !idx.is_empty() {
            entries.push(entry(
                Group::Region { region: reg },
                &idx,
                points,
                r,
                total_ss,
            ));
        }
    }
    for lean in Lean::ALL {
        let idx: Vec<usize> = (0..r.len())
            .filter(|&i| Lean::of_nz(points[i].nz) == lean)
            .collect();
        if !idx.is_empty() {
            entries.push(entry(Group::Lean { lean }, &idx, points, r, total_ss));
        }
    }
    for rev in reversals {
        let idx: Vec<usize> = (0..r.len())
            .filter(|&i| (points[i].s - rev.s).abs() <= REVERSAL_WINDOW_MM)
            .collect();
        let nearest = idx
            .iter()
            .min_by(|&&a, &&b| {
                (points[a].s - rev.s)
                    .abs()
                    .total_cmp(&(points[b].s - rev.s).abs())
            })
            .map(|&i| points[i].id);
        if let Some(nearest) = nearest {
            entries.push(entry(
                Group::Reversal {
                    axis: rev.axis,
                    s: rev.s,
                    nearest,
                    of_verdict: false,
                    marked: false,
                },
                &idx,
                points,
                r,
                total_ss,
            ));
        }
    }
    let h: Vec<f64> = points.iter().map(|p| p.h).collect();
    let order: Vec<f64> = points.iter().map(|p| p.order as f64).collect();
    let s: Vec<f64> = points.iter().map(|p| p.s).collect();
    let trends = vec![
        trend("contact_height", &h, r),
        trend("order", &order, r),
        trend("path_length", &s, r),
    ];

    let seq_vals: Vec<Vec<f64>> = seqs
        .iter()
        .map(|(_, idx)| idx.iter().map(|&i| r[i]).collect())
        .collect();
    let noise = noise::estimate_noise(&seq_vals, inputs);
    // Inserted one by one: `collect` into a map sorts with a copy of the sort code of its own
    // (numerics::order).
    let mut randomness_per_curve = BTreeMap::new();
    for ((c, _), v) in seqs.iter().zip(&seq_vals) {
        randomness_per_curve.insert(c.clone(), noise::randomness(v));
    }
    let randomness = noise::randomness_pooled(&seq_vals);
    let ljung_box = noise::ljung_box(&seq_vals, noise::LJUNG_BOX_LAGS);
    let sigma = noise.used.max(f64::MIN_POSITIVE);
    let dof = r.len().saturating_sub(rank).max(1);
    let chi2 = total_ss / (sigma * sigma);
    let structure_rms = (total_ss / dof as f64 - sigma * sigma).max(0.0).sqrt();
    let report_implausible = noise.implausible;
    let concentrated_entry = entries
        .iter()
        .enumerate()
        .filter(|(_, e)| matches!(e.group, Group::Curve { .. } | Group::Region { .. }))
        .filter(|(_, e)| e.concentrated)
        .max_by(|(_, a), (_, b)| a.concentration.total_cmp(&b.concentration))
        .map(|(k, _)| k);
    let mut report = WhereReport {
        concentrated_in: concentrated_entry.map(|k| entries[k].name.clone()),
        concentrated_entry,
        verdict_axes: Vec::new(),
        entries,
        trends,
        noise,
        randomness_per_curve,
        randomness,
        ljung_box,
        chi2,
        chi2_dof: dof,
        chi2_p: stats::chi2_sf(chi2, dof as f64),
        structure_rms,
        // (a σ̂ more than noise can plausibly be is structure, whatever its size against σ̂)
        structured: structure_rms > detect_factor * sigma || report_implausible,
    };
    // No verdict yet: a reversal is marked when the residual is concentrated near it.
    report.mark_verdict_axes(&[]);
    report
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::part::Surface;

    /// 20 points on two curves, `u` and `s` increasing; residual zero except in the first turn.
    fn points() -> Vec<PointMeta> {
        (0..20)
            .map(|i| {
                let k = i % 10;
                PointMeta {
                    id: 100 + i as u32,
                    curve: if i < 10 { "A_Z11" } else { "A_Z25" }.into(),
                    surface: Surface::A,
                    u: (k as f64 + 0.5) / 10.0,
                    h: if i < 10 { 11.0 } else { 25.0 },
                    s: 20.0 * k as f64,
                    order: i,
                    nz: 0.0,
                }
            })
            .collect()
    }

    #[test]
    fn entries_name_their_points_and_reversals_their_nearest_point() {
        let pts = points();
        let r: Vec<f64> = pts
            .iter()
            .map(|p| {
                if Region::of_u(p.u) == Region::Turn1 {
                    0.004
                } else {
                    0.0
                }
            })
            .collect();
        let rev = [Reversal {
            axis: AxisName::C,
            s: 62.0,
        }];
        let mut w = locate(
            &r,
            &pts,
            0,
            noise::NoiseInputs {
                floor: Some(0.001),
                ..Default::default()
            },
            &rev,
            DETECT_FACTOR,
        );
        // Each group's ids are exactly its points (closed form: the rules of regions.rs).
        for e in &w.entries {
            let expect: Vec<u32> = pts
                .iter()
                .filter(|p| match &e.group {
                    Group::Curve { curve } => p.curve == *curve,
                    Group::Region { region } => Region::of_u(p.u) == *region,
                    Group::Lean { lean } => Lean::of_nz(p.nz) == *lean,
                    Group::Reversal { .. } => (p.s - 62.0).abs() <= REVERSAL_WINDOW_MM,
                })
                .map(|p| p.id)
                .collect();
            assert_eq!(e.ids, expect, "{}", e.name);
            assert_eq!(e.n, e.ids.len());
        }
        let rv = w
            .entries
            .iter()
            .find(|e| matches!(e.group, Group::Reversal { .. }))
            .unwrap();
        // s = 60 (k = 3) is the nearest to 62 mm; the first curve's point comes first.
        let Group::Reversal { nearest, axis, .. } = rv.group else {
            unreachable!()
        };
        assert_eq!((nearest, axis), (103, AxisName::C));
        assert_eq!(rv.name, "C@62.0");
        // The window 52..72 mm holds k = 3 (s = 60 mm, u = 0.35, in turn_1) of each curve: 2 of
        // the 6 non-zero residuals on 2 of 20 points, 3.3 × its share: concentrated, so marked.
        assert!(rv.concentrated);
        let marked = |w: &WhereReport| {
            w.entries
                .iter()
                .filter(|e| matches!(e.group, Group::Reversal { marked: true, .. }))
                .count()
        };
        assert_eq!(marked(&w), 1);
        w.mark_verdict_axes(&[AxisName::X]);
        assert_eq!(marked(&w), 1, "still concentrated");
        let k = w.concentrated_entry.unwrap();
        assert_eq!(
            w.entries[k].group,
            Group::Region {
                region: Region::Turn1
            }
        );
        assert_eq!(w.concentrated_in.as_deref(), Some("turn_1"));
    }
}
