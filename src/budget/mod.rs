//! The error budget of the machining process, point by point (paper 000 §3-§6): how much of the
//! measured deviation of an S-shape part comes from the design (overcut of the non-developable
//! ruled surfaces, §3.1), the CAM tool path (§4.1, Fig. 13-14), the NC controller (§5.1, Fig.
//! 15-16), the machine's geometric errors (§5.2, eq. 12-14), the tool (§3.2) and what is left,
//! with the CMM's uncertainty band (§6, MPE_E).
//!
//! The pipeline of this module:
//! - [`cl`]: a CAM cutter-location file (CSV `x,y,z,i,j,k` or APT `GOTO/x,y,z,i,j,k`) as tool
//!   positions: tip (mm) and unit tool axis in the part frame;
//! - [`trace`]: an NC controller trace of axis values (`X,Y,Z,B,C`, optional `time`) turned into
//!   tool positions by the nominal direct kinematics of the configured machine (eq. 9 / eq. 12
//!   with no errors);
//! - [`discrete`]: the deviation a discrete tool path leaves at a measurement point, as in §4.1 /
//!   Fig. 13 (the normal line intersected with every tool position, the smallest entering
//!   abscissa) with the chord-error bound of eq. 7;
//! - [`sources`]: the sources per point and their min / max per source and per curve; the known
//!   path deviation is subtracted before the machine is identified (`crate::analysis`);
//! - [`synthetic`]: the ideal flank path (eq. 2) sampled at a fixed step, its controller trace by
//!   inverse kinematics (eq. 10), and writers of both file formats (examples and tests).
//!
//! Units: mm and rad (degrees only in trace files, as the machine description says). Sign
//! convention (s-shape.md): a deviation is `(machined − nominal)·N`, N the outward normal;
//! **+ = material left, − = overcut**.

pub mod cl;
pub mod discrete;
pub mod sources;
pub mod synthetic;
pub mod trace;

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::cmm::error::{list_line_problems, write_line_problem};
use crate::cmm::{CmmError, ColumnRef};
use crate::machine::MachineError;
use crate::toolpath::ToolpathError;

pub use cl::read_cl;
pub use discrete::{path_deviation, DiscreteHit};
pub use sources::{error_budget, Budget, BudgetOptions, BudgetPoint, SourceRange, Sources};
pub use trace::{read_trace, TraceMachine};

/// Largest tool-path or trace file read (bytes): 50 MB, as for CMM files (cmm-csv.md).
pub const MAX_FILE_BYTES: usize = 50 * 1024 * 1024;
/// Largest number of tool positions in one file (a 2-hour trace sampled every 8 ms is 900,000).
pub const MAX_POSITIONS: usize = 1_000_000;

/// A tool path as read: tool positions in file order, with the line each came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ToolPath {
    /// The file name (for messages).
    pub name: String,
    /// `CSV x,y,z,i,j,k`, `APT`, or `trace X,Y,Z,B,C through <machine>`.
    pub format: String,
    /// Tool tips (mm, part frame).
    pub tips: Vec<[f64; 3]>,
    /// Unit tool axes, from the tip towards the spindle.
    pub axes: Vec<[f64; 3]>,
    /// 1-based line of each position in its file.
    pub lines: Vec<usize>,
    /// Sample times of a trace (s), where the file has them.
    pub times: Option<Vec<f64>>,
    /// Tool diameter a `CUTTER/d` record declares (mm).
    pub cutter_diameter: Option<f64>,
    /// What the reader noticed and accepted (ignored records, normalised axes).
    pub notes: Vec<String>,
}

impl ToolPath {
    pub fn len(&self) -> usize {
        self.tips.len()
    }
    pub fn is_empty(&self) -> bool {
        self.tips.is_empty()
    }
}

/// One bad line of a tool-path or trace file: line, column, what was found, what was expected
/// (the same wording as [`crate::cmm::RowProblem`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LineProblem {
    /// 1-based line number.
    pub line: usize,
    pub column: Option<ColumnRef>,
    /// Short reason in words (`not a number`, `unrecognised record`, …).
    pub reason: String,
    pub found: String,
    pub expected: String,
}

impl fmt::Display for LineProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_line_problem(
            f,
            self.line,
            self.column.as_ref(),
            &self.reason,
            &self.found,
            &self.expected,
        )
    }
}

fn list_problems(p: &[LineProblem]) -> String {
    list_line_problems(p, 50)
}

/// Failures of the budget stage, with the offending values.
#[derive(Debug, thiserror::Error)]
pub enum BudgetError {
    /// The file could not be decoded as text (empty, binary, too large): the CMM reader's words.
    #[error("{name}: {source}")]
    Decode { name: String, source: CmmError },
    #[error("{name}: {count} bad line(s); the file is rejected as a whole:{}", list_problems(.problems))]
    BadLines {
        name: String,
        count: usize,
        problems: Vec<LineProblem>,
    },
    #[error("{name}: line {line}: no recognisable header: found '{found}', expected {expected}")]
    NoHeader {
        name: String,
        line: usize,
        found: String,
        expected: String,
    },
    #[error("{name}: line {line}: required column missing: {missing}; found columns: {found}")]
    MissingColumns {
        name: String,
        line: usize,
        missing: String,
        found: String,
    },
    #[error("{name}: no tool position in the file (expected {expected})")]
    NoPositions { name: String, expected: String },
    #[error("{name}: more than {limit} tool positions ({found}), over the limit of {limit}")]
    TooManyPositions {
        name: String,
        found: usize,
        limit: usize,
    },
    #[error("{name}: point {id} ({curve}) at ({x:.3}, {y:.3}, {z:.3}) is not reached by any tool position facing it within {limit} mm along its normal: the path does not cover this point (wrong file, frame or units?)")]
    NotReached {
        name: String,
        id: String,
        curve: String,
        x: f64,
        y: f64,
        z: f64,
        limit: f64,
    },
    #[error("tool radius {0} mm is not a positive finite number")]
    BadRadius(f64),
    #[error("CMM band: MPE {constant_um} µm + L/{per_um_mm} must be finite and >= 0 (per > 0)")]
    BadMpe { constant_um: f64, per_um_mm: f64 },
    #[error("machine: {0}")]
    Machine(#[from] MachineError),
    #[error("{0}")]
    Analysis(#[from] AnalysisError),
    #[error("design envelope: {0}")]
    Toolpath(#[from] ToolpathError),
    #[error("example part: {0}")]
    Simulate(#[from] crate::simulate::SimulateError),
}

/// Decodes a tool-path file (size limit, binary data, encodings: the CMM reader's rules).
pub(crate) fn decode_text(bytes: &[u8], name: &str) -> Result<String, BudgetError> {
    crate::cmm::decode::decode(bytes, name, MAX_FILE_BYTES)
        .map(|d| d.text.into_owned())
        .map_err(|source| BudgetError::Decode {
            name: name.to_string(),
            source,
        })
}

/// Rejects a file with bad lines, listing them all.
pub(crate) fn reject(name: &str, problems: Vec<LineProblem>) -> Result<(), BudgetError> {
    if problems.is_empty() {
        Ok(())
    } else {
        Err(BudgetError::BadLines {
            name: name.to_string(),
            count: problems.len(),
            problems,
        })
    }
}
