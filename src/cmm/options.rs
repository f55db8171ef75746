//! Options of reading and matching a CMM file; defaults follow cmm-csv.md.

use crate::numerics::parallel::Threads;
use serde::{Deserialize, Serialize};

use super::units::LengthUnit;

/// File size limit: 50 MB (MiB, 52 428 800 bytes).
pub const MAX_BYTES: usize = 50 * 1024 * 1024;
/// Data-row limit.
pub const MAX_ROWS: usize = 1_000_000;
/// Default minimum of usable points: the 8 location errors of s-shape.md and the tool-radius
/// term, plus one degree of freedom left for the residual.
pub const MIN_POINTS: usize = 10;
/// A point further than this from the nominal surfaces is rejected (mm).
pub const MAX_DISTANCE_MM: f64 = 2.0;
/// A file normal further than this from the model's normal is warned about (degrees).
pub const NORMAL_WARN_DEG: f64 = 2.0;
/// A file deviation and the one from its positions disagreeing by more than this are warned
/// about (mm; 1 µm).
pub const DEVIATION_WARN_MM: f64 = 1e-3;

/// How to read (and match) a file. `Default` is strict: any bad row rejects the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ReadOptions {
    /// Exclude the bad rows (listed in the result) instead of rejecting the file.
    pub exclude_bad_rows: bool,
    /// Fewest usable points accepted.
    pub min_points: usize,
    /// Largest file accepted (bytes).
    pub max_bytes: usize,
    /// Most data rows accepted.
    pub max_rows: usize,
    /// Unit of length columns whose header gives none. `None`: mm, with a check that the data
    /// are not inches; `Some(unit)`: that unit, unchecked (the person said so).
    pub length_unit: Option<LengthUnit>,
    /// Largest distance of a point from the nominal surfaces (mm).
    pub max_distance_mm: f64,
    /// Angle between file and model normals above which a warning is given (degrees).
    pub normal_warn_deg: f64,
    /// Disagreement between a file deviation and the positions above which a warning is given (mm).
    pub deviation_warn_mm: f64,
    /// Threads the points are matched on (the same matches on any count; not a setting of
    /// the result: not written out).
    #[serde(skip)]
    pub threads: Threads,
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self {
            exclude_bad_rows: false,
            min_points: MIN_POINTS,
            max_bytes: MAX_BYTES,
            max_rows: MAX_ROWS,
            length_unit: None,
            max_distance_mm: MAX_DISTANCE_MM,
            normal_warn_deg: NORMAL_WARN_DEG,
            deviation_warn_mm: DEVIATION_WARN_MM,
            threads: Threads::ONE,
        }
    }
}

impl ReadOptions {
    /// Checks the numeric settings: `max_distance_mm`, `normal_warn_deg` and
    /// `deviation_warn_mm` must be finite and > 0 (a NaN limit would let every point through).
    pub fn validate(&self) -> Result<(), super::CmmError> {
        for (name, value) in [
            ("max_distance_mm", self.max_distance_mm),
            ("normal_warn_deg", self.normal_warn_deg),
            ("deviation_warn_mm", self.deviation_warn_mm),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(super::CmmError::BadOption {
                    name,
                    value: value.to_string(),
                    expected: "a finite number > 0",
                });
            }
        }
        Ok(())
    }
    pub fn with_exclude_bad_rows(mut self, yes: bool) -> Self {
        self.exclude_bad_rows = yes;
        self
    }
    pub fn with_threads(mut self, threads: Threads) -> Self {
        self.threads = threads;
        self
    }
    pub fn with_min_points(mut self, n: usize) -> Self {
        self.min_points = n;
        self
    }
    pub fn with_max_bytes(mut self, n: usize) -> Self {
        self.max_bytes = n;
        self
    }
    pub fn with_max_rows(mut self, n: usize) -> Self {
        self.max_rows = n;
        self
    }
    pub fn with_length_unit(mut self, unit: LengthUnit) -> Self {
        self.length_unit = Some(unit);
        self
    }
    pub fn with_max_distance_mm(mut self, mm: f64) -> Self {
        self.max_distance_mm = mm;
        self
    }
}
