//! What can go wrong when reading a CMM file, in words a person can act on
//! (`shared/spec/cmm-csv.md`, "Errors a person must get").
//!
//! Two levels: a [`CmmError`] rejects the whole file (empty, binary, no header, a missing
//! column, …); a [`RowProblem`] names one bad row with its line number, the column, the text
//! found and what was expected. A file with bad rows is rejected with *all* of them listed
//! ([`CmmError::BadRows`]) unless the caller asks to exclude them
//! ([`super::ReadOptions::exclude_bad_rows`]); excluded rows are then carried in the result.

use std::fmt;

use serde::{Deserialize, Serialize};

/// A column of the file: 1-based position and the header text (or a descriptive name for files
/// without a header, e.g. `z` of a PC-DMIS XYZIJK line).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ColumnRef {
    /// 1-based column number.
    pub number: usize,
    /// Header text as written in the file (or the field's meaning where there is no header).
    pub name: String,
}

impl fmt::Display for ColumnRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "column {} '{}'", self.number, self.name)
    }
}

/// Why a row is bad.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RowProblemKind {
    /// A value that should be a number is not one.
    NotNumeric,
    /// `NaN`, `inf` or a number too large for a double.
    NotFinite,
    /// A required value is empty.
    EmptyValue,
    /// Fewer fields than the header (the row was cut short).
    Truncated,
    /// More fields than the header.
    TooManyFields,
    /// The row uses a different separator from the header.
    MixedSeparators,
    /// An opening quote without its closing quote carried the row over several lines.
    UnbalancedQuote,
    /// The id was already used on an earlier line.
    DuplicateId,
    /// The normal given in the file has zero length.
    ZeroNormal,
    /// A deviation far larger than a machined part can have (probably another unit).
    ImplausibleDeviation,
    /// The point lies more than the allowed distance from the nominal surfaces.
    FarFromSurface,
}

impl RowProblemKind {
    /// Short reason in words.
    pub fn reason(self) -> &'static str {
        match self {
            Self::NotNumeric => "not a number",
            Self::NotFinite => "not a finite number",
            Self::EmptyValue => "empty value",
            Self::Truncated => "truncated row",
            Self::TooManyFields => "too many fields",
            Self::MixedSeparators => "mixed separators",
            Self::UnbalancedQuote => "unbalanced quote",
            Self::DuplicateId => "duplicate id",
            Self::ZeroNormal => "zero-length normal",
            Self::ImplausibleDeviation => "implausible deviation",
            Self::FarFromSurface => "point far from the nominal surfaces",
        }
    }
}

/// One bad row: line, column, what was found and what was expected.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RowProblem {
    /// 1-based line number in the file.
    pub line: usize,
    /// The column concerned, where one is.
    pub column: Option<ColumnRef>,
    pub kind: RowProblemKind,
    /// The text found (a field, or the whole line when the row shape is wrong).
    pub found: String,
    /// What was expected instead, in words.
    pub expected: String,
}

impl fmt::Display for RowProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_line_problem(
            f,
            self.line,
            self.column.as_ref(),
            self.kind.reason(),
            &self.found,
            &self.expected,
        )
    }
}

/// The one wording of a bad line, shared by every reader (CMM rows, tool paths, NC traces):
/// `line L, column C 'name': reason: found 'F', expected E`.
pub fn write_line_problem(
    f: &mut fmt::Formatter<'_>,
    line: usize,
    column: Option<&ColumnRef>,
    reason: &str,
    found: &str,
    expected: &str,
) -> fmt::Result {
    write!(f, "line {line}")?;
    if let Some(c) = column {
        write!(f, ", {c}")?;
    }
    write!(f, ": {reason}: found '{found}', expected {expected}")
}

/// Lists problems one per line; past `cap` of them, says how many more there are.
pub fn list_line_problems<T: fmt::Display>(problems: &[T], cap: usize) -> String {
    let shown: String = problems
        .iter()
        .take(cap)
        .map(|r| format!("\n  {r}"))
        .collect();
    if problems.len() > cap {
        format!("{shown}\n  … and {} more", problems.len() - cap)
    } else {
        shown
    }
}

/// Lists row problems one per line, for [`CmmError::BadRows`] (all of them: the reader's own
/// limits bound how many there can be).
fn list_rows(rows: &[RowProblem]) -> String {
    list_line_problems(rows, usize::MAX)
}

/// How many distinct lines `rows` are on.
pub(crate) fn distinct_lines(rows: &[RowProblem]) -> usize {
    let mut lines: Vec<usize> = rows.iter().map(|r| r.line).collect();
    lines.sort_unstable();
    lines.dedup();
    lines.len()
}

/// A file the reader rejects, with the offending values in the message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CmmError {
    #[error("'{name}' is empty: {detail}; expected a CMM export with a header row and one point per line")]
    Empty { name: String, detail: String },

    #[error("'{name}' holds binary data ({detail}), expected text: export the measurement as CSV or text{hint}")]
    Binary {
        name: String,
        detail: String,
        hint: String,
    },

    #[error("the file is {bytes} bytes, over the limit of {limit} bytes ({limit_mb} MB)")]
    TooLarge {
        bytes: usize,
        limit: usize,
        limit_mb: f64,
    },

    #[error("the file has more than {limit} data rows ({rows}), over the limit of {limit} rows")]
    TooManyRows { rows: usize, limit: usize },

    #[error("line {line}: no recognisable header: found '{found}', expected column names such as id, curve, x, y, z, nx, ny, nz, deviation (or xmeas, ymeas, zmeas), or a PC-DMIS XYZIJK / PowerInspect file{hint}")]
    NoHeader {
        line: usize,
        found: String,
        hint: String,
    },

    #[error("line {line}, column {column} '{header}': unknown unit '{unit}', expected mm, µm (um), in (inch), cm or m")]
    UnknownUnit {
        line: usize,
        column: usize,
        header: String,
        unit: String,
    },

    #[error("line {line}: columns {first} and {second} both mean {meaning}; keep one of them or rename the other")]
    AmbiguousColumns {
        line: usize,
        first: String,
        second: String,
        meaning: String,
    },

    #[error("line {line}: required column missing: {missing}; found columns: {found}")]
    MissingColumns {
        line: usize,
        missing: String,
        found: String,
    },

    #[error("line {line}: PC-DMIS XYZIJK header without a unit: found '{found}', expected METRIC or INCH in columns 11-16")]
    XyzijkUnit { line: usize, found: String },

    #[error("inch data without a unit: all coordinates lie within {max_abs:.3} of the origin (x {x_min:.3}..{x_max:.3}, y {y_min:.3}..{y_max:.3}, z {z_min:.3}..{z_max:.3}), but the S-shape is about 270 mm wide and 30 mm high; multiplied by 25.4 they fit the part, so these look like inches: write the unit in the header (e.g. 'x [in]'), use INCH in an XYZIJK file, or pass the length unit explicitly")]
    InchWithoutUnit {
        max_abs: f64,
        x_min: f64,
        x_max: f64,
        y_min: f64,
        y_max: f64,
        z_min: f64,
        z_max: f64,
    },

    #[error("wrong units: {detail}")]
    WrongUnits { detail: String },

    #[error("the measurement is not aligned to the part: {detail}; the CMM coordinate system must be the part's (origin and axes of the part frame: paper 000 Table 1's, Z = 0 at the base, Z up), or this is another part")]
    NotAligned { detail: String },

    #[error("{count} bad row(s) on {lines} line(s) of {rows} data rows; the file is rejected as a whole (choose to exclude these rows explicitly to use the others):{}", list_rows(.problems))]
    BadRows {
        count: usize,
        lines: usize,
        rows: usize,
        problems: Vec<RowProblem>,
    },

    #[error("too few points: {found} usable point(s){excluded_note}, the identification needs at least {needed}")]
    TooFewPoints {
        found: usize,
        needed: usize,
        excluded_note: String,
    },

    #[error("no measurement: the file has positions but neither a deviation nor measured columns (columns found: {columns}), and every one of its {points} points lies on the nominal surface to 0.1 µm (largest distance {largest_um:.4} µm): these are nominal positions. Give the measured positions (measured x, y, z columns) or the normal deviation")]
    NoMeasurement {
        points: usize,
        largest_um: f64,
        columns: String,
    },

    #[error("reading option {name} = {value}: expected {expected}")]
    BadOption {
        name: &'static str,
        value: String,
        expected: &'static str,
    },

    #[error("projection onto the nominal part failed at line {line}: {source}")]
    Projection {
        line: usize,
        source: crate::geometry::GeometryError,
    },
}

impl CmmError {
    /// `BadRows` from a non-empty list of problems among `rows` data rows.
    pub fn bad_rows(problems: Vec<RowProblem>, rows: usize) -> Self {
        Self::BadRows {
            count: problems.len(),
            lines: distinct_lines(&problems),
            rows,
            problems,
        }
    }

    /// `TooFewPoints`: `found` usable points where `needed` are required, after `excluded_rows`
    /// bad rows left out at the caller's request (0: none, and no note).
    pub(crate) fn too_few_points(found: usize, needed: usize, excluded_rows: usize) -> Self {
        Self::TooFewPoints {
            found,
            needed,
            excluded_note: if excluded_rows == 0 {
                String::new()
            } else {
                format!(" after excluding {excluded_rows} bad row(s)")
            },
        }
    }

    /// The row problems of a `BadRows` error (empty for the other kinds).
    pub fn row_problems(&self) -> &[RowProblem] {
        match self {
            Self::BadRows { problems, .. } => problems,
            _ => &[],
        }
    }
}
