//! ISO 230-1 location errors of every axis and the minimal independent set (paper 000 Table 3).
//!
//! Every axis `i` has six location errors of its reference line, named without underscores:
//! `EX0i, EY0i, EZ0i` (mm, position) and `EA0i, EB0i, EC0i` (rad, orientation about x, y, z).
//! They enter the chain as the matrix `D_i` of paper 000 eq. 11 before the axis motion.
//!
//! ## Reduction to the minimal set (derived from the chain, not listed per machine)
//! Following paper 000 §5.2 / Table 3 (ISO 230-1 with the machine coordinate system: X primary,
//! Y secondary; origin on the first rotary axis line at the height where the second one meets it):
//! - **Linear axis** along `k`: its position errors are meaningless (`-`: a linear axis is a
//!   direction) except the one along `k`, its zero position (`0`); its rotation about `k` is
//!   meaningless. Of the two squareness angles, the primary axis (X) has none (`0`: it defines x),
//!   the secondary (Y) keeps the one about the third direction (EC0Y; `0` for the one about X,
//!   which defines the plane), the tertiary (Z) keeps both.
//! - **Rotary axis** about `k`: its rotation about `k` is its angular zero (`0`); its position
//!   along `k` is meaningless; its two tilts are free. The **first** rotary axis (the one nearest
//!   the workpiece in the structural code) carries the origin: both its perpendicular positions
//!   are `0`. The **second** one loses the position along the first one's direction (origin
//!   height) and keeps the other.
//!
//! For `w C Y' b X Z B t` (paper 000) this gives EC0Y, EA0Z, EB0Z, EA0C, EB0C, EX0B, EA0B, EC0B.

use serde::{Deserialize, Serialize};

use super::chain::{AxisKind, AxisName, Chain};
use super::unit::Unit;
use super::MachineError;
use crate::numerics::order::sort_by_index;

/// Typical magnitude of an angular location error (rad): the unit of paper 000 Figure 19.
pub const TYPICAL_ANGLE_RAD: f64 = 1e-4;
/// Typical magnitude of a linear location error or tool-radius error (mm): Figure 19's unit for `EX0B`.
pub const TYPICAL_LENGTH_MM: f64 = 0.01;

/// The typical size of a location error of this kind of component, in its unit
/// ([`Unit::of_kind`]).
pub fn kind_typical(kind: AxisKind) -> f64 {
    match kind {
        AxisKind::Linear => TYPICAL_LENGTH_MM,
        AxisKind::Rotary => TYPICAL_ANGLE_RAD,
    }
}

/// One location error: component (X, Y, Z position or A, B, C orientation) of one axis's line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct LocationError {
    /// X, Y, Z: position (mm) along x, y, z; A, B, C: orientation (rad) about x, y, z.
    pub component: AxisName,
    /// The axis whose reference line is displaced.
    pub axis: AxisName,
}

impl LocationError {
    pub const fn new(component: AxisName, axis: AxisName) -> Self {
        Self { component, axis }
    }
    /// `EC0Y` etc.
    pub fn name(&self) -> String {
        format!("E{}0{}", self.component.letter(), self.axis.letter())
    }
    /// Parses `EC0Y` (also `E_C0Y`, `ECOY` with a letter O as in the paper's OCR).
    pub fn parse(s: &str) -> Result<Self, MachineError> {
        let bad = || MachineError::BadErrorName {
            name: s.to_string(),
        };
        let t: Vec<char> = s.chars().filter(|&c| c != '_').collect();
        if t.len() != 4 || t[0] != 'E' || !(t[2] == '0' || t[2] == 'O') {
            return Err(bad());
        }
        let component = AxisName::from_letter(t[1]).ok_or_else(bad)?;
        let axis = AxisName::from_letter(t[3]).ok_or_else(bad)?;
        Ok(Self { component, axis })
    }
    /// The unit of its value: `mm` for a position component (X, Y, Z), `rad` for an orientation
    /// (A, B, C).
    pub fn unit(&self) -> Unit {
        Unit::of_kind(self.component.kind())
    }
    /// Its typical size on a real machine, in its unit ([`TYPICAL_LENGTH_MM`],
    /// [`TYPICAL_ANGLE_RAD`]: paper 000 Figure 19's units).
    pub fn typical(&self) -> f64 {
        kind_typical(self.component.kind())
    }
    /// Index 0..6 of the component in `D_i`'s parameter vector (X, Y, Z, A, B, C).
    pub fn component_index(&self) -> usize {
        self.component.index()
    }
}

impl std::fmt::Display for LocationError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.name())
    }
}

/// Status of one location error in the reduction (paper 000 Table 3 notation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum LocationStatus {
    /// A parameter of the minimal set.
    Free,
    /// `0`: set to zero by the choice of the coordinate system, origin or axis zero.
    Zero,
    /// `-`: has no meaning for this axis.
    Meaningless,
}

/// One row of the reduction table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LocationRow {
    pub error: LocationError,
    pub status: LocationStatus,
    /// Why, in words.
    pub reason: String,
}

/// The 6 location errors of every axis with their status, and the minimal independent set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MinimalSet {
    pub rows: Vec<LocationRow>,
}

impl MinimalSet {
    /// The free parameters, ordered: linear axes X, Y, Z, then rotary axes from the workpiece to
    /// the tool; within an axis X, Y, Z, A, B, C (paper 000's ξ order for its machine).
    pub fn free(&self) -> Vec<LocationError> {
        self.rows
            .iter()
            .filter(|r| r.status == LocationStatus::Free)
            .map(|r| r.error)
            .collect()
    }
    /// Names of [`MinimalSet::free`].
    pub fn names(&self) -> Vec<String> {
        self.free().iter().map(LocationError::name).collect()
    }
    pub fn status(&self, e: LocationError) -> Option<LocationStatus> {
        self.rows.iter().find(|r| r.error == e).map(|r| r.status)
    }
}

/// Derives the reduction table of the chain's location errors (module docs).
pub fn minimal_set(chain: &Chain) -> MinimalSet {
    let mut rows = Vec::new();
    let mut linear: Vec<AxisName> = chain
        .axes()
        .filter(|a| a.name.kind() == AxisKind::Linear)
        .map(|a| a.name)
        .collect();
    sort_by_index(&mut linear, |n| n.index());
    let rotary: Vec<AxisName> = chain
        .code_order()
        .iter()
        .filter(|a| a.name.kind() == AxisKind::Rotary)
        .map(|a| a.name)
        .collect();
    let row = |axis: AxisName, comp: usize, status, reason: &str| LocationRow {
        error: LocationError::new(AxisName::ALL[comp], axis),
        status,
        reason: reason.to_string(),
    };
    for (rank, &axis) in linear.iter().enumerate() {
        let k = axis.direction();
        let dirs: Vec<usize> = linear.iter().map(|a| a.direction()).collect();
        for comp in 0..6 {
            let (status, reason) = if comp < 3 {
                if comp == k {
                    (LocationStatus::Zero, "zero position of the axis (origin)")
                } else {
                    (
                        LocationStatus::Meaningless,
                        "position of a linear axis line (only its direction matters)",
                    )
                }
            } else {
                let about = comp - 3;
                if about == k {
                    (
                        LocationStatus::Meaningless,
                        "rotation of a direction about itself",
                    )
                } else if rank == 0 {
                    (
                        LocationStatus::Zero,
                        "primary axis: defines the x direction",
                    )
                } else if rank == 1 && about == dirs[0] {
                    (
                        LocationStatus::Zero,
                        "secondary axis: the plane of the primary and secondary axes",
                    )
                } else {
                    (LocationStatus::Free, "squareness")
                }
            };
            rows.push(row(axis, comp, status, reason));
        }
    }
    let first_dir = rotary.first().map(|a| a.direction());
    for (rank, &axis) in rotary.iter().enumerate() {
        let k = axis.direction();
        for comp in 0..6 {
            let (status, reason) = if comp < 3 {
                if comp == k {
                    (
                        LocationStatus::Meaningless,
                        "position of an axis line along itself",
                    )
                } else if rank == 0 {
                    (LocationStatus::Zero, "origin on the first rotary axis line")
                } else if Some(comp) == first_dir {
                    (
                        LocationStatus::Zero,
                        "origin at the height where this axis meets the first rotary axis",
                    )
                } else {
                    (LocationStatus::Free, "offset of the axis line")
                }
            } else if comp - 3 == k {
                (LocationStatus::Zero, "angular zero of the axis")
            } else {
                (LocationStatus::Free, "tilt of the axis line")
            };
            rows.push(row(axis, comp, status, reason));
        }
    }
    MinimalSet { rows }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for s in ["EC0Y", "EX0B", "EA0C"] {
            assert_eq!(LocationError::parse(s).unwrap().name(), s);
        }
        assert_eq!(LocationError::parse("E_COY").unwrap().name(), "EC0Y");
        assert!(LocationError::parse("EQ0Y").is_err());
    }
}
