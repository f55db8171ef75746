//! The fitted shape of a family against the physics (issue 30: "the fitted shape parameter within
//! its reported 95 % interval ≥ 90 %"): the generator knows the shape it machined with, the
//! product reports an interval.
//!
//! - **Backlash** with a first-order settling of `tau` mm of tool-tip path: `backlash_<axis>`'s lag
//!   `tau` and its profile interval ([`crate::gap::shape`]). An underdamped settling is not a
//!   member of the family (its shape rings) and is not scored.
//! - **Warm-up** of time constant `T` over a part cut in `t_cut` minutes (the pause between the
//!   surfaces, when the head warms without cutting, left out): `thermal_drift`'s `f = T/t_cut` and
//!   its interval. The pause puts a step between the surfaces that the family (a law in path
//!   length) does not have, so this check is approximate.
//! - **One axis's servo** trailing the others (`Kv_i` against the common `Kv`, at the feed `F`):
//!   `servo_lag_<axis>.l = (1/Kv_i − 1/Kv)·F/60` mm, within `l̂ ± 1.96 std`.
//!
//! Scored only when the verdict names that effect (the interval is the named fit's).

use serde::Serialize;

use crate::gap::report::DiagnosisReport;
use crate::parameter::Effect;
use crate::validate::physics::backlash::Settling;
use crate::validate::physics::machining::AXES;
use crate::validate::physics::Physics;

/// The shape the physics machined with: the effect, what it is, its value.
pub fn truth_of(physics: &Physics) -> Option<(Effect, &'static str, f64)> {
    match physics {
        Physics::Backlash { axis, lost } => match lost.settling {
            Settling::FirstOrder { tau } => Some((Effect::Backlash(*axis), "backlash lag", tau)),
            Settling::Underdamped { .. } => None,
        },
        Physics::Warmup {
            warmup,
            part_minutes,
            ..
        } => Some((
            Effect::ThermalDrift,
            "warm-up",
            // the family's clock is the path (the cutting time): the pause is left out of it
            warmup.minutes / (part_minutes - warmup.pause_s / 60.0),
        )),
        Physics::Servo { feed, loops, .. } => {
            let kv: Vec<f64> = loops.iter().map(|l| l.kv).collect();
            let odd: Vec<usize> = (0..kv.len())
                .filter(|&i| (0..kv.len()).filter(|&j| j != i).all(|j| kv[j] != kv[i]))
                .collect();
            let [i] = odd.as_slice() else { return None };
            let others: Vec<f64> = (0..kv.len()).filter(|j| j != i).map(|j| kv[j]).collect();
            if others.iter().any(|k| *k != others[0]) {
                return None;
            }
            Some((
                Effect::ServoLag(AXES[*i]),
                "servo lag",
                (1.0 / kv[*i] - 1.0 / others[0]) * feed / 60.0,
            ))
        }
        _ => None,
    }
}

/// One check: the truth and the reported interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShapeCheck {
    pub what: &'static str,
    pub truth: f64,
    pub low: f64,
    pub high: f64,
    pub within: bool,
}

/// The check of `physics` against the report, when the verdict names the effect with a shape.
pub fn check(physics: &Physics, report: &DiagnosisReport) -> Option<ShapeCheck> {
    let (effect, what, truth) = truth_of(physics)?;
    if !report.verdict.finding.effects().contains(&effect) {
        return None;
    }
    let (low, high) = match effect {
        Effect::ServoLag(_) => {
            let e = report.verdict.parameter(effect, "l")?;
            (e.value - 1.96 * e.std, e.value + 1.96 * e.std)
        }
        _ => {
            let sh = report
                .candidates
                .iter()
                .find(|c| c.effect == effect && c.with.is_none())?
                .shape
                .as_ref()?;
            (
                if sh.low_open { 0.0 } else { sh.low },
                if sh.high_open { f64::INFINITY } else { sh.high },
            )
        }
    };
    Some(ShapeCheck {
        what,
        truth,
        low,
        high,
        within: low <= truth && truth <= high,
    })
}
