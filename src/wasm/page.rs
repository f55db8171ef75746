//! What the page needs before any computation, in one call when it opens: the version, the
//! machines of the "Kinematic chain" setting, the built-in example parts, the measurement curves
//! in id order, and the words and thresholds it writes beside the core's results (so that no
//! label or threshold is copied into `www/`).
//!
//! Each word is given for a value of a core enum, keyed by that value's serde tag (the text the
//! results carry), and chosen by an exhaustive `match`: a new variant does not compile until it
//! has its words.

use std::collections::BTreeMap;

use serde::Serialize;
use wasm_bindgen::prelude::*;

use crate::compare::{Flag, DIFFERENT_Z, SUSPECT_Z};
use crate::examples::{example_text, EXAMPLES};
use crate::gap::location::{Group, REVERSAL_WINDOW_MM};
use crate::gap::regions::{Lean, Region};
use crate::identify::{GroupKind, Status};
use crate::machine::AxisName;
use crate::part::Curve;
use crate::sensitivity::cone_frustum::ConeFrustum;
use crate::sensitivity::error_set::ErrorStatus;
use crate::sensitivity::frenet::Cutting;
use crate::settings::{MachineChoice, MachineInfo};

/// A built-in example part: its name, what it is and the file's text.
#[derive(Serialize)]
struct Example {
    name: &'static str,
    description: &'static str,
    text: String,
}

/// The page's words for the values the results carry, keyed by the value's serde tag.
#[derive(Serialize)]
struct Words {
    /// A where-group of the diagnosis (`group` of `diagnosis.report.where[]`).
    groups: BTreeMap<String, &'static str>,
    /// A location error's status in the machine's set (`error_set.rows[].status`).
    error_status: BTreeMap<String, &'static str>,
    /// An identified parameter's status (`identification.parameters[].status`).
    parameter_status: BTreeMap<String, &'static str>,
    /// A group of the identification (`identification.groups[].kind`).
    group_kind: BTreeMap<String, &'static str>,
    /// An effect of the machine's catalogue (`error_set.effects[].status`).
    effect_status: BTreeMap<&'static str, &'static str>,
    /// A difference of two parts (`differences[].flag` of `compareParameters`).
    flags: BTreeMap<String, String>,
}

/// The thresholds behind the words: the where-window of a reversal and the comparison's z
/// limits with their two-sided false-alarm rates under the normal law.
#[derive(Serialize)]
struct Thresholds {
    /// Half-width of the window of tool path around an axis reversal (mm).
    reversal_window_mm: f64,
    different_z: f64,
    suspect_z: f64,
    /// `P(|z| ≥ different_z)` for one parameter of two equal parts.
    different_false_alarm: f64,
    /// `P(|z| ≥ suspect_z)`.
    suspect_false_alarm: f64,
    /// An identified parameter is clearly non-zero at `|value| ≥ nonzero_t` std.
    nonzero_t: f64,
}

/// A cone frustum of the Sensitivity view: its name and shape (degrees).
#[derive(Serialize)]
struct Cone {
    kind: &'static str,
    /// Half apex angle θ.
    half_apex_deg: f64,
    /// Inclination β of the cone axis.
    inclination_deg: f64,
}

/// An S-shape surface of the path coefficients and the way its flank pass cuts.
#[derive(Serialize)]
struct PathSurface {
    surface: &'static str,
    /// `down-cutting` or `up-cutting`.
    cutting: &'static str,
}

/// What the curves beside Figure 19 offer ([`super::curves`]).
#[derive(Serialize)]
struct Paths {
    cones: Vec<Cone>,
    /// Paper 002's offsets of the cone on the table (mm): centre `d`, height `p`.
    cone_offsets: [f64; 2],
    surfaces: Vec<PathSurface>,
}

fn paths() -> Paths {
    let degrees = |rad: f64| (rad.to_degrees() * 1e9).round() / 1e9;
    let offsets = ConeFrustum::m3_15().with_offsets();
    Paths {
        cones: super::curves::CONES
            .iter()
            .map(|&(kind, make)| {
                let c = make();
                Cone {
                    kind,
                    half_apex_deg: degrees(c.half_apex),
                    inclination_deg: degrees(c.inclination),
                }
            })
            .collect(),
        cone_offsets: [offsets.centre_offset, offsets.height_offset],
        surfaces: super::curves::SURFACES
            .iter()
            .map(|&(surface, _, cutting)| PathSurface {
                surface,
                cutting: match cutting {
                    Cutting::Down => "down-cutting",
                    Cutting::Up => "up-cutting",
                },
            })
            .collect(),
    }
}

#[derive(Serialize)]
struct Start {
    version: &'static str,
    machines: Vec<MachineInfo>,
    examples: Vec<Example>,
    /// The measurement curves in id order (the x order of every per-point plot).
    curves: Vec<&'static str>,
    words: Words,
    thresholds: Thresholds,
    /// The cones and surfaces of the curves beside Figure 19.
    paths: Paths,
}

/// The serde tag of `v`: the string it serialises to, or its `tag` field.
fn tag<T: Serialize>(v: &T, field: &str) -> String {
    match serde_json::to_value(v) {
        Ok(serde_json::Value::String(s)) => s,
        Ok(o) => o[field].as_str().unwrap_or_default().to_string(),
        Err(_) => String::new(),
    }
}

fn words_of<T: Serialize, W>(all: &[T], word: impl Fn(&T) -> W) -> BTreeMap<String, W> {
    all.iter().map(|v| (tag(v, ""), word(v))).collect()
}

fn group_word(g: &Group) -> &'static str {
    match g {
        Group::Curve { .. } => "curve",
        Group::Region { .. } => "region of the S",
        Group::Lean { .. } => "lean of the wall",
        Group::Reversal { .. } => "axis reversal",
    }
}

fn error_status_word(s: &ErrorStatus) -> &'static str {
    match s {
        ErrorStatus::Kept => "identified",
        ErrorStatus::Absorbed => "absorbed by the identified ones",
        ErrorStatus::Invisible => "invisible on a flank-milled wall",
        ErrorStatus::Index => "angular zero (not fitted)",
    }
}

fn parameter_status_word(s: &Status) -> &'static str {
    match s {
        Status::Identified => "identified",
        Status::Weak => "weak",
        Status::NotSeparable => "not separable",
    }
}

fn group_kind_word(k: &GroupKind) -> &'static str {
    match k {
        GroupKind::NotSeparable => "not separable",
        GroupKind::Weak => "weak",
    }
}

fn flag_word(f: &Flag) -> String {
    match f {
        Flag::Different => format!("different (|z| ≥ {DIFFERENT_Z})"),
        Flag::Suspect => format!("suspect ({SUSPECT_Z} ≤ |z| < {DIFFERENT_Z})"),
        Flag::Consistent => format!("consistent (|z| < {SUSPECT_Z})"),
        Flag::Undetermined => "no std to compare".into(),
    }
}

fn words() -> Words {
    let groups = [
        Group::Curve {
            curve: String::new(),
        },
        Group::Region {
            region: Region::EndStart,
        },
        Group::Lean {
            lean: Lean::Upright,
        },
        Group::Reversal {
            axis: AxisName::C,
            s: 0.0,
            nearest: 0,
            of_verdict: false,
            marked: false,
        },
    ];
    Words {
        groups: groups
            .iter()
            .map(|g| (tag(g, "group"), group_word(g)))
            .collect(),
        error_status: words_of(
            &[
                ErrorStatus::Kept,
                ErrorStatus::Absorbed,
                ErrorStatus::Invisible,
                ErrorStatus::Index,
            ],
            error_status_word,
        ),
        parameter_status: words_of(
            &[Status::Identified, Status::Weak, Status::NotSeparable],
            parameter_status_word,
        ),
        group_kind: words_of(&[GroupKind::NotSeparable, GroupKind::Weak], group_kind_word),
        // crate::effects::catalogue::EffectStatus::status
        effect_status: BTreeMap::from([
            ("offered", "offered"),
            ("invisible", "invisible"),
            ("left_out", "left out"),
        ]),
        flags: words_of(
            &[
                Flag::Different,
                Flag::Suspect,
                Flag::Consistent,
                Flag::Undetermined,
            ],
            flag_word,
        ),
    }
}

/// Two-sided tail of the standard normal law, `P(|z| ≥ z)`.
fn two_sided(z: f64) -> f64 {
    crate::numerics::stats::erfc(z / std::f64::consts::SQRT_2)
}

/// Everything the page needs when it opens: `{version, machines: [{id, name, uses_l0}],
/// examples: [{name, description, text}], curves: [name], words: {groups, error_status,
/// parameter_status, group_kind, effect_status, flags}, thresholds: {reversal_window_mm,
/// different_z, suspect_z, different_false_alarm, suspect_false_alarm}, paths: {cones: [{kind,
/// half_apex_deg, inclination_deg}], cone_offsets: [d, p] (mm), surfaces: [{surface,
/// cutting}]}}`; `machines[].id` is the value of the analysis setting `machine`, an example's
/// `text` its CMM file.
#[wasm_bindgen]
pub fn start() -> Result<JsValue, JsError> {
    let examples = EXAMPLES
        .iter()
        .map(|(name, description, _)| {
            example_text(name)
                .map(|text| Example {
                    name,
                    description,
                    text,
                })
                .ok_or_else(|| JsError::new(&format!("no built-in example named {name:?}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    super::to_js(&Start {
        version: crate::VERSION,
        machines: MachineChoice::ALL.map(MachineChoice::info).into(),
        examples,
        curves: Curve::ALL.map(Curve::name).into(),
        words: words(),
        thresholds: Thresholds {
            reversal_window_mm: REVERSAL_WINDOW_MM,
            different_z: DIFFERENT_Z,
            suspect_z: SUSPECT_Z,
            different_false_alarm: two_sided(DIFFERENT_Z),
            suspect_false_alarm: two_sided(SUSPECT_Z),
            nonzero_t: crate::identify::NONZERO_T,
        },
        paths: paths(),
    })
}
