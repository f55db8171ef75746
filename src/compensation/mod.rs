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

pub mod controller;
pub mod description_std;
pub mod entry;
pub mod part;
pub mod propagate;
pub mod remedy;
pub mod withheld;

use serde::Serialize;

pub use part::{predicted_part, LeftIn, PredictedPart, PredictedPoint, Spread};
pub use remedy::{remedy, Remedy};
pub use withheld::{withheld, Withheld};

use controller::{siemens_compensation, ControllerCompensation};
use entry::{entry_rule, ErrorEntry};
use propagate::{entered_covariance, has_covariance};

use crate::analysis::Analysis;
use crate::final_fit::correct::Basis;
use crate::machine::axis_lines::{kinematic_description, KinematicDescription};
use crate::machine::{LocationError, MachineErrors};
use crate::parameter::ParamId;

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
    /// The errors entered: separable and `|value| ≥ 2 std` ([`entry`]).
    pub entered: Vec<ErrorEntry>,
    /// The other location errors, each with why it is not entered.
    pub not_entered: Vec<ErrorEntry>,
    /// The std of every number of `after` (same shape), propagated from the entered errors.
    pub after_std: KinematicDescription,
    /// The covariance the std were propagated with (`fit covariance, std widened` or
    /// `diagonal`).
    pub covariance: &'static str,
    /// The compensation in a real controller's parameters (SINUMERIK), when the chain has an
    /// orientable toolholder; else why not in `controller_unavailable`.
    pub controller: Option<ControllerCompensation>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub controller_unavailable: Option<String>,
    /// The part after compensation on the measured points (in-sample: the fit saw them).
    pub part: PredictedPart,
    /// The part after compensation predicted on curves the fit did not see.
    pub withheld: Withheld,
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
    let location = withheld::location_columns(a);
    let named: Vec<(String, LocationError)> = location
        .iter()
        .map(|(j, l)| (params[*j].name(), *l))
        .collect();
    let entries = entry_rule(id, &named);
    let values: Vec<f64> = params
        .iter()
        .map(|p| id.parameters.of(p).map_or(0.0, |e| e.value))
        .collect();
    let (entered, not_entered): (Vec<ErrorEntry>, Vec<ErrorEntry>) =
        entries.into_iter().partition(ErrorEntry::entered);
    let rows: Vec<usize> = entered
        .iter()
        .filter_map(|e| params.iter().position(|p| p.name() == e.name))
        .collect();
    let errs: Vec<LocationError> = entered.iter().map(|e| e.error).collect();
    let x: Vec<f64> = entered.iter().map(|e| e.value).collect();
    let std: Vec<f64> = entered.iter().map(|e| e.std.unwrap_or(0.0)).collect();
    let covariance = if has_covariance(&id.covariance, &rows) {
        "the final fit's covariance, each std widened to the final answer's (model spread)"
    } else {
        "diagonal (the fit has no covariance of these errors)"
    };
    let cov = entered_covariance(&id.covariance, &rows, &std);
    let errors = controller::machine_errors(&errs, &x);
    let before = kinematic_description(&chain, &MachineErrors::none());
    let after = kinematic_description(&chain, &errors);
    let (after_std, _) = description_std::description_std(&chain, &errs, &x, &cov);
    let (controller, controller_unavailable) = match siemens_compensation(&chain, &errs, &x, &cov) {
        Ok(c) => (Some(c), None),
        Err(e) => (None, Some(e.to_string())),
    };
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
    let removed: Vec<bool> = params
        .iter()
        .map(|p| entered.iter().any(|e| e.name == p.name()))
        .collect();
    let part = predicted_part(
        &pts.iter().map(|p| p.id.clone()).collect::<Vec<_>>(),
        &pts.iter().map(|p| p.curve.clone()).collect::<Vec<_>>(),
        &pts.iter().map(|p| p.used).collect::<Vec<_>>(),
        &pts.iter().map(|p| p.measured).collect::<Vec<_>>(),
        params,
        &a.design.columns,
        &values,
        &removed,
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
    let withheld = withheld(a);
    let mut c = Compensation {
        machine: a.settings.machine.describe(),
        tool_tip_shift: sub(after.tool_tip, before.tool_tip),
        before,
        after,
        after_std,
        covariance,
        changes,
        entered,
        not_entered,
        controller,
        controller_unavailable,
        part,
        withheld,
        effects_left,
        notes: Vec::new(),
    };
    c.notes = notes(a, &c);
    c
}

/// What the compensation does and does not correct, in sentences.
fn notes(a: &Analysis, c: &Compensation) -> Vec<String> {
    let (part, effects_left) = (&c.part, &c.effects_left);
    let mut notes = vec![format!(
        "Enter the \"after\" description in the controller's kinematic transformation (each \
         axis's line and the tool tip at the reference pose, machine frame, all axes at 0): its \
         inverse kinematics then cuts the nominal part. Entered: {} (separable, |value| ≥ {} \
         std). Predicted on the measured points (in-sample): RMS {:.2} µm → {:.2} µm, largest \
         |deviation| {:.2} µm → {:.2} µm.",
        if c.entered.is_empty() {
            "none".to_string()
        } else {
            c.entered
                .iter()
                .map(|e| e.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        },
        entry::SIGNIFICANCE_T,
        part.before.rms * 1e3,
        part.after.rms * 1e3,
        part.before.max_abs * 1e3,
        part.after.max_abs * 1e3
    )];
    if !c.withheld.points.is_empty() {
        notes.push(format!(
            "Predicted on withheld curves (each curve predicted by the fit of the others): RMS \
             {:.2} µm → {:.2} µm, largest |deviation| {:.2} µm → {:.2} µm over {} points.",
            c.withheld.measured.rms * 1e3,
            c.withheld.after.rms * 1e3,
            c.withheld.measured.max_abs * 1e3,
            c.withheld.after.max_abs * 1e3,
            c.withheld.points.len()
        ));
    }
    notes.extend(c.not_entered.iter().filter_map(|e| e.why.clone()).map(|w| {
        let kept = part
            .left_in
            .iter()
            .find(|l| {
                c.not_entered.iter().any(|e| e.name == l.parameter) && w.starts_with(&l.parameter)
            })
            .map_or(String::new(), |l| {
                format!("; the part keeps its {:.2} µm RMS", l.rms * 1e3)
            });
        format!("{w}{kept}.")
    }));
    if let Some(ctl) = &c.controller {
        for h in &ctl.homes {
            notes.push(h.sentence.clone());
        }
        let tilt: Vec<&controller::ControllerParameter> = ctl
            .parameters
            .iter()
            .filter(|p| p.group == controller::ParameterGroup::Nowhere)
            .collect();
        let (x, y) = (tilt[0].value, tilt[1].value);
        let angle = x.hypot(y);
        let h_max = a.points.iter().map(|p| p.h).fold(0.0, f64::max);
        if angle > 0.0 {
            notes.push(format!(
                "The spindle tilt at zero angles, ({x:.2e} ± {:.1e}, {y:.2e} ± {:.1e}) = {angle:.2e} \
                 rad, has no home in the toolholder (its tool points along z at zero angles): \
                 with the tip compensated, the part keeps at most {:.2} µm from it at the highest \
                 measured contact height ({h_max:.1} mm above the tip).",
                tilt[0].std,
                tilt[1].std,
                angle * h_max * 1e3
            ));
        }
    }
    if let Some(why) = &c.controller_unavailable {
        notes.push(format!("No SINUMERIK toolholder: {why}."));
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
