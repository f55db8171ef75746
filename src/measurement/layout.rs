//! What a layout of measured points can and cannot tell: points per curve, curves not measured,
//! the estimators it weakens, and the candidates it cannot see.
//!
//! The built-in layout is 25 points on each of the four curves (s-shape.md). A lab may send 30
//! to 200 points, leave a curve out, number the points its own way and write the rows in any
//! order: the diagnosis groups points by curve label and orders them by `u`, so the rules hold on
//! any layout, with these limits:
//! - the per-curve smooth basis of [`crate::measurement::smooth_noise`] has degree `min(5, ⌊m/2⌋ − 1)` on a
//!   curve of `m` points ([`curve_degree`]): at least half of each curve's points stay free to
//!   measure the noise (with 6 points a degree-5 basis would fit them exactly and leave no
//!   noise to see); a waviness the lower degree cannot follow then counts as noise there;
//! - the Ljung–Box test skips curves of fewer than `lags + 3` = 7 points;
//! - a candidate whose signature the location errors absorb entirely on these points (added rank
//!   0) cannot be detected at any size; the others have a detection limit per parameter (in the
//!   candidate's `evidence.detection_limit`).

use serde::Serialize;

use crate::effects::data::PointMeta;
use crate::effects::data::{curve_sequences, is_scan};
use crate::measurement::noise::LJUNG_BOX_LAGS;
use crate::measurement::smooth_noise::SMOOTH_DEGREE;
use crate::parameter::Effect;
use crate::part::Curve;

/// Fewest points on a curve for the full [`SMOOTH_DEGREE`] basis (`⌊m/2⌋ − 1 ≥ 5`).
pub const FULL_BASIS_POINTS: usize = 12;

/// Degree of the smooth basis on a curve of `m` points: `min(max_degree, ⌊m/2⌋ − 1)`, 0 below 4.
pub fn curve_degree(m: usize, max_degree: usize) -> usize {
    (m / 2).saturating_sub(1).min(max_degree)
}

/// Points on one curve.
#[derive(Debug, Clone, Serialize)]
pub struct CurveCount {
    pub curve: String,
    pub points: usize,
    /// Degree of the smooth basis there ([`curve_degree`]).
    pub smooth_degree: usize,
}

/// The layout of the measured points and what it limits.
#[derive(Debug, Clone, Serialize)]
pub struct Layout {
    pub points: usize,
    pub curves: Vec<CurveCount>,
    /// Curves of the built-in layout (s-shape.md) with no point.
    pub not_measured: Vec<String>,
    /// Candidates the location errors absorb entirely on these points.
    pub invisible: Vec<Effect>,
    /// Whether it is the built-in layout's shape: the four curves, each with at least
    /// [`FULL_BASIS_POINTS`] points.
    pub full: bool,
    /// Plain-language limits (empty for a full layout).
    pub notes: Vec<String>,
}

/// The layout of `points`; `invisible`: the candidates these points cannot show (no rank added
/// to the baseline), in any order.
pub fn layout(points: &[PointMeta], invisible: Vec<Effect>) -> Layout {
    let seqs = curve_sequences(points);
    let curves: Vec<CurveCount> = seqs
        .iter()
        .map(|(c, idx)| CurveCount {
            curve: c.clone(),
            points: idx.len(),
            smooth_degree: curve_degree(idx.len(), SMOOTH_DEGREE),
        })
        .collect();
    // a scan's lines are not the measurement curves: none of those is missing
    let scan = is_scan(points);
    let not_measured: Vec<String> = Curve::ALL
        .iter()
        .map(|c| c.name().to_string())
        .filter(|name| !scan && !curves.iter().any(|c| &c.curve == name))
        .collect();
    // by id, inserted one at a time (a few effects; no instance of the standard sort for it,
    // numerics::order)
    let mut by_id: Vec<Effect> = Vec::with_capacity(invisible.len());
    for e in invisible {
        let at = by_id.partition_point(|x| x.id() <= e.id());
        by_id.insert(at, e);
    }
    let invisible = by_id;
    let full = not_measured.is_empty()
        && curves.iter().all(|c| {
            c.points
                >= if scan {
                    LJUNG_BOX_LAGS + 3
                } else {
                    FULL_BASIS_POINTS
                }
        });
    let mut notes = Vec::new();
    if !not_measured.is_empty() {
        notes.push(format!(
            "not measured: {}; the errors and effects are seen through the other curves only",
            not_measured.join(", ")
        ));
    }
    // a scan's smooth basis is over its surfaces, not per line (smooth_noise::surface_basis)
    let short: Vec<String> = curves
        .iter()
        .filter(|c| !scan && c.points < FULL_BASIS_POINTS)
        .map(|c| {
            format!(
                "{} ({} points, degree {})",
                c.curve, c.points, c.smooth_degree
            )
        })
        .collect();
    if !short.is_empty() {
        notes.push(format!(
            "few points on {}: the smooth basis that measures the noise is of lower degree there, \
             so a waviness shorter than about a third of the curve counts as noise",
            short.join(", ")
        ));
    }
    let no_whiteness: Vec<&str> = curves
        .iter()
        .filter(|c| c.points < LJUNG_BOX_LAGS + 3)
        .map(|c| c.curve.as_str())
        .collect();
    if !no_whiteness.is_empty() {
        notes.push(format!(
            "no whiteness test on {} (fewer than {} points)",
            no_whiteness.join(", "),
            LJUNG_BOX_LAGS + 3
        ));
    }
    if !invisible.is_empty() && !full {
        let ids: Vec<&str> = invisible.iter().map(|e| e.id()).collect();
        notes.push(format!(
            "cannot be detected on these points at any size (the location errors absorb them): {}",
            ids.join(", ")
        ));
    }
    Layout {
        points: points.len(),
        curves,
        not_measured,
        invisible,
        full,
        notes,
    }
}

/// One sentence for the report; `None` for a full layout.
pub fn sentence(l: &Layout) -> Option<String> {
    (!l.full).then(|| {
        let counts: Vec<String> = l
            .curves
            .iter()
            .map(|c| format!("{} {}", c.curve, c.points))
            .collect();
        format!(
            "Layout: {} points ({}); {}.",
            l.points,
            counts.join(", "),
            l.notes.join("; ")
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degree_leaves_half_the_points_free() {
        assert_eq!(curve_degree(25, 5), 5);
        assert_eq!(curve_degree(12, 5), 5);
        assert_eq!(curve_degree(11, 5), 4);
        assert_eq!(curve_degree(8, 5), 3);
        assert_eq!(curve_degree(6, 5), 2);
        assert_eq!(curve_degree(3, 5), 0);
        for m in 2..60 {
            assert!(curve_degree(m, 5) < m.div_ceil(2).max(1), "{m}");
        }
    }
}
