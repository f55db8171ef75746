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
//! A surface whose heights do not fall into lines (a run of heights wider than [`LINE_SPAN_MM`],
//! or runs of fewer than [`SCAN_MIN_LINE_POINTS`] points on the median: a scan along the rulings
//! at staggered heights, or a cloud of points) is cut into height bands
//! of equal counts instead, as many as a square grid of its points would have lines
//! ([`band_count`]), each band then read as a line: withheld, smoothed and tested along the path
//! like one. Read as one line per surface, such a file (20,000 points on 250 staggered rulings)
//! had withheld whole surfaces in its cross-validation, mapped each surface as one row and
//! reported its lines 0.000 mm apart.
//!
//! A file is read as a scan when it has at least [`SCAN_MIN_POINTS`] points and its lines hold a
//! median of at least [`SCAN_MIN_LINE_POINTS`] points; else it is a discrete layout, each point
//! labelled with the nearer measurement curve as before (the built-in 100 points, a lab's 30-200
//! points: [`crate::measurement::layout`]). The layout (surfaces, lines or bands, points per line,
//! the spacing along and between the lines) is reported ([`ScanLayout`]).

use serde::Serialize;

use crate::numerics::order::{sort_by_key_f64, sort_f64};
use crate::part::{MeasurementPoint, Surface};

/// Heights further apart than this (mm) are on different scan lines (a scan's lines are 0.3 mm
/// or more apart; a line's own points agree in height to the µm).
pub const LINE_GAP_MM: f64 = 0.05;
/// The widest run of heights (mm) read as one scan line. A line of constant height agrees to the
/// µm in its nominal feet (a deviation moves a foot along the normal, whose z component is at
/// most 0.25 on the S-shape's flanks: 0.05 mm for a 0.2 mm deviation); a wider run joins points
/// spread over the heights, and its surface is read in height bands.
pub const LINE_SPAN_MM: f64 = 0.5;
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
    /// The surfaces (of `surfaces`) whose points are not on lines of constant height, read in
    /// height bands of equal counts ([`LINE_SPAN_MM`]): their `lines` are the bands.
    pub banded: Vec<Surface>,
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
    let mut banded = Vec::new();
    for s in Surface::BOTH {
        let mut idx: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].surface == s)
            .collect();
        if idx.is_empty() {
            continue;
        }
        sort_by_key_f64(&mut idx, |&i| points[i].point.z);
        let mut runs = height_runs(points, &idx);
        let span = |run: &[usize]| match (run.first(), run.last()) {
            (Some(&lo), Some(&hi)) => points[hi].point.z - points[lo].point.z,
            _ => 0.0,
        };
        let mut sizes: Vec<f64> = runs.iter().map(|r| r.len() as f64).collect();
        sort_f64(&mut sizes);
        let few = sizes[sizes.len() / 2] < SCAN_MIN_LINE_POINTS as f64;
        if idx.len() >= 2 * SCAN_MIN_LINE_POINTS
            && (few || runs.iter().any(|r| span(r) > LINE_SPAN_MM))
        {
            runs = height_bands(&idx, band_count(points, &idx));
            banded.push(s);
        }
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
        banded,
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

/// `idx` (sorted by height) cut into `k` bands of equal counts (band `b` from `b·n/k`: some one
/// point more where `k` does not divide `n`).
fn height_bands(idx: &[usize], k: usize) -> Vec<Vec<usize>> {
    let (n, k) = (idx.len(), k.clamp(1, idx.len().max(1)));
    (0..k)
        .map(|b| idx[b * n / k..(b + 1) * n / k].to_vec())
        .collect()
}

/// How many height bands a surface's points `idx` (sorted by height) are read in: the lines of a
/// square grid of as many points over the same heights and length, `√(n·Δz/L)` (n points,
/// heights over Δz, a band of `n/k` points over the length `L` then as far apart along it as the
/// bands' `Δz/k`), at least 2 and at most as many as hold [`SCAN_MIN_LINE_POINTS`] points each.
/// `L` is the polyline through at most 64 points, in increasing `u`, of the 1/16 of the points
/// nearest the middle height (each step far longer than the band's own sideways zig-zag).
fn band_count(points: &[MeasurementPoint], idx: &[usize]) -> usize {
    let n = idx.len();
    let (Some(&lo), Some(&hi)) = (idx.first(), idx.last()) else {
        return 1;
    };
    let dz = points[hi].point.z - points[lo].point.z;
    let half = (n / 32).max(1);
    let mut mid = idx[n / 2 - half.min(n / 2)..(n / 2 + half).min(n)].to_vec();
    sort_by_key_f64(&mut mid, |&i| points[i].u);
    let step = mid.len().div_ceil(64).max(1);
    let sub: Vec<usize> = mid
        .iter()
        .step_by(step)
        .chain(mid.last())
        .copied()
        .collect();
    let length: f64 = sub
        .windows(2)
        .map(|w| (points[w[1]].point - points[w[0]].point).norm())
        .sum();
    let most = (n / SCAN_MIN_LINE_POINTS).max(1);
    if length <= 0.0 || dz <= 0.0 {
        return most.min(2);
    }
    ((n as f64 * dz / length).sqrt().round() as usize).clamp(2.min(most), most)
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
        .map(|(s, n)| {
            let what = if l.banded.contains(s) {
                "height bands"
            } else {
                "lines"
            };
            format!("{n} {what} on {}", s.name())
        })
        .collect();
    let banded = if l.banded.is_empty() {
        String::new()
    } else {
        let names: Vec<&str> = l.banded.iter().map(|s| s.name()).collect();
        format!(
            " The points of {} are not on lines of constant height: they are read in bands of \
             heights of equal counts, each band as a line.",
            names.join(" and ")
        )
    };
    format!(
        "Scan: {} points, {}, {} points a line ({:.3} mm apart along it), lines {:.3} mm apart.{banded}",
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

    /// The points of `simulate --scan HEIGHTSxRULINGS` on `part`.
    fn scan(part: &SShape, heights: usize, rulings: usize) -> Vec<MeasurementPoint> {
        crate::part::ScanLayout { heights, rulings }.scan_points(part)
    }

    #[test]
    fn dense_scan_lines_are_found_from_heights_alone() {
        let part = SShape::iso();
        let mut pts = scan(&part, 7, 40);
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

    /// Heights that form no lines (each surface's 1,000 points at 100 heights 0.242 mm apart, 10
    /// points a height: `simulate --scan 100x10`, runs of fewer than 12 points; `--scan 1000x10`,
    /// heights 0.024 mm apart, one run a surface) are cut into bands of equal counts,
    /// `√(n·Δz/L)` of them: √(1000 · 24 mm / L) with `L` the mid-height curve from 5 % to 95 %
    /// of its length (587.5 mm on either surface: 6.39, so 6); a grid of lines keeps its lines.
    #[test]
    fn heights_that_form_no_lines_are_read_in_bands() {
        let part = SShape::iso();
        let r = read_scan(&scan(&part, 100, 10)).unwrap();
        assert_eq!(r.layout.banded, vec![Surface::A, Surface::B]);
        for s in Surface::BOTH {
            let l = 0.9 * crate::part::points::arc_length_table(&part, s, 0.5).total();
            let k = (1000.0 * 24.0 / l).sqrt().round() as usize;
            assert_eq!(k, 6, "{l}");
        }
        assert_eq!(r.layout.lines_per_surface, vec![6, 6]);
        // 1,000 points in 6 bands: 166 or 167 each, bottom to top, each band's heights its own
        assert_eq!(r.layout.points_per_line.min, 166.0);
        assert_eq!(r.layout.points_per_line.max, 167.0);
        let a: Vec<&ScanLine> = r.layout.lines.iter().take(6).collect();
        for w in a.windows(2) {
            assert!(w[1].height - w[0].height > 3.9, "{w:?}");
        }
        assert!(sentence(&r.layout).contains("6 height bands on A, 6 height bands on B"));
        assert!(read_scan(&scan(&part, 7, 40))
            .unwrap()
            .layout
            .banded
            .is_empty());
        // one run a surface, 24 mm wide: 10,000 points, √(10000 · 24 / 587.5) = 20.2 bands
        assert_eq!(
            read_scan(&scan(&part, 1000, 10))
                .unwrap()
                .layout
                .lines_per_surface,
            vec![20, 20]
        );
        assert_eq!(
            height_bands(&[4, 5, 6, 7, 8], 2),
            vec![vec![4, 5], vec![6, 7, 8]]
        );
    }

    #[test]
    fn dense_discrete_layouts_are_not_scans() {
        let pts = builtin_points(&SShape::iso());
        assert!(read_scan(&pts).is_none());
        assert_eq!(line_label(Surface::B, 11.0), "B_Z11");
        assert_eq!(line_label(Surface::A, 12.3456), "A_Z12.346");
    }
}
