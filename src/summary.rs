//! A one-look summary of the built-in example part: what the page and `testpiece info` show first.

use serde::Serialize;

use crate::part::{SShape, Surface};

/// Length of one measurement curve of the S-shape.
#[derive(Debug, Clone, Serialize)]
pub struct CurveLength {
    /// `A_Z11`, `A_Z25`, `B_Z11`, `B_Z25`
    pub curve: String,
    /// Height of the curve (mm)
    pub z: f64,
    /// Arc length of the curve `S(u, z/30)`, u ∈ [0, 1] (mm)
    pub length: f64,
}

/// The summary of the nominal S-shape part.
#[derive(Debug, Clone, Serialize)]
pub struct PartSummary {
    pub version: &'static str,
    pub curves: Vec<CurveLength>,
}

/// Lengths of the four measurement curves (Z = 11 and 25 mm on surfaces A and B).
pub fn part_summary() -> PartSummary {
    let part = SShape::iso();
    let mut curves = Vec::new();
    for s in Surface::BOTH {
        for z in [11.0, 25.0] {
            curves.push(CurveLength {
                curve: format!("{}_Z{}", s.name(), z as u32),
                z,
                length: part.curve_length(s, z / crate::part::s_shape::HEIGHT, 16),
            });
        }
    }
    PartSummary {
        version: crate::VERSION,
        curves,
    }
}
