//! The result of reading a CMM file: one [`CmmPoint`] per usable row (all lengths in mm), the
//! format found, warnings, and the rows excluded at the caller's explicit request.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::delimited::Separator;
use super::error::RowProblem;
use super::header::Column;

/// One measured point as the file gives it. Lengths in mm (converted from the file's units);
/// the normal as written (not normalised; checked non-zero).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CmmPoint {
    /// 1-based line number in the file.
    pub line: usize,
    /// Point id as written, or the 1-based row number where the file has no id column.
    pub id: String,
    /// Curve label (`A_Z11`, …) where the file has one.
    pub curve: Option<String>,
    /// Nominal position (mm).
    pub nominal: Option<[f64; 3]>,
    /// Outward normal as given by the file (unitless).
    pub normal: Option<[f64; 3]>,
    /// Measured position (mm).
    pub measured: Option<[f64; 3]>,
    /// Normal deviation (mm), `(measured - nominal)·N`: + material left, - overcut.
    pub deviation: Option<f64>,
    /// Texts of the extra columns, in the order of [`CmmFile::extra_columns`].
    pub extra: Vec<String>,
}

impl CmmPoint {
    /// The position the point stands for on or near the part: measured if given, else nominal.
    pub fn position(&self) -> Option<[f64; 3]> {
        self.measured.or(self.nominal)
    }
}

/// A remark that does not stop the reading.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CmmWarning {
    /// 1-based line the remark is about, if one.
    pub line: Option<usize>,
    pub message: String,
}

impl CmmWarning {
    pub fn at(line: usize, message: impl Into<String>) -> Self {
        Self {
            line: Some(line),
            message: message.into(),
        }
    }
    pub fn file(message: impl Into<String>) -> Self {
        Self {
            line: None,
            message: message.into(),
        }
    }
}

impl fmt::Display for CmmWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "line {l}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

/// Which family of format the file is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FormatKind {
    /// Delimited table with a header row.
    Delimited,
    /// PC-DMIS `XYZIJK` export.
    Xyzijk,
    /// Autodesk PowerInspect ASCII (`name X Y Z I J K offset lowTol highTol`).
    PowerInspect,
    /// DMIS output (ISO 22093): `FA(label)=FEAT/POINT,CART,x,y,z,i,j,k` per measured point.
    DmisOutput,
}

/// What the reader found about the file's format.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FormatInfo {
    pub kind: FormatKind,
    /// One sentence for people, e.g. "semicolon-separated table with decimal comma, …".
    pub description: String,
    /// Text encoding (`UTF-8`, `UTF-8 with BOM`, `Windows-1252`, …).
    pub encoding: String,
    /// Field separator (delimited tables and XYZIJK).
    pub separator: Option<Separator>,
    /// Whether numbers use a decimal comma.
    pub decimal_comma: bool,
    /// Line of the header row (delimited) or of the `XYZIJK` line.
    pub header_line: Option<usize>,
    /// The columns with their meaning and unit.
    pub columns: Vec<Column>,
    /// Positions x, y, z with neither a deviation nor measured columns: read as measured
    /// positions and projected.
    #[serde(default)]
    pub positions_read_as_measured: bool,
}

/// A CMM file read: points in file order, format, warnings, excluded rows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CmmFile {
    /// The name the caller gave (usually the file name).
    pub name: String,
    pub format: FormatInfo,
    /// Header names of the columns kept as text (tolerances, comments, …).
    pub extra_columns: Vec<String>,
    pub points: Vec<CmmPoint>,
    /// Rows left out because the caller chose `exclude_bad_rows`, each with its reason; every
    /// downstream result must show them. Empty otherwise (bad rows reject the file).
    pub excluded: Vec<RowProblem>,
    pub warnings: Vec<CmmWarning>,
    /// Comment and blank lines seen (not data).
    pub comment_lines: usize,
    pub blank_lines: usize,
}

impl CmmFile {
    /// The distinct line numbers of the excluded rows, ascending.
    pub fn excluded_lines(&self) -> Vec<usize> {
        let mut lines: Vec<usize> = self.excluded.iter().map(|p| p.line).collect();
        lines.sort_unstable();
        lines.dedup();
        lines
    }
}
