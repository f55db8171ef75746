//! Are the numbers in the units the file claims? Checks against the size of the nominal part
//! before any point is matched (cmm-csv.md: "inch data without a unit", "a point more than
//! 2 mm from the nominal surfaces (probably wrong units or alignment: say which)").
//!
//! - Positions: the S-shape spans about x -138..132, y -97..100, z 0..30 mm (sampled from
//!   [`SShape::iso`]). If most points lie outside that box (grown by [`BOX_MARGIN_MM`]) the
//!   file is rejected, naming the unit factor that would bring them in (25.4, 1/25.4, 1000,
//!   1/1000) or, if none does, the alignment. Without a unit in the file, data that all fit a
//!   box 25.4 times smaller are inches ([`CmmError::InchWithoutUnit`]).
//! - Deviations: larger than the distance limit on most rows means another unit (µm); on a few
//!   rows, those rows are bad ([`RowProblemKind::ImplausibleDeviation`]).

use super::error::{CmmError, ColumnRef, RowProblem, RowProblemKind};
use super::header::Layout;
use super::table::{CmmPoint, CmmWarning};
use crate::part::{SShape, Surface};

/// Margin around the part's bounding box for the unit checks (mm). Generous: misalignment is
/// judged point by point when matching, this only catches unit errors.
pub const BOX_MARGIN_MM: f64 = 10.0;

/// Bounding box `[min, max]` of [`SShape::iso`] (mm): a constant of the part design,
/// [`part_box`] of the ISO part to the bit (the test below recomputes it), so that a file is
/// checked without sampling the part again and without a process-wide cache.
pub const ISO_BOX: [[f64; 3]; 2] = [[-137.0, -95.5, 0.0], [131.0, 99.5, 30.000000000000007]];

/// Bounding box `[min, max]` of the nominal part (mm).
pub fn part_box(part: &SShape) -> [[f64; 3]; 2] {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for s in Surface::BOTH {
        for k in 0..=200 {
            for v in [0.0, 1.0] {
                let p = part.point_at(s, k as f64 / 200.0, v);
                for i in 0..3 {
                    lo[i] = lo[i].min(p[i]);
                    hi[i] = hi[i].max(p[i]);
                }
            }
        }
    }
    [lo, hi]
}

fn inside(p: [f64; 3], scale: f64, b: &[[f64; 3]; 2], margin: f64) -> bool {
    (0..3).all(|i| {
        let v = p[i] * scale;
        v >= b[0][i] - margin && v <= b[1][i] + margin
    })
}

fn span(points: &[[f64; 3]]) -> [[f64; 3]; 2] {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    [lo, hi]
}

fn describe_box(b: &[[f64; 3]; 2]) -> String {
    format!(
        "x {:.3}..{:.3}, y {:.3}..{:.3}, z {:.3}..{:.3} mm",
        b[0][0], b[1][0], b[0][1], b[1][1], b[0][2], b[1][2]
    )
}

/// Checks the positions of `points` against the part. `unit_explicit`: the file or the caller
/// stated the length unit of the positions (no inch guess then). `unit_text`: that unit, for
/// the message.
pub fn check_positions(
    points: &[CmmPoint],
    b: [[f64; 3]; 2],
    unit_explicit: bool,
    unit_text: &str,
) -> Result<(), CmmError> {
    let pos: Vec<[f64; 3]> = points.iter().filter_map(CmmPoint::position).collect();
    if pos.is_empty() {
        return Ok(());
    }
    let count_in = |scale: f64| {
        pos.iter()
            .filter(|p| inside(**p, scale, &b, BOX_MARGIN_MM))
            .count()
    };
    let n = pos.len();
    let s = span(&pos);
    if !unit_explicit {
        // All points fit the part shrunk 25.4 times (2 mm margin), and the data do not reach
        // beyond 0.3 of the part's size in mm: inches.
        let tight = pos.iter().all(|p| inside(*p, 25.4, &b, 2.0));
        let extent = (0..3).map(|i| s[1][i] - s[0][i]).fold(0.0, f64::max);
        let part_extent = (0..3).map(|i| b[1][i] - b[0][i]).fold(0.0, f64::max);
        if tight && extent < 0.3 * part_extent && n >= 2 {
            let max_abs = pos
                .iter()
                .flat_map(|p| p.iter().map(|v| v.abs()))
                .fold(0.0, f64::max);
            return Err(CmmError::InchWithoutUnit {
                max_abs,
                x_min: s[0][0],
                x_max: s[1][0],
                y_min: s[0][1],
                y_max: s[1][1],
                z_min: s[0][2],
                z_max: s[1][2],
            });
        }
    }
    if count_in(1.0) * 2 >= n {
        return Ok(());
    }
    let factors = [
        (25.4, "inches read as mm"),
        (1.0 / 25.4, "mm labelled as inches"),
        (1e-3, "µm read as mm"),
        (1e3, "m read as mm, or mm labelled as µm"),
    ];
    // A factor explains the data if nearly all points then fit the part *and* spread over a
    // good part of it (a shrink factor alone would pull any cloud into the box).
    let part_extent = (0..3).map(|i| b[1][i] - b[0][i]).fold(0.0, f64::max);
    let extent = (0..3).map(|i| s[1][i] - s[0][i]).fold(0.0, f64::max);
    let explains = |f: f64| count_in(f) * 10 >= n * 9 && extent * f > 0.3 * part_extent;
    let outside = n - count_in(1.0);
    match factors.iter().find(|(f, _)| explains(*f)) {
        Some((f, what)) => Err(CmmError::WrongUnits {
            detail: format!(
                "{outside} of {n} points lie outside the part: the positions span {} but the S-shape lies within {}; multiplied by {} they would fit ({what}): check the unit of the position columns (read as {unit_text})",
                describe_box(&s),
                describe_box(&b),
                fmt_factor(*f)
            ),
        }),
        None => Err(CmmError::NotAligned {
            detail: format!(
                "{outside} of {n} points lie outside the part: the positions span {} but the S-shape lies within {}, and no unit conversion makes them fit",
                describe_box(&s),
                describe_box(&b)
            ),
        }),
    }
}

fn fmt_factor(f: f64) -> String {
    let short = |v: f64| (v * 1000.0).round() / 1000.0;
    if f < 1.0 {
        format!("1/{}", short(1.0 / f))
    } else {
        format!("{}", short(f))
    }
}

/// Checks deviations against `max_mm`: most rows beyond it is a unit error; a few rows are
/// bad rows (returned). Also warns when a µm column holds only tiny numbers.
pub fn check_deviations(
    points: &[CmmPoint],
    layout: &Layout,
    max_mm: f64,
    warnings: &mut Vec<CmmWarning>,
) -> Result<Vec<RowProblem>, CmmError> {
    let Some(k) = layout.deviation else {
        return Ok(Vec::new());
    };
    let col = &layout.columns[k];
    let devs: Vec<(usize, f64)> = points
        .iter()
        .filter_map(|p| p.deviation.map(|d| (p.line, d)))
        .collect();
    if devs.is_empty() {
        return Ok(Vec::new());
    }
    let big: Vec<&(usize, f64)> = devs.iter().filter(|(_, d)| d.abs() > max_mm).collect();
    let unit = col
        .unit
        .map_or("mm (no unit in the header)", |u| u.symbol());
    if big.len() * 2 > devs.len() {
        let mut abs: Vec<f64> = devs.iter().map(|(_, d)| d.abs()).collect();
        abs.sort_by(f64::total_cmp);
        let median = abs[abs.len() / 2];
        let max = abs[abs.len() - 1];
        return Err(CmmError::WrongUnits {
            detail: format!(
                "column {} '{}' read as {unit}: {} of {} deviations exceed {max_mm} mm (median |deviation| {median:.4} mm, largest {max:.4} mm), but a machined part deviates by a few tenths of a mm at most: the column is probably in µm; write the unit in the header, e.g. 'deviation [µm]'",
                col.number,
                col.header,
                big.len(),
                devs.len()
            ),
        });
    }
    if col.unit == Some(super::units::LengthUnit::Um)
        && devs.len() >= 10
        && devs.iter().all(|(_, d)| d.abs() < 1e-5)
    {
        warnings.push(CmmWarning::file(format!(
            "column {} '{}' says µm but every deviation is below 0.01 µm: check that the values are not in mm",
            col.number, col.header
        )));
    }
    Ok(big
        .into_iter()
        .map(|&(line, d)| RowProblem {
            line,
            column: Some(ColumnRef {
                number: col.number,
                name: col.header.clone(),
            }),
            kind: RowProblemKind::ImplausibleDeviation,
            found: format!("{d} mm"),
            expected: format!(
                "a deviation within ±{max_mm} mm (read as {unit}); a larger one means a wrong unit or a point not on the part"
            ),
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_iso_box_is_the_sampled_box_of_the_iso_part() {
        assert_eq!(part_box(&SShape::iso()), ISO_BOX);
    }
}
