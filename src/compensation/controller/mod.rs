//! The entered errors in a real controller's own parameters, each with its std, and where each
//! entered error goes: a kinematic parameter, the controller's squareness (cross-error)
//! table, the part program's work offset, or nowhere.
//!
//! Controller: SINUMERIK (orientable toolholder `$TC_CARR`, [`siemens`]), checked by an
//! implementation written from Siemens' documentation ([`siemens_kinematics`]). Where an error
//! goes is read from the first-order derivatives of the written numbers at the nominal machine
//! (at the identified values, second-order cross terms of two errors would add spurious homes):
//! an error goes where a typical error of its size
//! ([`crate::machine::location_errors::kind_typical`]) moves a written number by more than
//! [`HOME_FLOOR`].

pub mod siemens;
pub mod siemens_kinematics;

use nalgebra::DMatrix;
use serde::Serialize;

use super::propagate::{jacobian, propagated_std};
use crate::machine::{Chain, ErrorParam, LocationError, MachineErrors, Unit};
use siemens_kinematics::{KinematicType, Toolholder};

/// A written number that a typical error moves by less than this (mm, or unit-vector
/// components, or mm/mm) is not a home of that error.
pub const HOME_FLOOR: f64 = 1e-9;

/// One parameter as the controller holds it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControllerParameter {
    /// `$TC_CARR7`, `CEC Z→Y`, `TRANS X`.
    pub name: String,
    /// What it is.
    pub meaning: String,
    pub value: f64,
    /// Propagated from the entered errors (module docs of [`super::propagate`]).
    pub std: f64,
    pub unit: Unit,
    pub group: ParameterGroup,
    /// Where it lives, in words.
    pub place: &'static str,
}

/// Where a written number lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ParameterGroup {
    /// The toolholder's kinematic parameters and the tool's length.
    Kinematic,
    /// The squareness / cross-error compensation table.
    Squareness,
    /// The part program's work offset.
    WorkOffset,
    /// No parameter holds it (the tool's direction at zero angles).
    Nowhere,
}

impl ParameterGroup {
    /// Where a number of the group lives, in words.
    pub fn place(self) -> &'static str {
        match self {
            ParameterGroup::Kinematic => "toolholder / tool table",
            ParameterGroup::Squareness => "squareness table (CEC)",
            ParameterGroup::WorkOffset => "part program: work offset",
            ParameterGroup::Nowhere => "nowhere (no parameter)",
        }
    }
}

/// Where one entered error goes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorHome {
    pub name: String,
    /// The groups it moves, in [`ParameterGroup`] order.
    pub groups: Vec<ParameterGroup>,
    /// The parameters it moves (names) and the group of each.
    pub parameters: Vec<String>,
    #[serde(skip)]
    pub groups_of: Vec<ParameterGroup>,
    /// Where it goes, in a sentence.
    pub sentence: String,
}

/// The compensation as one controller holds it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControllerCompensation {
    pub controller: &'static str,
    pub kinematic_type: KinematicType,
    pub toolholder: Toolholder,
    /// Every written number with its std, then the tool direction at zero angles (`Nowhere`).
    pub parameters: Vec<ControllerParameter>,
    pub homes: Vec<ErrorHome>,
}

fn rows() -> Vec<(String, String, Unit, ParameterGroup)> {
    use ParameterGroup::*;
    let mut r = Vec::new();
    let xyz = ["x", "y", "z"];
    let mut vector = |first: usize, what: &str, unit: Unit| {
        for (k, c) in xyz.iter().enumerate() {
            r.push((
                format!("$TC_CARR{}", first + k),
                format!("{what}, {c}"),
                unit.clone(),
                Kinematic,
            ));
        }
    };
    vector(1, "offset vector l1", Unit::Mm);
    vector(4, "offset vector l2", Unit::Mm);
    vector(15, "offset vector l3", Unit::Mm);
    vector(18, "offset vector l4", Unit::Mm);
    vector(7, "rotary axis vector v1", Unit::One);
    vector(10, "rotary axis vector v2", Unit::One);
    for (name, c) in [("$TC_DP5", "x"), ("$TC_DP4", "y"), ("$TC_DP3", "z")] {
        r.push((
            name.to_string(),
            format!("tool length component (G17), {c}"),
            Unit::Mm,
            Kinematic,
        ));
    }
    let slope = Unit::parse("mm/mm");
    for a in ["X", "Y", "Z"] {
        for o in ["X", "Y", "Z"] {
            r.push((
                format!("CEC {a}→{o}"),
                format!("squareness: {o} correction per mm of {a} travel"),
                slope.clone(),
                Squareness,
            ));
        }
    }
    for c in ["X", "Y", "Z"] {
        r.push((
            format!("TRANS {c}"),
            format!("work offset, translation {c}"),
            Unit::Mm,
            WorkOffset,
        ));
    }
    for c in ["X", "Y", "Z"] {
        r.push((
            format!("ROT {c}"),
            format!("work offset, rotation about {c} (Rz·Ry·Rx)"),
            Unit::Rad,
            WorkOffset,
        ));
    }
    for c in xyz {
        r.push((
            format!("tool direction at zero angles, {c}"),
            "the spindle tilt: no toolholder parameter holds it".to_string(),
            Unit::One,
            Nowhere,
        ));
    }
    r
}

/// The written numbers in [`rows`] order.
fn flatten(h: &Toolholder, d0: [f64; 3]) -> Vec<f64> {
    let mut v = Vec::with_capacity(39);
    for a in [h.l1, h.l2, h.l3, h.l4, h.v1, h.v2, h.tool] {
        v.extend(a);
    }
    for a in h.cec {
        v.extend(a);
    }
    v.extend(h.work_offset_translation);
    v.extend(h.work_offset_rotation);
    v.extend(d0);
    v
}

/// The errors `names` with `values` as the chain's machine errors.
pub fn machine_errors(errors: &[LocationError], values: &[f64]) -> MachineErrors {
    errors
        .iter()
        .zip(values)
        .fold(MachineErrors::none(), |m, (l, v)| {
            m.with(ErrorParam::Location(*l), *v)
        })
}

/// The SINUMERIK compensation of `chain` with the entered `errors` at `values`, their
/// covariance `cov` (module docs); `Err` when the chain has no orientable toolholder.
pub fn siemens_compensation(
    chain: &Chain,
    errors: &[LocationError],
    values: &[f64],
    cov: &DMatrix<f64>,
) -> Result<ControllerCompensation, siemens::SiemensError> {
    let (holder, d0) = siemens::toolholder(chain, &machine_errors(errors, values))?;
    let f = |x: &[f64]| -> Vec<f64> {
        siemens::toolholder(chain, &machine_errors(errors, x))
            .map(|(h, d)| flatten(&h, d))
            .unwrap_or_default()
    };
    let typical: Vec<f64> = errors.iter().map(|l| l.typical()).collect();
    let steps: Vec<f64> = typical.iter().map(|t| 1e-2 * t).collect();
    let j = jacobian(&f, values, &steps);
    let std = propagated_std(&j, cov);
    let value = flatten(&holder, d0);
    let parameters: Vec<ControllerParameter> = rows()
        .into_iter()
        .enumerate()
        .map(|(i, (name, meaning, unit, group))| ControllerParameter {
            name,
            meaning,
            value: value[i],
            std: std[i],
            unit,
            group,
            place: group.place(),
        })
        .collect();
    let j0 = jacobian(&f, &vec![0.0; values.len()], &steps);
    let homes = errors
        .iter()
        .enumerate()
        .map(|(k, l)| {
            let moved: Vec<&ControllerParameter> = parameters
                .iter()
                .enumerate()
                .filter(|(i, _)| (j0[(*i, k)] * typical[k]).abs() > HOME_FLOOR)
                .map(|(_, p)| p)
                .collect();
            let mut groups: Vec<ParameterGroup> = moved.iter().map(|p| p.group).collect();
            groups.dedup();
            ErrorHome {
                name: l.name(),
                groups,
                parameters: moved.iter().map(|p| p.name.clone()).collect(),
                groups_of: moved.iter().map(|p| p.group).collect(),
                sentence: String::new(),
            }
        })
        .map(|mut h| {
            h.sentence = home_sentence(&h);
            h
        })
        .collect();
    Ok(ControllerCompensation {
        controller: "SINUMERIK (840D sl / ONE): orientable toolholder $TC_CARR, CEC, work offset",
        kinematic_type: holder.kinematic_type,
        toolholder: holder,
        parameters,
        homes,
    })
}

/// Where one entered error goes, in a sentence.
fn home_sentence(h: &ErrorHome) -> String {
    use ParameterGroup as G;
    let of = |g: G| -> Vec<&str> {
        h.parameters
            .iter()
            .zip(&h.groups_of)
            .filter(|(_, k)| **k == g)
            .map(|(p, _)| p.as_str())
            .collect()
    };
    let mut parts = Vec::new();
    for g in &h.groups {
        let names = of(*g).join(", ");
        parts.push(match g {
            G::Kinematic => format!("the toolholder's kinematic parameters ({names})"),
            G::Squareness => format!("the squareness (CEC) table ({names})"),
            G::WorkOffset => format!("the part program's work offset ({names})"),
            G::Nowhere => "nowhere for its tilt of the tool at zero angles (no toolholder \
                 parameter holds a spindle tilt: the part keeps it)"
                .to_string(),
        });
    }
    if parts.is_empty() {
        parts.push("no written number (it moves none by more than 1e-9)".to_string());
    }
    format!("{} goes to {}.", h.name, parts.join("; "))
}
