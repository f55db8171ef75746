//! Split rows to points: numbers parsed and converted to mm by their column's unit, every bad
//! field reported with line, column, the text found and what was expected.

use super::delimited::{RawRow, Separator};
use super::error::{ColumnRef, RowProblem, RowProblemKind};
use super::header::{Column, Layout};
use super::number::{parse_number, NumberError};
use super::table::{CmmPoint, FormatKind};
use super::units::LengthUnit;
use crate::numerics::parallel::{map_mut, Threads};

/// A table split into rows, whatever its format, before its numbers are read.
#[derive(Debug, Clone, PartialEq)]
pub struct ParsedTable {
    pub kind: FormatKind,
    pub layout: Layout,
    pub rows: Vec<RawRow>,
    /// Rows of the wrong shape.
    pub problems: Vec<RowProblem>,
    pub separator: Option<Separator>,
    pub decimal_comma: bool,
    pub header_line: Option<usize>,
    /// Lines before the header that were not used (titles), reported as a warning.
    pub preamble: Vec<usize>,
    /// A short phrase for the format description ("PC-DMIS XYZIJK, METRIC").
    pub label: String,
}

/// Points and problems of a set of rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Converted {
    pub points: Vec<CmmPoint>,
    pub problems: Vec<RowProblem>,
}

fn column_ref(c: &Column) -> ColumnRef {
    ColumnRef {
        number: c.number,
        name: c.header.clone(),
    }
}

struct RowReader<'a> {
    row: &'a RawRow,
    layout: &'a Layout,
    decimal_comma: bool,
    default_unit: LengthUnit,
    problems: Vec<RowProblem>,
}

impl RowReader<'_> {
    fn problem(&mut self, k: usize, kind: RowProblemKind, expected: String) {
        let c = &self.layout.columns[k];
        self.problems.push(RowProblem {
            line: self.row.line,
            column: Some(column_ref(c)),
            kind,
            found: self.row.fields[k].clone(),
            expected,
        });
    }

    /// The number in column `k`, converted to mm if it is a length column.
    fn number(&mut self, k: usize) -> Option<f64> {
        let c = &self.layout.columns[k];
        let is_length = c.role.is_some_and(|r| r.is_length());
        let unit = c.unit.unwrap_or(self.default_unit);
        match parse_number(&self.row.fields[k], self.decimal_comma) {
            Ok(v) => Some(if is_length { unit.mm(v) } else { v }),
            Err(e) => {
                let what = match c.role {
                    Some(r) if is_length => {
                        format!("a number in {} ({})", unit.symbol(), r.describe())
                    }
                    Some(r) => format!("a number ({})", r.describe()),
                    None => "a number".into(),
                };
                let (kind, expected) = match e {
                    NumberError::Empty => (RowProblemKind::EmptyValue, what),
                    NumberError::NotNumeric => (RowProblemKind::NotNumeric, what),
                    NumberError::NotFinite => (
                        RowProblemKind::NotFinite,
                        format!("{what}; NaN and infinite values cannot be used"),
                    ),
                };
                self.problem(k, kind, expected);
                None
            }
        }
    }

    fn triple(&mut self, cols: Option<[usize; 3]>) -> Option<[f64; 3]> {
        let [a, b, c] = cols?;
        let (x, y, z) = (self.number(a), self.number(b), self.number(c));
        Some([x?, y?, z?])
    }
}

/// Converts `rows` to points. `generated_ids`: number the rows 1.. where the layout has no id.
pub fn convert(
    rows: &[RawRow],
    layout: &Layout,
    decimal_comma: bool,
    default_unit: LengthUnit,
) -> Converted {
    convert_from(rows, 0, layout, decimal_comma, default_unit)
}

/// Rows converted a chunk at a time on the threads given ([`convert_on`]), in chunks of this many
/// (the chunks do not depend on the threads).
pub const CONVERT_CHUNK: usize = 4096;

/// [`convert`], the rows in chunks of [`CONVERT_CHUNK`] side by side on `threads` threads, their
/// points and problems joined in the rows' order: the same points and problems. The rows are
/// given up: each chunk is dropped by the thread that converted it (a dense scan's 200,000 rows
/// of strings had been freed on one thread after the reading, 15 ms, issue 31).
pub fn convert_on(
    rows: Vec<RawRow>,
    layout: &Layout,
    decimal_comma: bool,
    default_unit: LengthUnit,
    threads: Threads,
) -> Converted {
    let n = rows.len();
    let mut rest = rows.into_iter();
    let mut chunks: Vec<(usize, Vec<RawRow>)> = (0..n)
        .step_by(CONVERT_CHUNK)
        .map(|first| (first, rest.by_ref().take(CONVERT_CHUNK).collect()))
        .collect();
    let chunks = map_mut(threads, &mut chunks, |(first, chunk)| {
        let rows = std::mem::take(chunk);
        convert_from(&rows, *first, layout, decimal_comma, default_unit)
    });
    let mut out = Converted {
        points: Vec::with_capacity(n),
        problems: Vec::new(),
    };
    for mut c in chunks {
        out.points.append(&mut c.points);
        out.problems.append(&mut c.problems);
    }
    out
}

/// [`convert`] of rows whose first is row `first` of the table (the generated ids count from
/// it).
fn convert_from(
    rows: &[RawRow],
    first: usize,
    layout: &Layout,
    decimal_comma: bool,
    default_unit: LengthUnit,
) -> Converted {
    let mut out = Converted {
        points: Vec::with_capacity(rows.len()),
        problems: Vec::new(),
    };
    for (i, row) in rows.iter().enumerate() {
        let index = first + i;
        let mut r = RowReader {
            row,
            layout,
            decimal_comma,
            default_unit,
            problems: Vec::new(),
        };
        let id = match layout.id {
            Some(k) => {
                let text = row.fields[k].trim().to_string();
                if text.is_empty() {
                    r.problem(k, RowProblemKind::EmptyValue, "a point id".into());
                }
                text
            }
            None => (index + 1).to_string(),
        };
        let curve = layout
            .curve
            .map(|k| row.fields[k].trim().to_string())
            .filter(|t| !t.is_empty());
        let nominal = r.triple(layout.nominal);
        let measured = r.triple(layout.measured);
        let normal = r.triple(layout.normal);
        if let (Some(n), Some(cols)) = (normal, layout.normal) {
            if n.iter().map(|v| v * v).sum::<f64>().sqrt() < 1e-9 {
                let c = &layout.columns[cols[0]];
                r.problems.push(RowProblem {
                    line: row.line,
                    column: Some(column_ref(c)),
                    kind: RowProblemKind::ZeroNormal,
                    found: format!("({}, {}, {})", n[0], n[1], n[2]),
                    expected: "a normal vector of non-zero length (i, j, k)".into(),
                });
            }
        }
        let deviation = layout.deviation.and_then(|k| r.number(k));
        if r.problems.is_empty() {
            out.points.push(CmmPoint {
                line: row.line,
                id,
                curve,
                nominal: if layout.nominal.is_some() {
                    nominal
                } else {
                    None
                },
                normal,
                measured,
                deviation,
                extra: layout
                    .extra
                    .iter()
                    .map(|&k| row.fields[k].clone())
                    .collect(),
            });
        } else {
            out.problems.append(&mut r.problems);
        }
    }
    out
}
