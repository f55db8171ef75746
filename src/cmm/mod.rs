//! Reading CMM exports (`shared/spec/cmm-csv.md`) and matching points to the nominal part.
//!
//! Bytes → text ([`decode`]) → lines without comments and blanks ([`lines`]) → a table: a
//! delimited table with a header ([`delimited`], [`header`]), a fixed format ([`fixed`]:
//! PC-DMIS XYZIJK, PowerInspect ASCII) or a DMIS output ([`dmis_output`]) → numbers in mm ([`rows`], [`number`], [`units`]) →
//! checks of ids, units and count ([`plausibility`]) → [`CmmFile`].
//!
//! Tolerant in what it accepts, strict in what it reports: every non-blank, non-comment row is
//! either a point or a [`RowProblem`] with its line, column, the text found and what was
//! expected. A file with bad rows is rejected as a whole ([`CmmError::BadRows`], all rows
//! listed) unless [`ReadOptions::exclude_bad_rows`] is set; the excluded rows are then in
//! [`CmmFile::excluded`] for every later result to show.
//!
//! Units: every length returned is in mm. Sign convention (s-shape.md): deviation =
//! `(measured − nominal)·N`, N the outward normal; + = material left, − = overcut.

pub mod decode;
pub mod delimited;
pub mod dmis_output;
pub mod error;
pub mod fixed;
pub mod header;
pub mod lines;
pub mod matching;
pub mod number;
pub mod options;
pub mod plausibility;
pub mod rows;
pub mod table;
pub mod units;
pub mod write;

use crate::numerics::parallel::Threads;
use std::collections::hash_map::Entry;
use std::collections::HashMap;

pub use delimited::Separator;
pub use error::{CmmError, ColumnRef, RowProblem, RowProblemKind};
pub use header::{Column, Role};
pub use matching::{match_points, read_and_match, DeviationRule, MatchedPart, MatchedPoint};
pub use options::ReadOptions;
pub use table::{CmmFile, CmmPoint, CmmWarning, FormatInfo, FormatKind};
pub use units::LengthUnit;

use crate::numerics::order::sort_by_index;
use rows::ParsedTable;

/// Reads a CMM file with the default (strict) options. `name` is used in messages.
pub fn read_cmm(bytes: &[u8], name: &str) -> Result<CmmFile, CmmError> {
    read_cmm_with(bytes, name, &ReadOptions::default())
}

/// Finds the format of the content lines and splits them into rows.
fn parse_table(content: &[(usize, &str)], threads: Threads) -> Result<ParsedTable, CmmError> {
    let (first_line, first) = content[0];
    if fixed::is_xyzijk(first) {
        return fixed::xyzijk(content);
    }
    if dmis_output::is_dmis_output(first) {
        return dmis_output::dmis_output(content);
    }
    if let Some(h) = delimited::find_header(content) {
        let layout = header::layout_from_header(&h.fields, h.line)?;
        let data = &content[h.content_index + 1..];
        let split = delimited::split_rows(data, h.separator, &layout, threads);
        return Ok(ParsedTable {
            kind: FormatKind::Delimited,
            layout,
            rows: split.rows,
            problems: split.problems,
            separator: Some(h.separator),
            decimal_comma: split.decimal_comma,
            header_line: Some(h.line),
            preamble: content[..h.content_index].iter().map(|c| c.0).collect(),
            label: format!("{}-separated table", h.separator.describe()),
        });
    }
    if let Some(name_fields) = fixed::powerinspect_name_fields(first) {
        return fixed::powerinspect(content, name_fields);
    }
    let fields: Vec<String> = Separator::ALL
        .iter()
        .map(|&s| delimited::split(first, s))
        .max_by_key(Vec::len)
        .unwrap_or_default();
    let numeric = fields
        .iter()
        .filter(|f| number::parse_number(f, true).is_ok())
        .count();
    let hint = if numeric * 2 >= fields.len() && !fields.is_empty() {
        "; the first line holds numbers: the header row is missing".to_string()
    } else {
        String::new()
    };
    Err(CmmError::NoHeader {
        line: first_line,
        found: delimited::excerpt(first),
        hint,
    })
}

/// Moves rows whose id was used before into problems. With a curve column the identity of a
/// point is (curve, id): exports that number the points of each curve from 1 are accepted.
fn duplicates(points: &mut Vec<CmmPoint>, table: &ParsedTable) -> Vec<RowProblem> {
    let Some(k) = table.layout.id else {
        return Vec::new();
    };
    let col = &table.layout.columns[k];
    // Keys borrow the points (no copy of every id); the rows to drop are removed afterwards.
    let mut first: HashMap<(Option<&str>, &str), usize> = HashMap::with_capacity(points.len());
    let mut problems = Vec::new();
    let mut repeated = vec![false; points.len()];
    for (i, p) in points.iter().enumerate() {
        match first.entry((p.curve.as_deref(), p.id.as_str())) {
            Entry::Occupied(e) => {
                let line = *e.get();
                let within = match &p.curve {
                    Some(c) => format!(" in curve '{c}'"),
                    None => String::new(),
                };
                problems.push(RowProblem {
                    line: p.line,
                    column: Some(ColumnRef {
                        number: col.number,
                        name: col.header.clone(),
                    }),
                    kind: RowProblemKind::DuplicateId,
                    found: p.id.clone(),
                    expected: format!(
                        "a unique point id ('{}'{within} is already used on line {line})",
                        p.id
                    ),
                });
                repeated[i] = true;
            }
            Entry::Vacant(e) => {
                e.insert(p.line);
            }
        }
    }
    drop(first);
    if !problems.is_empty() {
        let mut k = 0;
        points.retain(|_| {
            k += 1;
            !repeated[k - 1]
        });
    }
    problems
}

/// What the columns hold, in words.
fn content_summary(t: &ParsedTable) -> String {
    let l = &t.layout;
    let mut parts = Vec::new();
    if l.id.is_some() {
        parts.push("id");
    }
    if l.curve.is_some() {
        parts.push("curve");
    }
    if l.nominal.is_some() {
        parts.push("nominal position");
    }
    if l.measured.is_some() {
        parts.push("measured position");
    }
    if l.normal.is_some() {
        parts.push("normal");
    }
    if l.deviation.is_some() {
        parts.push("deviation");
    }
    parts.join(" + ")
}

fn units_summary(t: &ParsedTable, default: LengthUnit) -> String {
    let mut parts: Vec<String> = Vec::new();
    for c in &t.layout.columns {
        if let Some(role) = c.role.filter(|r| r.is_length()) {
            let u = c.unit.unwrap_or(default);
            if u != LengthUnit::Mm {
                parts.push(format!("{} in {}", role.describe(), u.symbol()));
            }
        }
    }
    if parts.is_empty() {
        "lengths in mm".into()
    } else {
        format!("{} (converted to mm)", parts.join(", "))
    }
}

/// Reads a CMM file. See the module docs for what is accepted and reported.
pub fn read_cmm_with(bytes: &[u8], name: &str, opts: &ReadOptions) -> Result<CmmFile, CmmError> {
    opts.validate()?;
    let decoded = decode::decode(bytes, name, opts.max_bytes)?;
    let lines = content_lines(&decoded.text, bytes.len(), name, opts.max_rows)?;
    let mut table = parse_table(&lines.content, opts.threads)?;
    let data_rows = count_data_rows(&table, lines.content[0].0, name, opts.max_rows)?;
    let default_unit = opts.length_unit.unwrap_or(LengthUnit::Mm);
    let (mut points, mut problems) = read_points(&mut table, default_unit, opts.threads);
    let mut warnings = Vec::new();
    let implausible = check_units(&mut points, &table, opts, default_unit, &mut warnings)?;
    problems.extend(implausible);
    sort_by_index(&mut problems, |p| p.line);
    let excluded = exclude_bad_rows(problems, data_rows, opts, &mut warnings)?;
    if points.len() < opts.min_points {
        let excluded_rows = error::distinct_lines(&excluded);
        return Err(CmmError::too_few_points(
            points.len(),
            opts.min_points,
            excluded_rows,
        ));
    }
    warnings.extend(layout_warnings(&table, &lines.all));
    warnings.extend(odd_normals_warning(&points));
    let extra_columns = extra_column_names(&table);
    let description = describe_format(&table, default_unit, decoded.encoding, &extra_columns);
    Ok(CmmFile {
        name: name.to_string(),
        format: FormatInfo {
            kind: table.kind,
            description,
            encoding: decoded.encoding.to_string(),
            separator: table.separator,
            decimal_comma: table.decimal_comma,
            header_line: table.header_line,
            columns: table.layout.columns.clone(),
            positions_read_as_measured: table.layout.positions_read_as_measured,
        },
        extra_columns,
        points,
        excluded,
        warnings,
        comment_lines: lines.comments,
        blank_lines: lines.blanks,
    })
}

/// The lines of `text` (a file of `byte_count` bytes called `name`), refused when none holds
/// content or when there are more than `max_rows` content lines besides a header.
fn content_lines<'a>(
    text: &'a str,
    byte_count: usize,
    name: &str,
    max_rows: usize,
) -> Result<lines::Lines<'a>, CmmError> {
    let lines = lines::classify(text);
    if lines.content.is_empty() {
        let detail = if lines.comments > 0 {
            format!(
                "only comment and blank lines ({} comment, {} blank)",
                lines.comments, lines.blanks
            )
        } else {
            format!(
                "only white space ({} bytes, {} lines)",
                byte_count,
                lines.all.len()
            )
        };
        return Err(CmmError::Empty {
            name: name.to_string(),
            detail,
        });
    }
    if lines.content.len() > max_rows.saturating_add(1) {
        return Err(CmmError::TooManyRows {
            rows: lines.content.len() - 1,
            limit: max_rows,
        });
    }
    Ok(lines)
}

/// The number of data rows of `table` (points and rows of the wrong shape), refused when there
/// is none or more than `max_rows`. `first_line`: the first content line, named when the table
/// has no header line.
fn count_data_rows(
    table: &ParsedTable,
    first_line: usize,
    name: &str,
    max_rows: usize,
) -> Result<usize, CmmError> {
    let data_rows = table.rows.len() + table.problems.len();
    if data_rows == 0 {
        return Err(CmmError::Empty {
            name: name.to_string(),
            detail: format!(
                "a header on line {} but no data rows",
                table.header_line.unwrap_or(first_line)
            ),
        });
    }
    if data_rows > max_rows {
        return Err(CmmError::TooManyRows {
            rows: data_rows,
            limit: max_rows,
        });
    }
    Ok(data_rows)
}

/// The points of `table` in mm (lengths without a unit in `default_unit`), and the problems:
/// rows of the wrong shape, bad fields, repeated ids (those rows are dropped from the points).
/// The table's rows are given up to their conversion: `table.rows` is empty after.
fn read_points(
    table: &mut ParsedTable,
    default_unit: LengthUnit,
    threads: Threads,
) -> (Vec<CmmPoint>, Vec<RowProblem>) {
    let decimal_comma_allowed = table.separator != Some(Separator::Comma);
    // the rows given up to their conversion (nothing after it reads them)
    let converted = rows::convert_on(
        std::mem::take(&mut table.rows),
        &table.layout,
        decimal_comma_allowed,
        default_unit,
        threads,
    );
    let mut points = converted.points;
    let mut problems = table.problems.clone();
    problems.extend(converted.problems);
    problems.extend(duplicates(&mut points, table));
    (points, problems)
}

/// Units: positions against the part ([`plausibility::check_positions`]: a wrong unit or the
/// alignment rejects the file), deviations against the distance limit (mm,
/// [`plausibility::check_deviations`]): the rows with an implausible deviation are removed
/// from `points` and returned as problems.
fn check_units(
    points: &mut Vec<CmmPoint>,
    table: &ParsedTable,
    opts: &ReadOptions,
    default_unit: LengthUnit,
    warnings: &mut Vec<CmmWarning>,
) -> Result<Vec<RowProblem>, CmmError> {
    let position_cols: Vec<&Column> = table
        .layout
        .columns
        .iter()
        .filter(|c| matches!(c.role, Some(Role::Nominal(_) | Role::Measured(_))))
        .collect();
    let unit_explicit =
        opts.length_unit.is_some() || position_cols.iter().any(|c| c.unit.is_some());
    let unit_text = position_cols
        .iter()
        .find_map(|c| c.unit)
        .unwrap_or(default_unit)
        .symbol();
    plausibility::check_positions(points, plausibility::ISO_BOX, unit_explicit, unit_text)?;
    let dev_problems =
        plausibility::check_deviations(points, &table.layout, opts.max_distance_mm, warnings)?;
    if !dev_problems.is_empty() {
        points.retain(|p| !dev_problems.iter().any(|d| d.line == p.line));
    }
    Ok(dev_problems)
}

/// The bad rows (`problems`, sorted by line, among `data_rows`): they reject the file unless
/// `opts.exclude_bad_rows`; then they are returned as the excluded rows, with a warning
/// listing their lines.
fn exclude_bad_rows(
    problems: Vec<RowProblem>,
    data_rows: usize,
    opts: &ReadOptions,
    warnings: &mut Vec<CmmWarning>,
) -> Result<Vec<RowProblem>, CmmError> {
    if problems.is_empty() {
        return Ok(Vec::new());
    }
    if !opts.exclude_bad_rows {
        return Err(CmmError::bad_rows(problems, data_rows));
    }
    let lines_out = {
        let mut l: Vec<usize> = problems.iter().map(|p| p.line).collect();
        l.dedup();
        l
    };
    warnings.push(CmmWarning::file(format!(
        "{} row(s) excluded at your request (lines {}); every result is computed without them",
        lines_out.len(),
        lines_out
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    )));
    Ok(problems)
}

/// Warnings about how the table was read: title lines before the header (`all`: every line
/// of the file, for the excerpt), positions read as measured.
fn layout_warnings(table: &ParsedTable, all: &[&str]) -> Vec<CmmWarning> {
    let mut warnings = Vec::new();
    if !table.preamble.is_empty() {
        let first = table.preamble[0];
        warnings.push(CmmWarning::at(
            first,
            format!(
                "{} line(s) before the header on line {} were not read as data (first: '{}')",
                table.preamble.len(),
                table.header_line.unwrap_or(0),
                delimited::excerpt(all[first - 1])
            ),
        ));
    }
    if table.layout.positions_read_as_measured {
        warnings.push(CmmWarning::file(
            "the file has positions x, y, z but neither a deviation nor measured columns: they are read as measured positions and projected onto the nominal part",
        ));
    }
    warnings
}

/// The points whose file normal is not of unit length (`|‖n‖ − 1| > 0.01`): line and length.
fn odd_normals(points: &[CmmPoint]) -> Vec<(usize, f64)> {
    points
        .iter()
        .filter_map(|p| {
            let n = p.normal?;
            let len = n.iter().map(|v| v * v).sum::<f64>().sqrt();
            ((len - 1.0).abs() > 1e-2).then_some((p.line, len))
        })
        .collect()
}

/// One warning, at the first of them, for the normals not of unit length ([`odd_normals`]).
fn odd_normals_warning(points: &[CmmPoint]) -> Option<CmmWarning> {
    let odd = odd_normals(points);
    let &(line, len) = odd.first()?;
    Some(CmmWarning::at(
        line,
        format!(
            "{} normal(s) are not of unit length (this one {len:.6}); they are normalised where used",
            odd.len()
        ),
    ))
}

/// Header names of the columns kept as text (tolerances, comments, …), in column order.
fn extra_column_names(table: &ParsedTable) -> Vec<String> {
    table
        .layout
        .extra
        .iter()
        .map(|&k| table.layout.columns[k].header.clone())
        .collect()
}

/// One sentence on the format found: the table's label, decimal comma, header line, what the
/// columns hold, their units, the encoding, a missing id column and the extra columns kept.
fn describe_format(
    table: &ParsedTable,
    default_unit: LengthUnit,
    encoding: &str,
    extra_columns: &[String],
) -> String {
    let mut description = format!(
        "{}{}{}: {}; {}; {}",
        table.label,
        if table.decimal_comma {
            " with decimal comma"
        } else {
            ""
        },
        match (table.kind, table.header_line) {
            (FormatKind::Delimited, Some(h)) => format!(", header on line {h}"),
            _ => String::new(),
        },
        content_summary(table),
        units_summary(table, default_unit),
        encoding
    );
    if table.layout.id.is_none() {
        description.push_str("; no id column: points numbered 1.. in file order");
    }
    if !extra_columns.is_empty() {
        description.push_str(&format!(
            "; extra columns kept: {}",
            extra_columns.join(", ")
        ));
    }
    description
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    fn with_normal(line: usize, normal: [f64; 3]) -> CmmPoint {
        CmmPoint {
            line,
            id: line.to_string(),
            curve: None,
            nominal: Some([0.0; 3]),
            normal: Some(normal),
            measured: None,
            deviation: None,
            extra: Vec::new(),
        }
    }

    /// `‖(3, 4, 0)‖ = 5` (the 3-4-5 triangle, to rounding 1e-15) is listed; a unit normal and
    /// one within 1 % of unit length (`‖(0, 0, 1.005)‖`) are not.
    #[test]
    fn odd_normals_are_those_off_unit_length_by_more_than_one_percent() {
        let points = [
            with_normal(3, [0.6, 0.8, 0.0]),
            with_normal(4, [3.0, 4.0, 0.0]),
            with_normal(5, [0.0, 0.0, 1.005]),
        ];
        let odd = odd_normals(&points);
        assert_eq!(odd.len(), 1);
        assert_eq!(odd[0].0, 4);
        assert_near!(odd[0].1, 5.0, 1e-15);
        let w = odd_normals_warning(&points).unwrap();
        assert_eq!(w.line, Some(4));
        assert!(w
            .message
            .starts_with("1 normal(s) are not of unit length (this one 5.000000)"));
    }

    /// A text of comments and blanks is empty; a header and two rows pass a limit of 2 rows and
    /// fail one of 1 (the header is not a data row).
    #[test]
    fn content_lines_refuse_empty_and_too_long_texts() {
        let e = content_lines("# c\n\n", 5, "f.csv", 10).unwrap_err();
        assert!(matches!(&e, CmmError::Empty { detail, .. }
            if detail == "only comment and blank lines (1 comment, 2 blank)"));
        let text = "x,y,z\n1,2,3\n4,5,6\n";
        assert_eq!(
            content_lines(text, 18, "f.csv", 2).unwrap().content.len(),
            3
        );
        assert_eq!(
            content_lines(text, 18, "f.csv", 1).unwrap_err(),
            CmmError::TooManyRows { rows: 2, limit: 1 }
        );
    }
}
