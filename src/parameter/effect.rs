//! The candidate effects of `shared/spec/effects.md` by id: each [`Effect`] owns its id (fixed:
//! files, the CLI's JSON and the page use it as written), its parameters with their units (set
//! here, where they are defined: the unit of an effect's parameter is never read from its name),
//! its plain name, and the machines whose physics has it ([`Effect::on_chain`]). Its signature on
//! a part model is the effects stage's ([`crate::effects::effect`]).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::machine::chain::AxisKind;
use crate::machine::{AxisName, Chain, Unit};

use super::{ParamId, ParameterError};

/// One candidate unmodelled effect of effects.md.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Effect {
    /// `tool_radius`: tool radius error `dR` (mm).
    ToolRadius,
    /// `tool_taper`: radius varying along the tool axis, `dR0` (mm) and `g` (mm/mm).
    ToolTaper,
    /// `overcut`: flank-milling overcut of the ruled surface, `k` (1).
    Overcut,
    /// `backlash_<axis>`: lost motion `b` at the reversals of a linear (mm) or rotary (rad) axis.
    Backlash(AxisName),
    /// `thermal_drift`: growth `g` (mm) of the head along Z over the whole path.
    ThermalDrift,
    /// `setup_error`: datum alignment, `thetaz` (rad), `tx`, `ty` (mm).
    SetupError,
    /// `scale_<axis>`: linear scale error `k` (mm/mm) of a linear axis.
    Scale(AxisName),
    /// `c_index`: zero offset `dC` (rad) of the C axis.
    CIndex,
    /// `pivot_length`: pivot-to-tip length error `dL0` (mm).
    PivotLength,
    /// `a_index`: zero offset `dA` (rad) of the A axis.
    AIndex,
    /// `tool_wear`: material left in proportion to the machined length, `w` (mm) at the end.
    ToolWear,
    /// `servo_lag_<axis>`: the axis trailing the others by `l` (mm of tool-tip path).
    ServoLag(AxisName),
    /// `servo_common`: the rounding of the path by the lag `L` all axes share, per `L²` (mm²).
    ServoCommon,
}

/// Axes of the backlash candidates, in effects.md order (then A, added for paper 001's A-B head).
pub const BACKLASH_AXES: [AxisName; 6] = [
    AxisName::X,
    AxisName::Y,
    AxisName::Z,
    AxisName::B,
    AxisName::C,
    AxisName::A,
];

/// The axes of [`BACKLASH_AXES`] that `chain` has, in that order (paper 000 and 002: X, Y, Z, B,
/// C; paper 001: X, Y, Z, B, A).
pub fn backlash_axes(chain: &Chain) -> Vec<AxisName> {
    BACKLASH_AXES
        .into_iter()
        .filter(|&a| chain.axis(a).is_some())
        .collect()
}
/// Axes of the scale candidates, in effects.md order.
pub const SCALE_AXES: [AxisName; 3] = [AxisName::X, AxisName::Y, AxisName::Z];

impl Effect {
    /// Every candidate, in the order of effects.md's table (then those added for paper 001's A-B
    /// head, then the families of its "Shapes are families").
    pub const ALL: [Effect; 25] = [
        Effect::ToolRadius,
        Effect::ToolTaper,
        Effect::Overcut,
        Effect::Backlash(AxisName::X),
        Effect::Backlash(AxisName::Y),
        Effect::Backlash(AxisName::Z),
        Effect::Backlash(AxisName::B),
        Effect::Backlash(AxisName::C),
        Effect::ThermalDrift,
        Effect::SetupError,
        Effect::Scale(AxisName::X),
        Effect::Scale(AxisName::Y),
        Effect::Scale(AxisName::Z),
        Effect::CIndex,
        Effect::PivotLength,
        Effect::Backlash(AxisName::A),
        Effect::AIndex,
        Effect::ToolWear,
        Effect::ServoLag(AxisName::X),
        Effect::ServoLag(AxisName::Y),
        Effect::ServoLag(AxisName::Z),
        Effect::ServoLag(AxisName::B),
        Effect::ServoLag(AxisName::C),
        Effect::ServoLag(AxisName::A),
        Effect::ServoCommon,
    ];

    /// The candidates whose physics exists on `chain`, in the order of [`Effect::ALL`] (paper
    /// 000: the 15 of effects.md; paper 002: without `pivot_length`; paper 001: without
    /// `backlash_c` and `c_index`, with `backlash_a` and `a_index`).
    pub fn on_chain(chain: &Chain) -> Vec<Effect> {
        Effect::ALL
            .into_iter()
            .filter(|e| e.absent_from(chain).is_none())
            .collect()
    }

    /// The candidates [`Effect::on_chain`] leaves out, each with the reason.
    pub fn left_out(chain: &Chain) -> Vec<(Effect, String)> {
        Effect::ALL
            .into_iter()
            .filter_map(|e| e.absent_from(chain).map(|why| (e, why)))
            .collect()
    }

    /// Why the effect's physics does not exist on `chain` (`None`: it does): an axis the chain
    /// does not have, or no pivot (no rotary axis on the tool side) for `pivot_length`.
    pub fn absent_from(self, chain: &Chain) -> Option<String> {
        let no_axis = |a: AxisName| {
            chain
                .axis(a)
                .is_none()
                .then(|| format!("the machine has no {a} axis"))
        };
        match self {
            Effect::Backlash(a) | Effect::Scale(a) | Effect::ServoLag(a) => no_axis(a),
            Effect::CIndex => no_axis(AxisName::C),
            Effect::AIndex => no_axis(AxisName::A),
            Effect::PivotLength => (!chain
                .tool_axes()
                .iter()
                .any(|a| a.name.kind() == AxisKind::Rotary))
            .then(|| "no rotary axis on the tool side, the tool has no pivot".to_string()),
            _ => None,
        }
    }

    /// The id of effects.md (`tool_radius`, `backlash_c`, …).
    pub fn id(self) -> &'static str {
        use AxisName as A;
        match self {
            Effect::ToolRadius => "tool_radius",
            Effect::ToolTaper => "tool_taper",
            Effect::Overcut => "overcut",
            Effect::Backlash(A::X) => "backlash_x",
            Effect::Backlash(A::Y) => "backlash_y",
            Effect::Backlash(A::Z) => "backlash_z",
            Effect::Backlash(A::A) => "backlash_a",
            Effect::Backlash(A::B) => "backlash_b",
            Effect::Backlash(A::C) => "backlash_c",
            Effect::ThermalDrift => "thermal_drift",
            Effect::SetupError => "setup_error",
            Effect::Scale(A::X) => "scale_x",
            Effect::Scale(A::Y) => "scale_y",
            Effect::Scale(A::Z) => "scale_z",
            Effect::Scale(A::A) => "scale_a",
            Effect::Scale(A::B) => "scale_b",
            Effect::Scale(A::C) => "scale_c",
            Effect::CIndex => "c_index",
            Effect::PivotLength => "pivot_length",
            Effect::AIndex => "a_index",
            Effect::ToolWear => "tool_wear",
            Effect::ServoLag(A::X) => "servo_lag_x",
            Effect::ServoLag(A::Y) => "servo_lag_y",
            Effect::ServoLag(A::Z) => "servo_lag_z",
            Effect::ServoLag(A::A) => "servo_lag_a",
            Effect::ServoLag(A::B) => "servo_lag_b",
            Effect::ServoLag(A::C) => "servo_lag_c",
            Effect::ServoCommon => "servo_common",
        }
    }

    /// The effect of an effects.md id.
    pub fn from_id(id: &str) -> Option<Effect> {
        Effect::ALL.into_iter().find(|e| e.id() == id)
    }

    /// Parameter names and units (effects.md's table), in the order of the signature columns.
    pub fn parameters(self) -> &'static [(&'static str, Unit)] {
        const MM_PER_MM: Unit = Unit::Per {
            of: AxisKind::Linear,
            per: AxisKind::Linear,
            power: 1,
        };
        match self {
            Effect::ToolRadius => &[("dR", Unit::Mm)],
            Effect::ToolTaper => &[("dR0", Unit::Mm), ("g", MM_PER_MM)],
            Effect::Overcut => &[("k", Unit::One)],
            Effect::Backlash(a) if a.kind() == AxisKind::Rotary => &[("b", Unit::Rad)],
            Effect::Backlash(_) => &[("b", Unit::Mm)],
            Effect::ThermalDrift => &[("g", Unit::Mm)],
            Effect::SetupError => &[("thetaz", Unit::Rad), ("tx", Unit::Mm), ("ty", Unit::Mm)],
            Effect::Scale(_) => &[("k", MM_PER_MM)],
            Effect::CIndex => &[("dC", Unit::Rad)],
            Effect::PivotLength => &[("dL0", Unit::Mm)],
            Effect::AIndex => &[("dA", Unit::Rad)],
            Effect::ToolWear => &[("w", Unit::Mm)],
            Effect::ServoLag(_) => &[("l", Unit::Mm)],
            Effect::ServoCommon => &[("L2", Unit::Mm2)],
        }
    }

    /// Its parameters' ids (kind, name and unit), in column order.
    pub fn parameter_ids(self) -> Vec<ParamId> {
        (0..self.parameters().len())
            .map(|index| ParamId::Effect {
                effect: self,
                index,
            })
            .collect()
    }

    /// The parameter names, in column order.
    pub fn parameter_names(self) -> Vec<String> {
        self.parameters()
            .iter()
            .map(|(n, _)| n.to_string())
            .collect()
    }

    /// A plain-language name for reports.
    pub fn plain_name(self) -> &'static str {
        use AxisName as A;
        match self {
            Effect::ToolRadius => "tool radius error",
            Effect::ToolTaper => "tool radius varying along the tool axis (taper)",
            Effect::Overcut => "flank-milling overcut of the ruled surface",
            Effect::Backlash(A::X) => "backlash of the X axis",
            Effect::Backlash(A::Y) => "backlash of the Y axis",
            Effect::Backlash(A::Z) => "backlash of the Z axis",
            Effect::Backlash(A::A) => "backlash of the A axis",
            Effect::Backlash(A::B) => "backlash of the B axis",
            Effect::Backlash(A::C) => "backlash of the C axis",
            Effect::ThermalDrift => "thermal growth of the head along Z",
            Effect::SetupError => "part set-up (datum alignment) error",
            Effect::Scale(A::X) => "linear scale error of the X axis",
            Effect::Scale(A::Y) => "linear scale error of the Y axis",
            Effect::Scale(A::Z) => "linear scale error of the Z axis",
            Effect::Scale(A::A) => "scale error of the A axis",
            Effect::Scale(A::B) => "scale error of the B axis",
            Effect::Scale(A::C) => "scale error of the C axis",
            Effect::CIndex => "zero offset of the C axis",
            Effect::PivotLength => "pivot-to-tip length error",
            Effect::AIndex => "zero offset of the A axis",
            Effect::ToolWear => "tool wear along the machined length",
            Effect::ServoLag(A::X) => "X axis's servo trailing the others",
            Effect::ServoLag(A::Y) => "Y axis's servo trailing the others",
            Effect::ServoLag(A::Z) => "Z axis's servo trailing the others",
            Effect::ServoLag(A::A) => "A axis's servo trailing the others",
            Effect::ServoLag(A::B) => "B axis's servo trailing the others",
            Effect::ServoLag(A::C) => "C axis's servo trailing the others",
            Effect::ServoCommon => "rounding of the path by the servo lag all axes share",
        }
    }

    /// The effect and the index of its parameter written `key`: `<id>` for a one-parameter
    /// effect (`backlash_c`), `<id>.<parameter>` for any (`tool_taper.g`).
    pub fn parse_parameter(key: &str) -> Result<(Effect, usize), ParameterError> {
        let (id, name) = match key.split_once('.') {
            Some((id, name)) => (id, Some(name)),
            None => (key, None),
        };
        let effect: Effect = id.parse()?;
        let params = effect.parameters();
        let known = || {
            params
                .iter()
                .map(|(n, u)| format!("{n} ({u})"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        match name {
            None if params.len() == 1 => Ok((effect, 0)),
            None => Err(ParameterError::ParameterNeeded {
                key: key.to_string(),
                effect,
                known: known(),
            }),
            Some(name) => params
                .iter()
                .position(|(n, _)| *n == name)
                .map(|j| (effect, j))
                .ok_or_else(|| ParameterError::UnknownParameter {
                    key: key.to_string(),
                    effect,
                    name: name.to_string(),
                    known: known(),
                }),
        }
    }

    /// The machine axis the effect belongs to (backlash and scale), if any.
    pub fn axis(self) -> Option<AxisName> {
        match self {
            Effect::Backlash(a) | Effect::Scale(a) | Effect::ServoLag(a) => Some(a),
            _ => None,
        }
    }
}

/// The shape parameter of an effect's family (effects.md, "Shapes are families"): not a column
/// of the signature (the amplitude is, linearly), but fitted by a one-dimensional search over
/// `grid` (variable projection); the table's signature is the one at `reference`.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// `tau` (backlash: the lag, mm of tool-tip path) or `f` (thermal drift: the warm-up constant
    /// as a fraction of the machining time; `inf` is the linear law).
    pub name: &'static str,
    pub unit: Unit,
    /// The value of the reference signatures (`effect_signatures.csv`): 2 mm, and the linear law.
    pub reference: f64,
    /// The values searched, increasing (the reference among them).
    pub grid: Vec<f64>,
}

/// The backlash's lag of the reference signatures (effects.md's table, `effect_signatures.csv`):
/// 2 mm of tool-tip path.
pub const REFERENCE_LAG: f64 = 2.0;

/// Ratio of consecutive lags of the backlash family's grid: 2·1.3^k mm, k = −9..8, 0.19-16.3 mm
/// (effects.md: 0.2-15 mm on real machines). The signature changes by a few percent between
/// neighbours, below what a part can tell.
pub const LAG_GRID_RATIO: f64 = 1.3;

/// Warm-up constants of the thermal family's grid (fractions of the machining time), and the
/// linear law (`inf`): from a head that is warm after 4 % of the path to the linear limit.
pub const WARM_UP_GRID: [f64; 12] = [
    0.04,
    0.06,
    0.09,
    0.13,
    0.2,
    0.3,
    0.45,
    0.7,
    1.0,
    1.5,
    2.2,
    f64::INFINITY,
];

/// Pauses between the passes of the warm-up family's grid (a share of the cutting path's
/// time): the machine retracts from A, moves and approaches B while the head keeps warming,
/// seconds to a minute against the ~1 minute of cutting of the ISO part at 1000-2000 mm/min.
/// The first is none (the table's shape).
pub const PAUSE_GRID: [f64; 6] = [0.0, 0.1, 0.2, 0.35, 0.55, 0.8];

/// Overshoots of the backlash family's second parameter (a share of the lost motion): how far
/// past its new side the slide swings after a reversal when the axis's servo rings (a velocity
/// loop of damping `ζ < 1` behind the play; paper 002 Fig. 16 with a second-order servo). The
/// first is none, the first-order lag (the table's shape); the others are `ζ` 0.52 and 0.28
/// ([`damping_of_overshoot`]), a velocity loop tuned stiff and one tuned soft. Three values, not
/// five (ζ 0.69-0.25 by 0.05, 0.15, 0.3, 0.45): the same parts named on the development seeds
/// 1-6, at 60 % of the cost (the members are computed for every backlash candidate: a
/// 20,000-point scan 1.74 → 1.37 s CPU).
pub const OVERSHOOT_GRID: [f64; 3] = [0.0, 0.15, 0.4];

/// The damping `ζ` of a second-order response whose step overshoots by `overshoot` (a share of
/// the step), `ζ = −ln M/√(π² + ln² M)`; `None` for no overshoot (the family's first order).
pub fn damping_of_overshoot(overshoot: f64) -> Option<f64> {
    (overshoot > 0.0).then(|| {
        let l = overshoot.ln();
        -l / (std::f64::consts::PI * std::f64::consts::PI + l * l).sqrt()
    })
}

impl Effect {
    /// The second shape parameter of the family that the fit profiles out (the warm-up's pause
    /// between the passes, [`PAUSE_GRID`]; a backlash's overshoot, [`OVERSHOOT_GRID`]), `None`
    /// for the other effects.
    pub fn profiled(self) -> Option<Shape> {
        match self {
            Effect::Backlash(_) => Some(Shape {
                name: "overshoot",
                unit: Unit::One,
                reference: 0.0,
                grid: OVERSHOOT_GRID.to_vec(),
            }),
            Effect::ThermalDrift => Some(Shape {
                name: "pause",
                unit: Unit::One,
                reference: 0.0,
                grid: PAUSE_GRID.to_vec(),
            }),
            _ => None,
        }
    }

    /// The shape parameter of the effect's family, `None` for an effect of one shape.
    pub fn shape(self) -> Option<Shape> {
        match self {
            Effect::Backlash(_) => Some(Shape {
                name: "tau",
                unit: Unit::Mm,
                reference: REFERENCE_LAG,
                grid: (-9..=8)
                    .map(|k| REFERENCE_LAG * LAG_GRID_RATIO.powi(k))
                    .collect(),
            }),
            Effect::ThermalDrift => Some(Shape {
                name: "f",
                unit: Unit::One,
                reference: f64::INFINITY,
                grid: WARM_UP_GRID.to_vec(),
            }),
            _ => None,
        }
    }
}

impl fmt::Display for Effect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.id())
    }
}

impl FromStr for Effect {
    type Err = ParameterError;
    fn from_str(s: &str) -> Result<Self, ParameterError> {
        Effect::from_id(s).ok_or_else(|| ParameterError::UnknownEffect(s.to_string()))
    }
}

/// Serialised as its id (`"backlash_c"`).
impl Serialize for Effect {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.id())
    }
}

impl<'de> Deserialize<'de> for Effect {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_round_trip_and_follow_effects_md() {
        let ids: Vec<&str> = Effect::ALL.iter().map(|e| e.id()).collect();
        assert_eq!(
            ids,
            [
                "tool_radius",
                "tool_taper",
                "overcut",
                "backlash_x",
                "backlash_y",
                "backlash_z",
                "backlash_b",
                "backlash_c",
                "thermal_drift",
                "setup_error",
                "scale_x",
                "scale_y",
                "scale_z",
                "c_index",
                "pivot_length",
                "backlash_a",
                "a_index",
                "tool_wear",
                "servo_lag_x",
                "servo_lag_y",
                "servo_lag_z",
                "servo_lag_b",
                "servo_lag_c",
                "servo_lag_a",
                "servo_common"
            ]
        );
        for e in Effect::ALL {
            assert_eq!(e.id().parse::<Effect>().unwrap(), e);
            assert_eq!(
                serde_json::to_string(&e).unwrap(),
                format!("\"{}\"", e.id())
            );
        }
        assert!("reversal_x".parse::<Effect>().is_err());
    }

    #[test]
    fn parameters_are_named_by_id_or_id_dot_name() {
        assert_eq!(
            Effect::parse_parameter("backlash_c").unwrap(),
            (Effect::Backlash(AxisName::C), 0)
        );
        assert_eq!(
            Effect::parse_parameter("tool_taper.g").unwrap(),
            (Effect::ToolTaper, 1)
        );
        assert_eq!(
            Effect::parse_parameter("setup_error").unwrap_err().to_string(),
            "`setup_error`: `setup_error` has the parameters thetaz (rad), tx (mm), ty (mm); write `setup_error.<parameter>`"
        );
        assert_eq!(
            Effect::parse_parameter("tool_taper.h").unwrap_err().to_string(),
            "`tool_taper.h`: `tool_taper` has no parameter `h` (its parameters: dR0 (mm), g (mm/mm))"
        );
    }

    #[test]
    fn units_follow_the_axis_kind() {
        assert_eq!(
            Effect::Backlash(AxisName::C).parameters(),
            &[("b", Unit::Rad)]
        );
        assert_eq!(
            Effect::Backlash(AxisName::Y).parameters(),
            &[("b", Unit::Mm)]
        );
        assert_eq!(
            Effect::Scale(AxisName::Y).parameters()[0].1.to_string(),
            "mm/mm"
        );
    }

    #[test]
    fn each_machine_is_offered_the_effects_whose_physics_it_has() {
        let ids = |c: &Chain| {
            Effect::on_chain(c)
                .iter()
                .map(|e| e.id())
                .collect::<Vec<_>>()
        };
        // Paper 000: the 15 of effects.md's table, in their order, then the families of its
        // "Shapes are families" (tool wear, the servo of each of its five axes, the common lag).
        let paper000 = Chain::paper000(499.889);
        let mut want: Vec<&str> = Effect::ALL[..15].iter().map(|e| e.id()).collect();
        want.extend([
            "tool_wear",
            "servo_lag_x",
            "servo_lag_y",
            "servo_lag_z",
            "servo_lag_b",
            "servo_lag_c",
            "servo_common",
        ]);
        assert_eq!(ids(&paper000), want);
        assert!(Effect::left_out(&paper000).iter().all(|(e, _)| matches!(
            e,
            Effect::AIndex | Effect::Backlash(AxisName::A) | Effect::ServoLag(AxisName::A)
        )));
        // Paper 002's tilting table has no pivot: its B axis's height is the location error EZ0B.
        let paper002 = Chain::paper002();
        assert!(!ids(&paper002).contains(&"pivot_length"));
        assert!(ids(&paper002).contains(&"c_index"));
        let why = Effect::PivotLength.absent_from(&paper002).unwrap();
        assert_eq!(
            why,
            "no rotary axis on the tool side, the tool has no pivot"
        );
        // Paper 001's A-B head: no C, an A.
        let paper001 = Chain::paper001(499.889, 0.0);
        let a = ids(&paper001);
        assert!(!a.contains(&"c_index") && !a.contains(&"backlash_c"));
        assert_eq!(
            &a[a.len() - 10..],
            [
                "pivot_length",
                "backlash_a",
                "a_index",
                "tool_wear",
                "servo_lag_x",
                "servo_lag_y",
                "servo_lag_z",
                "servo_lag_b",
                "servo_lag_a",
                "servo_common"
            ]
        );
        assert_eq!(
            Effect::CIndex.absent_from(&paper001).unwrap(),
            "the machine has no C axis"
        );
    }
}
