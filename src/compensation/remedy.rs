//! Where an effect of `shared/spec/effects.md` that the kinematic compensation leaves on the
//! part is corrected: whether it is an error of the machine at all, and what corrects it.
//!
//! The compensation of [`super`] enters location errors (ISO 230-1, paper 000 eq. 11) in the
//! controller's kinematic description. The named effects are not location errors:
//! - machine errors of another kind: backlash (the controller's reversal / backlash
//!   compensation of that axis), linear scale errors (its pitch / linear error compensation),
//!   thermal growth of the head (thermal compensation, or a warm-up before the test), the C
//!   axis's zero offset (its reference offset), the pivot-to-tip length (the tool length / pivot
//!   length the kinematic transformation uses), the servo's following error (the position-loop
//!   gains: an axis trailing the others is matched to them);
//! - not machine errors: the tool's radius and taper (the tool table, or another tool), the part's
//!   set-up on the CMM (the measurement's datum alignment), the tool's wear, the flank-milling overcut of the ruled
//!   surface (the tool path: paper 000 §3; no machine correction removes it).

use serde::Serialize;

use crate::machine::AxisName;
use crate::parameter::Effect;

/// What corrects an effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Remedy {
    /// Whether the effect is an error of the machine (of another kind than a location error).
    pub machine_error: bool,
    /// What corrects it, in words.
    pub corrected_by: &'static str,
}

/// The remedy of an effect (module docs).
pub fn remedy(effect: Effect) -> Remedy {
    let machine = |corrected_by| Remedy {
        machine_error: true,
        corrected_by,
    };
    let other = |corrected_by| Remedy {
        machine_error: false,
        corrected_by,
    };
    match effect {
        Effect::Backlash(_) => machine("the controller's backlash (reversal) compensation of that axis"),
        Effect::Scale(AxisName::X | AxisName::Y | AxisName::Z) => {
            machine("the controller's linear (pitch) error compensation of that axis")
        }
        Effect::Scale(_) => machine("the controller's angular error compensation of that axis"),
        Effect::ThermalDrift => {
            machine("the controller's thermal compensation, or a warm-up before the test")
        }
        Effect::CIndex => machine("the C axis's reference (zero) offset in the controller"),
        Effect::AIndex => machine("the A axis's reference (zero) offset in the controller"),
        Effect::PivotLength => {
            machine("the tool length / pivot length of the controller's kinematic transformation")
        }
        Effect::ToolRadius | Effect::ToolTaper => {
            other("the tool table (measured radius), or another tool: not a machine error")
        }
        Effect::SetupError => {
            other("the datum alignment of the part on the CMM: not a machine error")
        }
        Effect::Overcut => other(
            "the tool path (flank milling of a non-developable ruled surface, paper 000 §3): not a machine error",
        ),
        Effect::ToolWear => other(
            "the tool (a fresh tool, a harder grade or coating, or the tool radius offset varied along the cut): not a machine error",
        ),
        Effect::ServoLag(_) => machine(
            "the position-loop gain (Kv) of that axis, matched to the other axes' (or their feed-forward)",
        ),
        Effect::ServoCommon => machine(
            "the position-loop gains or velocity feed-forward of every axis (a smaller following error), or a lower feed",
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every effect of effects.md has a remedy; the tool, set-up and overcut are not machine
    /// errors, the others are.
    #[test]
    fn every_effect_has_a_remedy() {
        for e in Effect::ALL {
            let r = remedy(e);
            let not_machine = matches!(
                e,
                Effect::ToolRadius
                    | Effect::ToolTaper
                    | Effect::SetupError
                    | Effect::Overcut
                    | Effect::ToolWear
            );
            assert_eq!(r.machine_error, !not_machine, "{}", e.id());
            assert!(!r.corrected_by.is_empty());
        }
    }
}
