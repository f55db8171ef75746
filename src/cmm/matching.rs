//! Matching CMM points to the nominal S-shape and their normal deviations
//! (cmm-csv.md "What the reader does with what it finds", s-shape.md "Measurement points").
//!
//! Every point is matched by closest-point projection of its *own* coordinates onto the nominal
//! surfaces ([`crate::part::projection::project`]), never by its id: the nominal position
//! where the file gives one, else the measured position. The projection gives the surface,
//! `(u, v)`, the foot point and the model's outward normal `N(u,v)`. Then:
//! 1. nominal position + deviation: the file's deviation is used;
//! 2. nominal + measured positions: `deviation = (measured − nominal)·N`;
//! 3. measured positions only: `deviation = (measured − foot)·N`, the signed distance;
//! 4. a deviation and positions: the deviation is used, with a warning where the positions give
//!    one differing by more than [`ReadOptions::deviation_warn_mm`] (1 µm).
//!
//! A file normal is compared with `N`: above [`ReadOptions::normal_warn_deg`] (2°) a warning,
//! noting a normal that points into the material (another sign convention). A point further
//! than [`ReadOptions::max_distance_mm`] (2 mm) from the surfaces, or with a larger deviation, is
//! a bad row whose message says whether another unit would bring it onto the part, else that
//! the alignment is off. Units: mm; deviation + = material left, − = overcut.

use crate::numerics::parallel::map_mut;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::error::{CmmError, RowProblem, RowProblemKind};
use super::options::ReadOptions;
use super::table::{CmmFile, CmmPoint, CmmWarning, FormatInfo};
use crate::geometry::GeometryError;
use crate::numerics::order::sort_by_index;
use crate::part::projection::{Projection, Projector};
use crate::part::{SShape, Surface};

/// Which rule of cmm-csv.md gave the deviation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DeviationRule {
    /// Rules 1 and 4: the deviation written in the file.
    FileDeviation,
    /// Rule 2: `(measured − nominal)·N`.
    MeasuredMinusNominal,
    /// Rule 3: signed distance of the measured point from the surface.
    Projection,
}

/// A point matched to the nominal part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatchedPoint {
    /// The row as read from the file.
    pub file: CmmPoint,
    pub surface: Surface,
    /// Surface parameters of the foot point (`v = z/30`).
    pub u: f64,
    pub v: f64,
    /// Foot of the projection on the nominal surface (mm).
    pub foot: [f64; 3],
    /// The model's outward unit normal `N(u,v)` at the foot.
    pub normal: [f64; 3],
    /// Normal deviation (mm), + = material left, − = overcut.
    pub deviation: f64,
    pub rule: DeviationRule,
    /// Signed distance of the projected coordinates (nominal if given, else measured) from the
    /// surface (mm).
    pub distance: f64,
    /// Whether the foot lies on an end of the surface (`u` = 0 or 1).
    pub clamped: bool,
    /// Angle between the file's normal and `N` (degrees), where the file has a normal.
    pub normal_angle_deg: Option<f64>,
    /// Deviation given by the positions where the file also writes one (rule 4).
    pub position_deviation: Option<f64>,
}

/// A CMM file matched to the nominal part: the data for identification.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatchedPart {
    pub name: String,
    pub format: FormatInfo,
    pub extra_columns: Vec<String>,
    pub points: Vec<MatchedPoint>,
    /// Rows excluded at the caller's explicit request (reading and matching), with reasons.
    pub excluded: Vec<RowProblem>,
    /// Warnings of reading and matching.
    pub warnings: Vec<CmmWarning>,
}

impl MatchedPart {
    /// Deviations in point order (mm).
    pub fn deviations(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.deviation).collect()
    }

    /// Distinct line numbers of the excluded rows, ascending.
    pub fn excluded_lines(&self) -> Vec<usize> {
        let mut l: Vec<usize> = self.excluded.iter().map(|p| p.line).collect();
        l.sort_unstable();
        l.dedup();
        l
    }
}

fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// Collects one kind of remark over many points into a single warning.
struct Tally {
    what: &'static str,
    lines: Vec<usize>,
    worst: Option<(usize, f64, String)>,
}

impl Tally {
    fn new(what: &'static str) -> Self {
        Self {
            what,
            lines: Vec::new(),
            worst: None,
        }
    }
    fn add(&mut self, line: usize, size: f64, detail: String) {
        self.lines.push(line);
        if self.worst.as_ref().is_none_or(|w| size > w.1) {
            self.worst = Some((line, size, detail));
        }
    }

    /// The tally of this one's points followed by `next`'s: the same as adding them one by one
    /// (the lines in order; the worst replaced only by a strictly larger one, as [`Tally::add`]
    /// does; no size added is NaN: each is added behind a comparison that NaN fails, or is a
    /// distance or a constant).
    fn append(&mut self, next: Tally) {
        self.lines.extend(next.lines);
        if let Some(w) = next.worst {
            if self.worst.as_ref().is_none_or(|s| w.1 > s.1) {
                self.worst = Some(w);
            }
        }
    }

    fn warning(self) -> Option<CmmWarning> {
        let (line, _, detail) = self.worst?;
        let list = self
            .lines
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(", ");
        Some(CmmWarning::at(
            line,
            format!(
                "{} point(s) {} (lines {list}); largest here: {detail}",
                self.lines.len(),
                self.what
            ),
        ))
    }
}

/// [`Projector::project`], but when the projection onto one surface fails (it can fail to converge on
/// the surface far from the point) the other surface's result is used alone.
fn project_point(part: &Projector<SShape>, p: &Vector3<f64>) -> Result<Projection, GeometryError> {
    match part.project(p) {
        Ok(q) => Ok(q),
        Err(first) => {
            let a = part.project_on(Surface::A, p);
            let b = part.project_on(Surface::B, p);
            match (a, b) {
                (Ok(a), Ok(b)) => Ok(if (p - a.foot).norm() <= (p - b.foot).norm() {
                    a
                } else {
                    b
                }),
                (Ok(q), Err(_)) | (Err(_), Ok(q)) => Ok(q),
                (Err(_), Err(_)) => Err(first),
            }
        }
    }
}

/// Whether a curve label names a surface (`A_Z11` → A).
fn surface_of_label(label: &str) -> Option<Surface> {
    let t = label.trim();
    let mut chars = t.chars();
    let first = chars.next()?.to_ascii_uppercase();
    let next = chars.next();
    if next.is_some_and(|c| c.is_ascii_alphanumeric()) {
        return None;
    }
    match first {
        'A' => Some(Surface::A),
        'B' => Some(Surface::B),
        _ => None,
    }
}

/// Why a point is far: another unit that brings it onto the part, or the alignment.
fn far_reason(part: &Projector<SShape>, p: &Vector3<f64>, max_mm: f64) -> String {
    for (f, what) in [
        (25.4, "inches read as mm"),
        (1.0 / 25.4, "mm read as inches"),
        (1e-3, "µm read as mm"),
        (1e3, "mm read as µm"),
    ] {
        if let Ok(q) = project_point(part, &(p * f)) {
            if (p * f - q.foot).norm() <= max_mm {
                return format!(
                    "multiplied by {f} it would lie on the part: probably a wrong unit ({what})"
                );
            }
        }
    }
    "no unit conversion brings it onto the part: probably the alignment (part origin and axes of the part frame: paper 000 Table 1's, Z = 0 at the base, Z up), or a point not on the test piece (probe slip, fixture)".into()
}

/// Matches the points of `file` to `part` with the rules of the module docs. Bad rows (points
/// too far) reject the file unless `opts.exclude_bad_rows`; then they join `file.excluded`.
pub fn match_points(
    part: &SShape,
    file: CmmFile,
    opts: &ReadOptions,
) -> Result<MatchedPart, CmmError> {
    let projector = Projector::new(part);
    let mut rows = file.points;
    let n = rows.len();
    // runs of rows matched side by side on the threads given, each run's matches, bad rows and
    // remarks in the file's order, the runs then joined in order: the first error and the
    // remarks as on one thread. Each row is moved into its match (a copy of each row, the
    // results gathered and then moved once more had been ~6 ms of one thread at 20,000 points,
    // issue 31).
    let size = n
        .div_ceil(opts.threads.get() * MATCH_RUNS_PER_THREAD)
        .max(1);
    let mut runs: Vec<&mut [CmmPoint]> = rows.chunks_mut(size).collect();
    let matched = map_mut(opts.threads, &mut runs, |run| {
        match_run(&projector, run, opts)
    });
    let mut points = Vec::with_capacity(n);
    let mut problems: Vec<RowProblem> = Vec::new();
    let mut remarks = Remarks::new();
    for run in matched {
        let (p, q, r) = run?;
        points.extend(p);
        problems.extend(q);
        remarks.append(r);
    }
    let mut warnings = file.warnings;
    let mut excluded = file.excluded;
    let rows = points.len() + problems.len();
    exclude_far_rows(problems, rows, opts, &mut warnings, &mut excluded)?;
    if points.len() < opts.min_points {
        return Err(CmmError::too_few_points(
            points.len(),
            opts.min_points,
            excluded.len(),
        ));
    }
    refuse_nominal_positions(&points, &file.format)?;
    warnings.extend(remarks.warnings());
    Ok(MatchedPart {
        name: file.name,
        format: file.format,
        extra_columns: file.extra_columns,
        points,
        excluded,
        warnings,
    })
}

/// A file of positions alone (no measured column, no deviation) whose every point lies within
/// this distance of the nominal surface (mm, 0.1 µm: far below any CMM's repeatability) holds
/// nominal positions, not a measurement.
pub const NOMINAL_ONLY_MM: f64 = 1e-4;

/// Refuses a file of nominal positions read as measured ([`NOMINAL_ONLY_MM`]), naming the
/// columns found: otherwise it would be identified as a machine with every error zero.
fn refuse_nominal_positions(points: &[MatchedPoint], format: &FormatInfo) -> Result<(), CmmError> {
    let largest = points.iter().map(|p| p.deviation.abs()).fold(0.0, f64::max);
    if !format.positions_read_as_measured || points.is_empty() || largest > NOMINAL_ONLY_MM {
        return Ok(());
    }
    Err(CmmError::NoMeasurement {
        points: points.len(),
        largest_um: largest * 1e3,
        columns: format
            .columns
            .iter()
            .map(|c| c.header.as_str())
            .collect::<Vec<_>>()
            .join(", "),
    })
}

/// Runs of rows a thread in [`match_points`]: the last runs still balance the threads.
const MATCH_RUNS_PER_THREAD: usize = 16;

/// The matches of a run of rows ([`match_point`] each, the row moved out of the file into its
/// match), its bad rows and its remarks, in the rows' order; the first error of the run.
fn match_run(
    projector: &Projector<SShape>,
    run: &mut [CmmPoint],
    opts: &ReadOptions,
) -> Result<(Vec<MatchedPoint>, Vec<RowProblem>, Remarks), CmmError> {
    let mut points = Vec::with_capacity(run.len());
    let mut problems = Vec::new();
    let mut remarks = Remarks::new();
    for row in run.iter_mut() {
        match match_point(projector, take_row(row), opts)? {
            Ok((point, gap)) => {
                remarks.note(&point, gap, opts);
                points.push(point);
            }
            Err(problem) => problems.push(problem),
        }
    }
    Ok((points, problems, remarks))
}

/// The row, moved out of `row` (left with its line and nothing else: no allocation).
fn take_row(row: &mut CmmPoint) -> CmmPoint {
    let empty = CmmPoint {
        line: row.line,
        id: String::new(),
        curve: None,
        nominal: None,
        normal: None,
        measured: None,
        deviation: None,
        extra: Vec::new(),
    };
    std::mem::replace(row, empty)
}

/// Matches one row: closest-point projection of its own coordinates (nominal if given, else
/// measured), the deviation by the rules of the module docs, and the check that the point is
/// near the surfaces: `Ok((point, gap))` with the distance `gap` (mm) of the projected
/// coordinates from the foot, or `Err` with the bad row (no position, or too far from the
/// surfaces). A failed projection is an error of the whole file (the outer `Err`).
fn match_point(
    projector: &Projector<SShape>,
    pt: CmmPoint,
    opts: &ReadOptions,
) -> Result<Result<(MatchedPoint, f64), RowProblem>, CmmError> {
    let Some(pos) = pt.nominal.or(pt.measured) else {
        // The reader guarantees a position; keep the promise not to drop rows silently.
        return Ok(Err(RowProblem {
            line: pt.line,
            column: None,
            kind: RowProblemKind::EmptyValue,
            found: String::new(),
            expected: "a nominal or measured position".into(),
        }));
    };
    let p = v3(pos);
    let proj: Projection = project_point(projector, &p).map_err(|source| CmmError::Projection {
        line: pt.line,
        source,
    })?;
    let n = proj.normal;
    let gap = (p - proj.foot).norm();
    let (deviation, rule, position_deviation) = deviation_by_rule(&pt, &n, proj.distance);
    if let Some(problem) = far_from_surface(projector, &pt, &p, &proj, gap, deviation, opts) {
        return Ok(Err(problem));
    }
    let normal_angle_deg = pt.normal.map(|fnorm| normal_angle_deg(fnorm, &n));
    Ok(Ok((
        MatchedPoint {
            file: pt,
            surface: proj.surface,
            u: proj.u,
            v: proj.v,
            foot: arr(&proj.foot),
            normal: arr(&n),
            deviation,
            rule,
            distance: proj.distance,
            clamped: proj.clamped,
            normal_angle_deg,
            position_deviation,
        },
        gap,
    )))
}

/// The normal deviation of a point (mm, + = material left) by the rules of the module docs,
/// the rule that gave it, and the deviation its positions give where the file also writes one
/// (rule 4). `n`: the model's outward unit normal at the foot; `distance`: the signed distance
/// (mm) of the projected coordinates from the surface.
fn deviation_by_rule(
    pt: &CmmPoint,
    n: &Vector3<f64>,
    distance: f64,
) -> (f64, DeviationRule, Option<f64>) {
    match (pt.nominal, pt.measured, pt.deviation) {
        (Some(nom), Some(meas), d) => {
            let from_pos = (v3(meas) - v3(nom)).dot(n);
            match d {
                Some(d) => (d, DeviationRule::FileDeviation, Some(from_pos)),
                None => (from_pos, DeviationRule::MeasuredMinusNominal, None),
            }
        }
        (Some(_), None, Some(d)) => (d, DeviationRule::FileDeviation, None),
        (None, Some(_), Some(d)) => (d, DeviationRule::FileDeviation, Some(distance)),
        (None, Some(_), None) => (distance, DeviationRule::Projection, None),
        // Nominal without deviation or measured is read as measured by the reader.
        (Some(_), None, None) | (None, None, _) => (distance, DeviationRule::Projection, None),
    }
}

/// The bad row of a point whose projected coordinates `p` lie further than
/// [`ReadOptions::max_distance_mm`] from the surfaces (`gap`, mm) or whose deviation (mm) is
/// larger, saying whether another unit would bring it onto the part; `None` for a near point.
fn far_from_surface(
    projector: &Projector<SShape>,
    pt: &CmmPoint,
    p: &Vector3<f64>,
    proj: &Projection,
    gap: f64,
    deviation: f64,
    opts: &ReadOptions,
) -> Option<RowProblem> {
    let far = gap > opts.max_distance_mm || deviation.abs() > opts.max_distance_mm;
    if !far {
        return None;
    }
    let what = if pt.nominal.is_some() {
        "nominal"
    } else {
        "measured"
    };
    Some(RowProblem {
        line: pt.line,
        column: None,
        kind: RowProblemKind::FarFromSurface,
        found: format!(
            "{what} ({:.4}, {:.4}, {:.4}) mm, {gap:.4} mm from surface {} (u {:.4}, z {:.3}), deviation {deviation:.4} mm",
            p.x,
            p.y,
            p.z,
            proj.surface.name(),
            proj.u,
            proj.foot.z
        ),
        expected: format!(
            "a point within {} mm of the nominal surfaces; {}",
            opts.max_distance_mm,
            far_reason(projector, p, opts.max_distance_mm)
        ),
    })
}

/// Angle (degrees, 0..180) between the file's normal `file_normal` (any length, non-zero) and
/// the model's outward unit normal `n`.
fn normal_angle_deg(file_normal: [f64; 3], n: &Vector3<f64>) -> f64 {
    let f = v3(file_normal);
    let c = (f.dot(n) / f.norm()).clamp(-1.0, 1.0);
    c.acos().to_degrees()
}

/// The remarks matching makes on single points, each kind collected over all points into one
/// warning.
struct Remarks {
    normal_off: Tally,
    inward: Tally,
    disagree: Tally,
    off_surface: Tally,
    wrong_label: Tally,
    at_end: Tally,
}

impl Remarks {
    fn new() -> Self {
        Self {
            normal_off: Tally::new(
                "with a file normal more than the allowed angle from the model's outward normal",
            ),
            inward: Tally::new("with a file normal pointing into the material (the file may use the opposite sign convention: check the sign of its deviations)"),
            disagree: Tally::new("where the file's deviation and the one given by its positions differ by more than the allowed amount; the file's deviation is used (rule 4)"),
            off_surface: Tally::new("whose nominal position lies off the nominal surface by more than 10 µm (the file's deviation is used as given)"),
            wrong_label: Tally::new(
                "whose curve label names the other surface than the one they lie on",
            ),
            at_end: Tally::new(
                "beyond the end of the surface (projected onto its edge u = 0 or 1)",
            ),
        }
    }

    /// These remarks followed by `next`'s (the remarks of the points after these).
    fn append(&mut self, next: Remarks) {
        self.normal_off.append(next.normal_off);
        self.inward.append(next.inward);
        self.disagree.append(next.disagree);
        self.off_surface.append(next.off_surface);
        self.wrong_label.append(next.wrong_label);
        self.at_end.append(next.at_end);
    }

    /// Notes what is remarkable about the matched point `m`: a file normal off the model's
    /// (degrees) or pointing inward, a file deviation that its positions contradict (mm), a
    /// nominal position off the surface by more than 10 µm, a curve label naming the other
    /// surface, a foot on the end of the surface (`gap`: distance from it, mm).
    fn note(&mut self, m: &MatchedPoint, gap: f64, opts: &ReadOptions) {
        let line = m.file.line;
        let deviation = m.deviation;
        if let Some(a) = m.normal_angle_deg {
            if a > 90.0 {
                self.inward.add(line, a, format!("{a:.2}° at line {line}"));
            } else if a > opts.normal_warn_deg {
                self.normal_off.add(
                    line,
                    a,
                    format!("{a:.2}° (limit {}°) at line {line}", opts.normal_warn_deg),
                );
            }
        }
        if let Some(pd) = m.position_deviation {
            let diff = (deviation - pd).abs();
            if diff > opts.deviation_warn_mm {
                self.disagree.add(
                    line,
                    diff,
                    format!(
                        "file {deviation:.6} mm vs positions {pd:.6} mm at line {line} (limit {} mm)",
                        opts.deviation_warn_mm
                    ),
                );
            }
        }
        if m.file.nominal.is_some()
            && m.distance.abs() > 0.01
            && m.rule == DeviationRule::FileDeviation
        {
            self.off_surface.add(
                line,
                m.distance.abs(),
                format!(
                    "{:.4} mm at line {line} (file deviation {deviation:.4} mm{})",
                    m.distance,
                    if (m.distance - deviation).abs() <= opts.deviation_warn_mm {
                        "; these look like measured positions, and they agree with the deviation"
                    } else {
                        ""
                    }
                ),
            );
        }
        if let Some(s) = m.file.curve.as_deref().and_then(surface_of_label) {
            if s != m.surface {
                self.wrong_label.add(
                    line,
                    1.0,
                    format!(
                        "label '{}' but on surface {} at line {line}",
                        m.file.curve.as_deref().unwrap_or(""),
                        m.surface.name(),
                    ),
                );
            }
        }
        if m.clamped {
            self.at_end.add(
                line,
                gap,
                format!("{gap:.4} mm from the edge at line {line}"),
            );
        }
    }

    /// One warning per kind of remark that some point earned, in a fixed order.
    fn warnings(self) -> impl Iterator<Item = CmmWarning> {
        [
            self.normal_off,
            self.inward,
            self.disagree,
            self.off_surface,
            self.wrong_label,
            self.at_end,
        ]
        .into_iter()
        .filter_map(Tally::warning)
    }
}

/// The points too far from the surfaces (`problems`, among `rows` rows matched): they reject
/// the file unless `opts.exclude_bad_rows`; then they join `excluded` (sorted by line) with a
/// warning listing their lines.
fn exclude_far_rows(
    problems: Vec<RowProblem>,
    rows: usize,
    opts: &ReadOptions,
    warnings: &mut Vec<CmmWarning>,
    excluded: &mut Vec<RowProblem>,
) -> Result<(), CmmError> {
    if problems.is_empty() {
        return Ok(());
    }
    if !opts.exclude_bad_rows {
        return Err(CmmError::bad_rows(problems, rows));
    }
    warnings.push(CmmWarning::file(format!(
        "{} point(s) too far from the nominal surfaces excluded at your request (lines {})",
        problems.len(),
        problems
            .iter()
            .map(|p| p.line.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    )));
    excluded.extend(problems);
    sort_by_index(excluded, |p| p.line);
    Ok(())
}

/// Reads `bytes` ([`super::read_cmm_with`]) and matches the points to the ISO S-shape.
pub fn read_and_match(
    bytes: &[u8],
    name: &str,
    opts: &ReadOptions,
) -> Result<MatchedPart, CmmError> {
    let file = super::read_cmm_with(bytes, name, opts)?;
    match_points(&SShape::iso(), file, opts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::numerics::parallel::Threads;

    fn point(
        nominal: Option<[f64; 3]>,
        measured: Option<[f64; 3]>,
        deviation: Option<f64>,
    ) -> CmmPoint {
        CmmPoint {
            line: 2,
            id: "1".into(),
            curve: None,
            nominal,
            normal: None,
            measured,
            deviation,
            extra: Vec::new(),
        }
    }

    /// Runs of rows matched side by side give the part and the remarks of one thread: the
    /// built-in 100 points, every 23rd from the 6th with its normal reversed (inward) and every
    /// 31st from the 8th labelled with the other surface's curve, read on 1 and 3 threads
    /// (runs of 3 rows: each remark in its own run); and a row too far off the part is the same
    /// error on both.
    #[test]
    fn runs_on_threads_match_and_remark_as_one_thread() {
        let part = SShape::iso();
        let mut csv = String::from("id,curve,x,y,z,nx,ny,nz,deviation\n");
        for (i, p) in crate::part::builtin_points(&part).iter().enumerate() {
            let sign = if i % 23 == 5 { -1.0 } else { 1.0 };
            let curve = match (i % 31 == 7, p.curve.name().starts_with('A')) {
                (true, true) => "B_Z11".to_string(),
                (true, false) => "A_Z11".to_string(),
                _ => p.curve.name().to_string(),
            };
            csv.push_str(&format!(
                "{},{curve},{},{},{},{},{},{},0.001\n",
                p.id,
                p.point.x,
                p.point.y,
                p.point.z,
                sign * p.normal.x,
                sign * p.normal.y,
                sign * p.normal.z
            ));
        }
        let read = |text: &str, t: usize| {
            let opts = ReadOptions::default().with_threads(Threads::new(t));
            read_and_match(text.as_bytes(), "runs.csv", &opts)
        };
        let one = read(&csv, 1).unwrap();
        assert_eq!(read(&csv, 3).unwrap(), one);
        let said = |what: &str| one.warnings.iter().any(|w| w.message.contains(what));
        assert!(said(
            "5 point(s) with a file normal pointing into the material"
        ));
        assert!(said("3 point(s) whose curve label names the other surface"));
        // a row 50 mm off the part (line 42): the same refusal on one thread and on three
        let far: String = csv
            .lines()
            .enumerate()
            .map(|(k, l)| {
                if k == 41 {
                    let mut f: Vec<String> = l.split(',').map(str::to_string).collect();
                    f[2] = format!("{}", f[2].parse::<f64>().unwrap() + 50.0);
                    f.join(",")
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n");
        let e1 = read(&far, 1).unwrap_err().to_string();
        assert_eq!(read(&far, 3).unwrap_err().to_string(), e1);
        assert!(e1.contains("42"), "{e1}");
    }

    /// Rule 2, `(measured − nominal)·N` with `measured − nominal = (0.01, 0.02, 0)` mm and
    /// `N = (0.6, 0.8, 0)`: 0.006 + 0.016 = 0.022 mm (closed form, to rounding 1e-12 mm); rule 4
    /// keeps the file's deviation and reports the positions' one; rule 3 is the distance.
    #[test]
    fn deviation_follows_the_rules_of_cmm_csv() {
        let n = Vector3::new(0.6, 0.8, 0.0);
        let (nom, meas) = ([10.0, 0.0, 5.0], [10.01, 0.02, 5.0]);
        let (d, rule, from_pos) = deviation_by_rule(&point(Some(nom), Some(meas), None), &n, 0.5);
        assert_eq!(
            (rule, from_pos),
            (DeviationRule::MeasuredMinusNominal, None)
        );
        assert_near!(d, 0.022, 1e-12);
        let (d, rule, from_pos) =
            deviation_by_rule(&point(Some(nom), Some(meas), Some(0.03)), &n, 0.5);
        assert_eq!((d, rule), (0.03, DeviationRule::FileDeviation));
        assert_near!(from_pos.unwrap(), 0.022, 1e-12);
        let projected = deviation_by_rule(&point(None, Some(meas), None), &n, -0.004);
        assert_eq!(projected, (-0.004, DeviationRule::Projection, None));
    }

    /// A file normal `(2, 2, 0)` against `N = (1, 0, 0)`: `acos(1/√2)` = 45° (closed form, to
    /// rounding 1e-12°); the opposite normal is 180° (pointing into the material).
    #[test]
    fn normal_angle_is_independent_of_the_file_normal_length() {
        let n = Vector3::new(1.0, 0.0, 0.0);
        assert_near!(normal_angle_deg([2.0, 2.0, 0.0], &n), 45.0, 1e-12);
        assert_near!(normal_angle_deg([-3.0, 0.0, 0.0], &n), 180.0, 1e-12);
    }
}
