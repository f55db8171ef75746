//! Matching CMM points to the nominal S-shape and their normal deviations
//! (cmm-csv.md "What the reader does with what it finds", s-shape.md "Measurement points").
//!
//! Every point is matched by closest-point projection of its *own* coordinates onto the nominal
//! surfaces ([`crate::geometry::projection::project`]), never by its id: the nominal position
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

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::error::{CmmError, RowProblem, RowProblemKind};
use super::options::ReadOptions;
use super::table::{CmmFile, CmmPoint, CmmWarning, FormatInfo};
use crate::geometry::projection::{Projection, Projector};
use crate::geometry::GeometryError;
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
    "no unit conversion brings it onto the part: probably the alignment (part origin and axes of s-shape.md), or a point not on the test piece (probe slip, fixture)".into()
}

/// Matches the points of `file` to `part` with the rules of the module docs. Bad rows (points
/// too far) reject the file unless `opts.exclude_bad_rows`; then they join `file.excluded`.
pub fn match_points(
    part: &SShape,
    file: CmmFile,
    opts: &ReadOptions,
) -> Result<MatchedPart, CmmError> {
    let projector = Projector::new(part);
    let mut points = Vec::with_capacity(file.points.len());
    let mut problems: Vec<RowProblem> = Vec::new();
    let mut normal_off = Tally::new(
        "with a file normal more than the allowed angle from the model's outward normal",
    );
    let mut inward = Tally::new("with a file normal pointing into the material (the file may use the opposite sign convention: check the sign of its deviations)");
    let mut disagree = Tally::new("where the file's deviation and the one given by its positions differ by more than the allowed amount; the file's deviation is used (rule 4)");
    let mut off_surface = Tally::new("whose nominal position lies off the nominal surface by more than 10 µm (the file's deviation is used as given)");
    let mut wrong_label =
        Tally::new("whose curve label names the other surface than the one they lie on");
    let mut at_end =
        Tally::new("beyond the end of the surface (projected onto its edge u = 0 or 1)");

    for pt in file.points {
        let Some(pos) = pt.nominal.or(pt.measured) else {
            // The reader guarantees a position; keep the promise not to drop rows silently.
            problems.push(RowProblem {
                line: pt.line,
                column: None,
                kind: RowProblemKind::EmptyValue,
                found: String::new(),
                expected: "a nominal or measured position".into(),
            });
            continue;
        };
        let p = v3(pos);
        let proj: Projection = project_point(&projector, &p).map_err(|e| CmmError::Projection {
            line: pt.line,
            message: e.to_string(),
        })?;
        let n = proj.normal;
        let gap = (p - proj.foot).norm();
        let (deviation, rule, position_deviation) = match (pt.nominal, pt.measured, pt.deviation) {
            (Some(nom), Some(meas), d) => {
                let from_pos = (v3(meas) - v3(nom)).dot(&n);
                match d {
                    Some(d) => (d, DeviationRule::FileDeviation, Some(from_pos)),
                    None => (from_pos, DeviationRule::MeasuredMinusNominal, None),
                }
            }
            (Some(_), None, Some(d)) => (d, DeviationRule::FileDeviation, None),
            (None, Some(_), Some(d)) => (d, DeviationRule::FileDeviation, Some(proj.distance)),
            (None, Some(_), None) => (proj.distance, DeviationRule::Projection, None),
            // Nominal without deviation or measured is read as measured by the reader.
            (Some(_), None, None) | (None, None, _) => {
                (proj.distance, DeviationRule::Projection, None)
            }
        };
        let far = gap > opts.max_distance_mm || deviation.abs() > opts.max_distance_mm;
        if far {
            let what = if pt.nominal.is_some() {
                "nominal"
            } else {
                "measured"
            };
            problems.push(RowProblem {
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
                    far_reason(&projector, &p, opts.max_distance_mm)
                ),
            });
            continue;
        }
        let normal_angle_deg = pt.normal.map(|fnorm| {
            let f = v3(fnorm);
            let c = (f.dot(&n) / f.norm()).clamp(-1.0, 1.0);
            c.acos().to_degrees()
        });
        if let Some(a) = normal_angle_deg {
            if a > 90.0 {
                inward.add(pt.line, a, format!("{a:.2}° at line {}", pt.line));
            } else if a > opts.normal_warn_deg {
                normal_off.add(
                    pt.line,
                    a,
                    format!(
                        "{a:.2}° (limit {}°) at line {}",
                        opts.normal_warn_deg, pt.line
                    ),
                );
            }
        }
        if let Some(pd) = position_deviation {
            let diff = (deviation - pd).abs();
            if diff > opts.deviation_warn_mm {
                disagree.add(
                    pt.line,
                    diff,
                    format!(
                        "file {deviation:.6} mm vs positions {pd:.6} mm at line {} (limit {} mm)",
                        pt.line, opts.deviation_warn_mm
                    ),
                );
            }
        }
        if pt.nominal.is_some()
            && proj.distance.abs() > 0.01
            && rule == DeviationRule::FileDeviation
        {
            off_surface.add(
                pt.line,
                proj.distance.abs(),
                format!(
                    "{:.4} mm at line {} (file deviation {deviation:.4} mm{})",
                    proj.distance,
                    pt.line,
                    if (proj.distance - deviation).abs() <= opts.deviation_warn_mm {
                        "; these look like measured positions, and they agree with the deviation"
                    } else {
                        ""
                    }
                ),
            );
        }
        if let Some(s) = pt.curve.as_deref().and_then(surface_of_label) {
            if s != proj.surface {
                wrong_label.add(
                    pt.line,
                    1.0,
                    format!(
                        "label '{}' but on surface {} at line {}",
                        pt.curve.as_deref().unwrap_or(""),
                        proj.surface.name(),
                        pt.line
                    ),
                );
            }
        }
        if proj.clamped {
            at_end.add(
                pt.line,
                gap,
                format!("{gap:.4} mm from the edge at line {}", pt.line),
            );
        }
        points.push(MatchedPoint {
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
        });
    }

    let mut warnings = file.warnings;
    let mut excluded = file.excluded;
    if !problems.is_empty() {
        if !opts.exclude_bad_rows {
            let rows = points.len() + problems.len();
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
        excluded.sort_by_key(|p| p.line);
    }
    if points.len() < opts.min_points {
        return Err(CmmError::TooFewPoints {
            found: points.len(),
            needed: opts.min_points,
            excluded_note: if excluded.is_empty() {
                String::new()
            } else {
                format!(" after excluding {} bad row(s)", excluded.len())
            },
        });
    }
    for t in [
        normal_off,
        inward,
        disagree,
        off_surface,
        wrong_label,
        at_end,
    ] {
        warnings.extend(t.warning());
    }
    Ok(MatchedPart {
        name: file.name,
        format: file.format,
        extra_columns: file.extra_columns,
        points,
        excluded,
        warnings,
    })
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
