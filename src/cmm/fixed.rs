//! Fixed formats without a header row (cmm-csv.md "Fixed formats"):
//! - PC-DMIS XYZIJK: first line `XYZIJK` (columns 1-6) and `METRIC` or `INCH` (columns 11-16),
//!   then `x,y,z,i,j,k[,dev]` per line. With a deviation the positions are read as nominal
//!   (rule 1, like the canonical format); without one as measured (rule 3).
//! - Autodesk PowerInspect ASCII: `name X Y Z I J K offset lowTol highTol` separated by spaces;
//!   `offset` is the normal deviation, the tolerances are kept as extra columns. No unit is
//!   written: mm, checked against inches like any file without a unit.

use super::delimited::{excerpt, split, split_all, unbalanced_quote, RawRow, Separator};
use super::error::{CmmError, RowProblem, RowProblemKind};
use super::header::{from_columns, Column, Role};
use super::number::{has_decimal_comma, parse_number};
use super::rows::ParsedTable;
use super::table::FormatKind;
use super::units::LengthUnit;

/// Whether the first content line announces a PC-DMIS XYZIJK file.
pub fn is_xyzijk(first: &str) -> bool {
    first
        .trim_start()
        .get(..6)
        .is_some_and(|s| s.eq_ignore_ascii_case("XYZIJK"))
}

fn column(number: usize, name: &str, role: Option<Role>, unit: Option<LengthUnit>) -> Column {
    Column {
        number,
        header: name.to_string(),
        role,
        unit,
    }
}

/// Splits data lines of a fixed format into rows of `width` fields, reporting the others.
fn fixed_rows(
    data: &[(usize, &str)],
    sep: Separator,
    width: usize,
    names: &str,
) -> (Vec<RawRow>, Vec<RowProblem>, bool) {
    let mut rows = Vec::with_capacity(data.len());
    let mut problems = Vec::new();
    let mut decimal_comma = false;
    for rec in split_all(data, sep) {
        let (line, text, fields) = (rec.line, data[rec.index].1, rec.fields);
        if let Some(last) = rec.spans_to {
            problems.extend(unbalanced_quote(data, rec.index, last));
            continue;
        }
        if fields.len() == width {
            if sep != Separator::Comma && !decimal_comma {
                decimal_comma = fields.iter().any(|f| has_decimal_comma(f));
            }
            rows.push(RawRow { line, fields });
            continue;
        }
        let other = Separator::ALL
            .into_iter()
            .find(|&s| s != sep && split(text, s).len() == width);
        let (kind, expected) = match other {
            Some(s) => (
                RowProblemKind::MixedSeparators,
                format!(
                    "{width} fields separated by {} as in the other lines, but this line uses {}",
                    sep.describe(),
                    s.describe()
                ),
            ),
            None if fields.len() < width => (
                RowProblemKind::Truncated,
                format!(
                    "{width} fields ({names}), found only {}: the row looks cut short",
                    fields.len()
                ),
            ),
            None => (
                RowProblemKind::TooManyFields,
                format!("{width} fields ({names}), found {}", fields.len()),
            ),
        };
        problems.push(RowProblem {
            line,
            column: None,
            kind,
            found: excerpt(text),
            expected,
        });
    }
    (rows, problems, decimal_comma)
}

/// Reads a PC-DMIS XYZIJK file: `content[0]` is the `XYZIJK` line.
pub fn xyzijk(content: &[(usize, &str)]) -> Result<ParsedTable, CmmError> {
    let (line, first) = content[0];
    let upper = first.trim_start().to_ascii_uppercase();
    let rest = upper.get(6..).unwrap_or("");
    // Columns 11-16 by the format; accept the word anywhere after XYZIJK.
    let unit = if rest.contains("METRIC") {
        LengthUnit::Mm
    } else if rest.contains("INCH") {
        LengthUnit::Inch
    } else {
        return Err(CmmError::XyzijkUnit {
            line,
            found: first.trim().to_string(),
        });
    };
    let data = &content[1..];
    let sep = match data.first() {
        Some((_, t)) if t.contains(',') => Separator::Comma,
        _ => Separator::Spaces,
    };
    let sevens = data
        .iter()
        .take(50)
        .filter(|(_, t)| split(t, sep).len() == 7)
        .count();
    let sixes = data
        .iter()
        .take(50)
        .filter(|(_, t)| split(t, sep).len() == 6)
        .count();
    let with_dev = sevens > sixes;
    let position = |k| {
        if with_dev {
            Role::Nominal(k)
        } else {
            Role::Measured(k)
        }
    };
    let mut columns = vec![
        column(1, "x", Some(position(0)), Some(unit)),
        column(2, "y", Some(position(1)), Some(unit)),
        column(3, "z", Some(position(2)), Some(unit)),
        column(4, "i", Some(Role::Normal(0)), None),
        column(5, "j", Some(Role::Normal(1)), None),
        column(6, "k", Some(Role::Normal(2)), None),
    ];
    if with_dev {
        columns.push(column(7, "dev", Some(Role::Deviation), Some(unit)));
    }
    let width = columns.len();
    let names = if with_dev {
        "x, y, z, i, j, k, dev"
    } else {
        "x, y, z, i, j, k"
    };
    let layout = from_columns(columns, line)?;
    let (rows, problems, decimal_comma) = fixed_rows(data, sep, width, names);
    Ok(ParsedTable {
        kind: FormatKind::Xyzijk,
        layout,
        rows,
        problems,
        separator: Some(sep),
        decimal_comma,
        header_line: Some(line),
        preamble: Vec::new(),
        label: format!(
            "PC-DMIS XYZIJK, {} ({}), {}",
            if unit == LengthUnit::Mm {
                "METRIC"
            } else {
                "INCH"
            },
            unit.symbol(),
            if with_dev {
                "nominal position + normal + deviation"
            } else {
                "measured position + normal"
            }
        ),
    })
}

/// Number of leading name fields if `line` looks like a PowerInspect row: the last 9 fields
/// numeric after one name field, or after several where the first is not a number (names with
/// spaces).
pub fn powerinspect_name_fields(line: &str) -> Option<usize> {
    let fields = split(line, Separator::Spaces);
    if fields.len() < 10 {
        return None;
    }
    let numeric = fields[fields.len() - 9..]
        .iter()
        .all(|f| parse_number(f, true).is_ok());
    // A numeric name is accepted only with exactly one name field (10 fields in all).
    let name_numeric = parse_number(&fields[0], true).is_ok();
    (numeric && (!name_numeric || fields.len() == 10)).then_some(fields.len() - 9)
}

/// Reads a PowerInspect ASCII file whose rows have `name_fields` name tokens.
pub fn powerinspect(
    content: &[(usize, &str)],
    name_fields: usize,
) -> Result<ParsedTable, CmmError> {
    let line = content[0].0;
    let names = [
        ("X", Some(Role::Nominal(0))),
        ("Y", Some(Role::Nominal(1))),
        ("Z", Some(Role::Nominal(2))),
        ("I", Some(Role::Normal(0))),
        ("J", Some(Role::Normal(1))),
        ("K", Some(Role::Normal(2))),
        ("offset", Some(Role::Deviation)),
        ("lowTol", None),
        ("highTol", None),
    ];
    let width = name_fields + names.len();
    let mut columns = vec![column(1, "name", Some(Role::Id), None)];
    // Further name tokens (names with spaces) are kept as extra columns.
    for k in 1..name_fields {
        columns.push(column(k + 1, &format!("name part {}", k + 1), None, None));
    }
    for (k, (n, role)) in names.iter().enumerate() {
        columns.push(column(name_fields + k + 1, n, *role, None));
    }
    let layout = from_columns(columns, line)?;
    let (rows, problems, decimal_comma) = fixed_rows(
        content,
        Separator::Spaces,
        width,
        "name X Y Z I J K offset lowTol highTol",
    );
    Ok(ParsedTable {
        kind: FormatKind::PowerInspect,
        layout,
        rows,
        problems,
        separator: Some(Separator::Spaces),
        decimal_comma,
        header_line: None,
        preamble: Vec::new(),
        label: "Autodesk PowerInspect ASCII (name X Y Z I J K offset lowTol highTol), nominal position + normal + deviation".into(),
    })
}
