//! The identified parameters as a compensation table a controller can take: one row per
//! parameter with its ISO 230-1 name, value and unit (CSV or JSON).
//!
//! Names: ISO 230-1 location errors are written without underscores (`EX0B` for E_X0B,
//! s-shape.md); `iso_230_1` gives the subscripted form. The value is the identified error itself
//! (the machine's deviation from its nominal geometry, paper 000 eq. 11), which is what a
//! controller's kinematic-compensation table holds; its sign is not flipped. Parameters that the
//! part could not separate carry their minimum-norm value with status `not_separable`: such a value
//! reproduces the measured part, but not necessarily the machine elsewhere.
//!
//! `fitted_with` says what the values were fitted with (the final identification of
//! [`crate::final_fit::correct`]): the effect ids joined by `+` (`backlash_y`), `structure` (the
//! unexplained structure as a correlated error), or `none` (the location errors alone). The
//! effect's own parameters (`backlash_y.b`) are rows of the table too: they are not machine
//! location errors, and the compensation of the location errors must not include them twice.

use serde::Serialize;

use super::{Identification, Status};
use crate::machine::{ErrorParam, Unit};
use crate::parameter::{ParamId, ParamKind};

/// One row of the compensation table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompensationEntry {
    /// Name as in files and APIs (`EX0B`, `dR`).
    pub name: String,
    /// ISO 230-1 form (`E_X0B`); the name itself for non-ISO parameters.
    pub iso_230_1: String,
    /// Identified value.
    pub value: f64,
    /// `mm` or `rad`.
    pub unit: Unit,
    /// Standard deviation (same unit), `None` when not separable.
    pub std: Option<f64>,
    /// `identified`, `weak` or `not_separable`.
    pub status: Status,
    /// What the values were fitted with: effect ids joined by `+`, `structure` or `none`.
    pub fitted_with: String,
    /// What the parameter is ([`ParamKind`]).
    pub kind: ParamKind,
}

/// ISO 230-1 subscripted form of a location error's name: `EX0B` → `E_X0B`; the name itself for
/// any other parameter.
pub fn iso_230_1_name(id: &ParamId) -> String {
    match id {
        ParamId::Machine(ErrorParam::Location(l)) => {
            format!("E_{}0{}", l.component.letter(), l.axis.letter())
        }
        _ => id.name(),
    }
}

/// The table, in design order; `fitted_with` as in the module doc.
pub fn compensation_table(id: &Identification, fitted_with: &str) -> Vec<CompensationEntry> {
    id.parameters
        .0
        .iter()
        .map(|p| CompensationEntry {
            name: p.name(),
            iso_230_1: iso_230_1_name(&p.id),
            value: p.value,
            unit: p.unit(),
            std: p.std,
            status: p.status,
            fitted_with: fitted_with.to_string(),
            kind: p.id.kind(),
        })
        .collect()
}

/// CSV with header `name,iso_230_1,value,unit,std,status,fitted_with` (shortest round-trip
/// numbers; empty std when not separable).
pub fn compensation_csv(id: &Identification, fitted_with: &str) -> String {
    let mut s = String::from("name,iso_230_1,value,unit,std,status,fitted_with\n");
    for e in compensation_table(id, fitted_with) {
        let status = match e.status {
            Status::Identified => "identified",
            Status::Weak => "weak",
            Status::NotSeparable => "not_separable",
        };
        let std = e.std.map(|v| format!("{v:e}")).unwrap_or_default();
        s.push_str(&format!(
            "{},{},{:e},{},{},{},{}\n",
            e.name, e.iso_230_1, e.value, e.unit, std, status, e.fitted_with
        ));
    }
    s
}

/// JSON array `[{"name","iso_230_1","value","unit","std","status","fitted_with","kind"}, ...]`.
pub fn compensation_json(id: &Identification, fitted_with: &str) -> String {
    serde_json::to_string_pretty(&compensation_table(id, fitted_with))
        .unwrap_or_else(|_| "[]".to_string())
}
