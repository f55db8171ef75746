//! A scan read as a scan: the points of a scanning CMM grouped by surface and scan line, from the
//! data alone (no id, no curve label needed).
//!
//! A scanning CMM sweeps each flank of the S-shape along lines of constant height. The points of
//! one surface are sorted by height `z` (mm, of the point on the nominal surface) and cut where
//! two consecutive heights differ by more than [`LINE_GAP_MM`]: each run is a scan line, labelled
//! `A_Z12.5` (surface, mean height to the µm, trailing zeros dropped: a line at a measurement
//! curve's height carries that curve's name). Along a line the points are in increasing `u`
//! ([`crate::effects::data::curve_sequences`]), whatever their order in the file.
//!
//! A file is read as a scan when it has at least [`SCAN_MIN_POINTS`] points and its lines hold a
//! median of at least [`SCAN_MIN_LINE_POINTS`] points; else it is a discrete layout, each point
//! labelled with the nearer measurement curve as before (the built-in 100 points, a lab's 30-200
//! points: [`crate::measurement::layout`]). The layout (surfaces, lines, points per line, the
//! spacing along and between the lines) is reported ([`ScanLayout`]).

use serde::Serialize;

use crate::numerics::order::{sort_by_key_f64, sort_f64};
use crate::part::{MeasurementPoint, Surface};

/// Heights further apart than this (mm) are on different scan lines (a scan's lines are 0.3 mm
/// or more apart; a line's own points agree in height to the µm).
pub const LINE_GAP_MM: f64 = 0.05;
/// Fewest points of a file read as a scan (a discrete plan has at most a few hundred).
pub const SCAN_MIN_POINTS: usize = 500;
/// Fewest points on the median line of a scan.
pub const SCAN_MIN_LINE_POINTS: usize = 12;

/// One scan line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScanLine {
    /// `A_Z12.5`: surface and mean height.
    pub label: String,
    pub surface: Surface,
    /// Mean height of its points (mm).
    pub height: f64,
    pub points: usize,
    /// Median distance between consecutive points along the line (mm; 0 for one point).
    pub spacing: f64,
}

/// Minimum, median and maximum of a count or a length.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Spread {
    pub min: f64,
    pub median: f64,
    pub max: f64,
}

impl Spread {
    /// Of `v` (not empty).
    fn of(mut v: Vec<f64>) -> Self {
        sort_f64(&mut v);
        Self {
            min: v.first().copied().unwrap_or(0.0),
            median: v.get(v.len() / 2).copied().unwrap_or(0.0),
            max: v.last().copied().unwrap_or(0.0),
        }
    }
}

/// The layout of a scan: its lines and their spread.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScanLayout {
    pub points: usize,
    /// Surfaces scanned (`A`, `B`).
    pub surfaces: Vec<Surface>,
    /// Lines per surface, in the order of `surfaces`.
    pub lines_per_surface: Vec<usize>,
    /// Points per line.
    pub points_per_line: Spread,
    /// Spacing along the lines (mm, each line's median).
    pub spacing: Spread,
    /// Height step between consecutive lines of a surface (mm).
    pub line_step: Spread,
    /// Every line, surface A's first, bottom to top.
    pub lines: Vec<ScanLine>,
}

/// A file's points read as a scan: its layout and the line label of every point.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanReading {
    pub layout: ScanLayout,
    /// The label of each point's line, in point order.
    pub labels: Vec<String>,
}

/// `A_Z12.5`: the surface and the height to the µm, trailing zeros dropped.
pub fn line_label(surface: Surface, z: f64) -> String {
    let text = format!("{z:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    format!("{}_Z{text}", surface.name())
}

/// The points read as a scan (module docs), or `None` for a discrete layout.
pub fn read_scan(points: &[MeasurementPoint]) -> Option<ScanReading> {
    if points.len() < SCAN_MIN_POINTS {
        return None;
    }
    let mut labels = vec![String::new(); points.len()];
    let mut lines = Vec::new();
    let mut surfaces = Vec::new();
    let mut lines_per_surface = Vec::new();
    let mut steps = Vec::new();
    for s in Surface::BOTH {
        let mut idx: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].surface == s)
            .collect();
        if idx.is_empty() {
            continue;
        }
        sort_by_key_f64(&mut idx, |&i| points[i].point.z);
        let runs = height_runs(points, &idx);
        let first_line = lines.len();
        for run in &runs {
            let height = run.iter().map(|&i| points[i].point.z).sum::<f64>() / run.len() as f64;
            let label = line_label(s, height);
            for &i in run {
                labels[i] = label.clone();
            }
            lines.push(ScanLine {
                label,
                surface: s,
                height,
                points: run.len(),
                spacing: spacing_along(points, run),
            });
        }
        steps.extend(
            lines[first_line..]
                .windows(2)
                .map(|w| w[1].height - w[0].height),
        );
        surfaces.push(s);
        lines_per_surface.push(runs.len());
    }
    let points_per_line = Spread::of(lines.iter().map(|l| l.points as f64).collect());
    if points_per_line.median < SCAN_MIN_LINE_POINTS as f64 {
        return None;
    }
    let layout = ScanLayout {
        points: points.len(),
        surfaces,
        lines_per_surface,
        points_per_line,
        spacing: Spread::of(lines.iter().map(|l| l.spacing).collect()),
        line_step: if steps.is_empty() {
            Spread {
                min: 0.0,
                median: 0.0,
                max: 0.0,
            }
        } else {
            Spread::of(steps)
        },
        lines,
    };
    Some(ScanReading { layout, labels })
}

/// The runs of `idx` (sorted by height) whose consecutive heights differ by at most
/// [`LINE_GAP_MM`].
fn height_runs(points: &[MeasurementPoint], idx: &[usize]) -> Vec<Vec<usize>> {
    let mut runs: Vec<Vec<usize>> = Vec::new();
    let mut last = f64::NEG_INFINITY;
    for &i in idx {
        let z = points[i].point.z;
        match runs.last_mut() {
            Some(run) if z - last <= LINE_GAP_MM => run.push(i),
            _ => runs.push(vec![i]),
        }
        last = z;
    }
    runs
}

/// Median distance (mm) between consecutive points of a line in increasing `u`.
fn spacing_along(points: &[MeasurementPoint], run: &[usize]) -> f64 {
    let mut by_u = run.to_vec();
    sort_by_key_f64(&mut by_u, |&i| points[i].u);
    let d: Vec<f64> = by_u
        .windows(2)
        .map(|w| (points[w[1]].point - points[w[0]].point).norm())
        .collect();
    if d.is_empty() {
        0.0
    } else {
        Spread::of(d).median
    }
}

/// One sentence for the report: `Scan: 20000 points, 2 surfaces × 40 lines, 250 points a line
/// (0.94 mm apart), lines 0.615 mm apart.`
pub fn sentence(l: &ScanLayout) -> String {
    let per = |s: &Spread| {
        if s.min == s.max {
            format!("{}", s.median)
        } else {
            format!("{}-{} (median {})", s.min, s.max, s.median)
        }
    };
    let lines: Vec<String> = l
        .surfaces
        .iter()
        .zip(&l.lines_per_surface)
        .map(|(s, n)| format!("{n} lines on {}", s.name()))
        .collect();
    format!(
        "Scan: {} points, {}, {} points a line ({:.3} mm apart along it), lines {:.3} mm apart.",
        l.points,
        lines.join(", "),
        per(&l.points_per_line),
        l.spacing.median,
        l.line_step.median
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::part::{builtin_points, SShape};

    #[test]
    fn dense_scan_lines_are_found_from_heights_alone() {
        let part = SShape::iso();
        let layout = crate::part::ScanLayout {
            heights: 7,
            rulings: 40,
        };
        let mut pts = layout.scan_points(&part);
        // the order of the file does not matter
        pts.reverse();
        let r = read_scan(&pts).unwrap();
        assert_eq!(r.layout.lines_per_surface, vec![7, 7]);
        assert_eq!(r.layout.points_per_line.min, 40.0);
        assert_eq!(r.layout.points_per_line.max, 40.0);
        // 24 mm over 6 steps; tolerance 1e-9 mm (the heights' rounding)
        assert!((r.layout.line_step.median - 4.0).abs() < 1e-9);
        assert_eq!(r.layout.lines[0].label, "A_Z3");
        assert_eq!(r.layout.lines[1].label, "A_Z7");
        assert_eq!(r.labels[0], "B_Z27");
    }

    #[test]
    fn dense_discrete_layouts_are_not_scans() {
        let pts = builtin_points(&SShape::iso());
        assert!(read_scan(&pts).is_none());
        assert_eq!(line_label(Surface::B, 11.0), "B_Z11");
        assert_eq!(line_label(Surface::A, 12.3456), "A_Z12.346");
    }
}
