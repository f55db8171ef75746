//! Compensation in the controller's terms (issue 19, step 3): from an analysis's final answer,
//! (1) the kinematic description a controller holds (each axis's line, the tool tip) before and
//! after the identified location errors are entered ([`crate::machine::axis_lines`]), and
//! (2) the part the same program would leave once they are compensated ([`part`]), with the
//! diagnosed effect, where it is not a location error, left in and said so.
//!
//! Pipeline position: identify → gap → **compensation**. "Before" is the nominal chain (what the
//! controller holds today); "after" is the chain with the identified location errors (the real
//! machine as identified), which is what the controller's kinematic transformation must hold
//! for its inverse kinematics to cut the nominal part. A not-separable group's individual values
//! are a convention: entered together they reproduce this part; the report says so.
//! Units: mm, rad; deviations `(measured − nominal)·N`, + = material left.

pub mod part;
pub mod remedy;

use serde::Serialize;

pub use part::{predicted_part, LeftIn, PredictedPart, PredictedPoint, Spread};
pub use remedy::{remedy, Remedy};

use crate::analysis::Analysis;
use crate::final_fit::correct::Basis;
use crate::identify::Status;
use crate::machine::axis_lines::{kinematic_description, KinematicDescription};
use crate::machine::{ErrorParam, LocationError, MachineErrors, Unit};
use crate::parameter::ParamId;

/// One location error entered into the description.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EnteredError {
    pub name: String,
    pub value: f64,
    pub unit: Unit,
    pub std: Option<f64>,
    pub status: Status,
}

/// The change of one axis (after − before).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxisChange {
    pub axis: crate::machine::AxisName,
    /// Shift of the line's point nearest the origin (mm; rotary axes).
    pub point_shift: Option<[f64; 3]>,
    /// Angle between the two directions (rad).
    pub tilt: f64,
}

/// Everything the compensation of one analysis reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Compensation {
    pub machine: &'static str,
    pub before: KinematicDescription,
    pub after: KinematicDescription,
    pub changes: Vec<AxisChange>,
    /// Shift of the tool tip at the reference pose (mm).
    pub tool_tip_shift: [f64; 3],
    pub entered: Vec<EnteredError>,
    pub part: PredictedPart,
    /// The named effects left on the part, with what corrects them.
    pub effects_left: Vec<EffectLeft>,
    pub notes: Vec<String>,
}

/// A named effect the kinematic compensation leaves on the part.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EffectLeft {
    pub effect: crate::parameter::Effect,
    pub plain_name: &'static str,
    #[serde(flatten)]
    pub remedy: Remedy,
    /// RMS of its fitted part over the used points (mm; the largest of its parameters' parts).
    pub rms: f64,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The compensation of an analysis's final answer (its design, values and measured points).
pub fn compensation(a: &Analysis) -> Compensation {
    let chain = a.settings.machine.chain(a.settings.l0);
    let id = &a.identification;
    let params = &a.design.parameters;
    let location: Vec<Option<LocationError>> = params
        .iter()
        .map(|p| match p {
            ParamId::Machine(ErrorParam::Location(l)) if chain.axis(l.axis).is_some() => Some(*l),
            _ => None,
        })
        .collect();
    let values: Vec<f64> = params
        .iter()
        .map(|p| id.parameters.of(p).map_or(0.0, |e| e.value))
        .collect();
    let mut errors = MachineErrors::none();
    let mut entered = Vec::new();
    for ((l, n), x) in location.iter().zip(params).zip(&values) {
        if let Some(l) = l {
            errors = errors.with(ErrorParam::Location(*l), *x);
            let p = id.parameters.of(n);
            entered.push(EnteredError {
                name: n.name(),
                value: *x,
                unit: l.unit(),
                std: p.and_then(|p| p.std),
                status: p.map_or(Status::Weak, |p| p.status),
            });
        }
    }
    let before = kinematic_description(&chain, &MachineErrors::none());
    let after = kinematic_description(&chain, &errors);
    let changes = before
        .axes
        .iter()
        .zip(&after.axes)
        .map(|(b, f)| {
            let dot: f64 = (0..3).map(|k| b.direction[k] * f.direction[k]).sum();
            let cross = [
                b.direction[1] * f.direction[2] - b.direction[2] * f.direction[1],
                b.direction[2] * f.direction[0] - b.direction[0] * f.direction[2],
                b.direction[0] * f.direction[1] - b.direction[1] * f.direction[0],
            ];
            let sin = (cross[0].powi(2) + cross[1].powi(2) + cross[2].powi(2)).sqrt();
            AxisChange {
                axis: b.axis,
                point_shift: b.point.zip(f.point).map(|(p, q)| sub(q, p)),
                tilt: sin.atan2(dot),
            }
        })
        .collect();
    let pts = &id.points;
    let is_location: Vec<bool> = location.iter().map(Option::is_some).collect();
    let part = predicted_part(
        &pts.iter().map(|p| p.id.clone()).collect::<Vec<_>>(),
        &pts.iter().map(|p| p.curve.clone()).collect::<Vec<_>>(),
        &pts.iter().map(|p| p.used).collect::<Vec<_>>(),
        &pts.iter().map(|p| p.measured).collect::<Vec<_>>(),
        params,
        &a.design.columns,
        &values,
        &is_location,
    );
    let effects_left: Vec<EffectLeft> = a
        .correction
        .effects_included
        .iter()
        .map(|&e| EffectLeft {
            effect: e,
            plain_name: e.plain_name(),
            remedy: remedy(e),
            rms: part
                .left_in
                .iter()
                .filter(|l| l.id.effect() == Some(e))
                .map(|l| l.rms)
                .fold(0.0, f64::max),
        })
        .collect();
    let notes = notes(a, &entered, &part, &effects_left);
    Compensation {
        machine: a.settings.machine.describe(),
        tool_tip_shift: sub(after.tool_tip, before.tool_tip),
        before,
        after,
        changes,
        entered,
        part,
        effects_left,
        notes,
    }
}

/// What the compensation does and does not correct, in sentences.
fn notes(
    a: &Analysis,
    entered: &[EnteredError],
    part: &PredictedPart,
    effects_left: &[EffectLeft],
) -> Vec<String> {
    let mut notes = vec![format!(
        "Enter the \"after\" description in the controller's kinematic transformation (each \
         axis's line and the tool tip at the reference pose, machine frame, all axes at 0): its \
         inverse kinematics then cuts the nominal part. Predicted on this part: RMS {:.2} µm → \
         {:.2} µm, largest |deviation| {:.2} µm → {:.2} µm.",
        part.before.rms * 1e3,
        part.after.rms * 1e3,
        part.before.max_abs * 1e3,
        part.after.max_abs * 1e3
    )];
    let convention: Vec<&str> = entered
        .iter()
        .filter(|e| e.status == Status::NotSeparable)
        .map(|e| e.name.as_str())
        .collect();
    if !convention.is_empty() {
        notes.push(format!(
            "{} cannot be separated on this part: their values are a convention that reproduces \
             this part; entered together they correct this program, not necessarily the machine \
             elsewhere.",
            convention.join(", ")
        ));
    }
    for e in effects_left {
        notes.push(format!(
            "Left in: the {} ({}) is {}, so this compensation does not remove it (its part: \
             {:.2} µm RMS); corrected by {}.",
            e.plain_name,
            e.effect.id(),
            if e.remedy.machine_error {
                "a machine error but not a location error of the kinematic description"
            } else {
                "not an error of the machine"
            },
            e.rms * 1e3,
            e.remedy.corrected_by
        ));
    }
    if let Some(l) = part.left_in.iter().find(|l| l.id == ParamId::ToolRadius) {
        notes.push(format!(
            "Left in: the tool-radius term dR = {:.4} mm is the tool's, not the machine's: correct \
             the tool table ({:.2} µm RMS on the part).",
            l.value,
            l.rms * 1e3
        ));
    }
    if a.correction.basis == Basis::Structure {
        notes.push(
            "The residual holds a structure no candidate explains (fitted as a correlated \
             error): it stays on the part after compensation."
                .to_string(),
        );
    }
    notes
}
