//! The candidate effects of `shared/spec/effects.md` as one type: each [`Effect`] owns its id
//! (fixed: files, the CLI's JSON and the page use it as written), its parameters with their
//! units, its plain name and its signature on a part model ([`Effect::signature`]).
//!
//! Signatures are per unit of each parameter, in `physical` mode (deviation =
//! `(machined − nominal)·N`, + = material left, − = overcut), at the measured points:
//! - `tool_radius.dR`: a tool of radius `10 + dR` cuts `dR` deeper along the normal: `−1`
//!   (s-shape.md).
//! - `tool_taper.dR0`, `.g`: the radius at height `h` above the tip is `10 + dR0 + g·h`
//!   (paper 001 Table 2 for the rotation profile): `−1` and `−h`, so the Z11 (h ≈ 15.5) and Z25
//!   (h ≈ 30) curves differ by `−g·14.5`.
//! - `overcut.k`: `k ×` the exact envelope deviation of the flank path at the points (paper 000
//!   §3, [`crate::toolpath::envelope`]); `k = 1` is the exact envelope.
//! - `backlash_<axis>.b`: the first-order-lag reversal model of
//!   [`crate::sensitivity::reversal`] on the machine's own axis path ([`super::effects::machine`]).
//! - `scale_<axis>.k`: `E_XX = k·X`, `E_YY = k·Y`, `E_ZZ = k·(Z − L0)`, the linear term of the
//!   axis's own positioning error motion ([`super::effects::machine`]).
//! - `thermal_drift.g`: the head grows along machine Z in proportion to machining time, i.e. to
//!   the tool-tip path length `s` from the start of A (through B); a drift `g` over the whole
//!   path moves the tool by `−g·(s/s_total)·ẑ` (towards the table): `−(s/s_total)·N_z`.
//! - `setup_error.thetaz`, `.tx`, `.ty`: the measured part rotated by `θz` about Z and shifted by
//!   `t`: a point moves by `θz ẑ × p + t`, deviation `(θz ẑ × p + t)·N` with `ẑ × p = (−y, x, 0)`.
//! - `c_index.dC`: a C-axis offset `dC` (`C_real = C_cmd + dC`) turns the table, and the part, by
//!   `dC` about the C axis; with `p = Rz(C)ᵀ(…)` (s-shape.md eq. 8-10) the tool's path in the part
//!   frame turns by `−dC`: `∂p/∂C·N = −(ẑ × p)·N`, the negative of `setup_error.thetaz`
//!   (reference README).
//! - `pivot_length.dL0`: a real pivot-to-tip length `L0 + dL0` moves the tool by `−dL0·w` along
//!   its own axis `w`, which has no normal component on a flank-milled wall (`N·w = 0`); the part
//!   origin was set with B = 0, which removed `−dL0·ẑ`, so what shows is `+dL0·ẑ·N = dL0·N_z`.

use std::fmt;
use std::str::FromStr;

use nalgebra::Vector3;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::GapError;
use crate::machine::chain::AxisKind;
use crate::machine::AxisName;

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
}

/// Axes of the backlash candidates, in effects.md order.
pub const BACKLASH_AXES: [AxisName; 5] = [
    AxisName::X,
    AxisName::Y,
    AxisName::Z,
    AxisName::B,
    AxisName::C,
];
/// Axes of the scale candidates, in effects.md order.
pub const SCALE_AXES: [AxisName; 3] = [AxisName::X, AxisName::Y, AxisName::Z];

impl Effect {
    /// Every candidate, in the order of effects.md.
    pub const ALL: [Effect; 15] = [
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
    ];

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
        }
    }

    /// The effect of an effects.md id.
    pub fn from_id(id: &str) -> Option<Effect> {
        Effect::ALL.into_iter().find(|e| e.id() == id)
    }

    /// Parameter names and units, in the order of the signature columns.
    pub fn parameters(self) -> &'static [(&'static str, &'static str)] {
        match self {
            Effect::ToolRadius => &[("dR", "mm")],
            Effect::ToolTaper => &[("dR0", "mm"), ("g", "mm/mm")],
            Effect::Overcut => &[("k", "1")],
            Effect::Backlash(a) if a.kind() == AxisKind::Rotary => &[("b", "rad")],
            Effect::Backlash(_) => &[("b", "mm")],
            Effect::ThermalDrift => &[("g", "mm")],
            Effect::SetupError => &[("thetaz", "rad"), ("tx", "mm"), ("ty", "mm")],
            Effect::Scale(_) => &[("k", "mm/mm")],
            Effect::CIndex => &[("dC", "rad")],
            Effect::PivotLength => &[("dL0", "mm")],
        }
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
        }
    }

    /// The effect and the index of its parameter written `key`: `<id>` for a one-parameter
    /// effect (`backlash_c`), `<id>.<parameter>` for any (`tool_taper.g`).
    pub fn parse_parameter(key: &str) -> Result<(Effect, usize), GapError> {
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
            None => Err(GapError::ParameterNeeded {
                key: key.to_string(),
                effect,
                known: known(),
            }),
            Some(name) => params
                .iter()
                .position(|(n, _)| *n == name)
                .map(|j| (effect, j))
                .ok_or_else(|| GapError::UnknownParameter {
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
            Effect::Backlash(a) | Effect::Scale(a) => Some(a),
            _ => None,
        }
    }

    /// The signature columns (one per parameter, one value per point, mm per unit of the
    /// parameter) on the part model `m`; the formulas are those of the module doc. `None` when
    /// the model has no column for the effect's axis.
    pub fn signature(self, m: &SignatureModel) -> Option<Vec<Vec<f64>>> {
        let per_point = |f: &dyn Fn(&EffectPoint) -> f64| m.points.iter().map(f).collect();
        let axis_column = |cols: &[(AxisName, Vec<f64>)], a: AxisName| {
            cols.iter()
                .find(|(b, _)| *b == a)
                .map(|(_, c)| vec![c.clone()])
        };
        Some(match self {
            Effect::ToolRadius => vec![vec![-1.0; m.points.len()]],
            Effect::ToolTaper => vec![vec![-1.0; m.points.len()], per_point(&|p| -p.h)],
            Effect::Overcut => vec![m.envelope.clone()],
            Effect::Backlash(a) => return axis_column(&m.backlash, a),
            Effect::Scale(a) => return axis_column(&m.scale, a),
            Effect::ThermalDrift => vec![per_point(&|p| -(p.s / m.s_total) * p.n.z)],
            Effect::SetupError => vec![
                per_point(&rotation_z),
                per_point(&|p| p.n.x),
                per_point(&|p| p.n.y),
            ],
            Effect::CIndex => vec![per_point(&|p| -rotation_z(p))],
            Effect::PivotLength => vec![per_point(&|p| p.n.z)],
        })
    }
}

/// `(ẑ × p)·N` per rad: the deviation of a rotation of the part about Z.
fn rotation_z(p: &EffectPoint) -> f64 {
    -p.p.y * p.n.x + p.p.x * p.n.y
}

impl fmt::Display for Effect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.id())
    }
}

impl FromStr for Effect {
    type Err = GapError;
    fn from_str(s: &str) -> Result<Self, GapError> {
        Effect::from_id(s).ok_or_else(|| GapError::UnknownEffect(s.to_string()))
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

/// What an effect's signature needs to know about a measured point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EffectPoint {
    /// Nominal point (mm, part frame).
    pub p: Vector3<f64>,
    /// Outward unit normal.
    pub n: Vector3<f64>,
    /// Contact height above the tool tip (mm).
    pub h: f64,
    /// Tool-tip path length from the start of A (mm).
    pub s: f64,
}

/// The part model the signatures are read from: the points, the exact envelope deviation at
/// them, the total path length, and the per-axis columns the kinematics stage computes
/// (backlash and scale, [`super::effects::machine`]).
#[derive(Debug, Clone, Default)]
pub struct SignatureModel {
    pub points: Vec<EffectPoint>,
    /// Envelope deviation of the flank path at each point (mm).
    pub envelope: Vec<f64>,
    /// Tool-tip path length of A then B (mm).
    pub s_total: f64,
    /// `backlash_<axis>.b` column per axis (mm per mm or rad).
    pub backlash: Vec<(AxisName, Vec<f64>)>,
    /// `scale_<axis>.k` column per axis (mm per mm/mm).
    pub scale: Vec<(AxisName, Vec<f64>)>,
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
                "pivot_length"
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
        assert_eq!(Effect::Backlash(AxisName::C).parameters(), &[("b", "rad")]);
        assert_eq!(Effect::Backlash(AxisName::Y).parameters(), &[("b", "mm")]);
    }

    #[test]
    fn c_index_is_the_negative_of_the_set_up_rotation() {
        let m = SignatureModel {
            points: vec![EffectPoint {
                p: Vector3::new(10.0, 20.0, 5.0),
                n: Vector3::new(0.6, 0.8, 0.0),
                h: 3.0,
                s: 50.0,
            }],
            envelope: vec![0.0],
            s_total: 100.0,
            ..Default::default()
        };
        let set_up = Effect::SetupError.signature(&m).unwrap();
        let c = Effect::CIndex.signature(&m).unwrap();
        // (ẑ × p)·N = −20·0.6 + 10·0.8 = −4 mm/rad.
        assert!((set_up[0][0] + 4.0).abs() < 1e-12);
        assert_eq!(c[0][0], -set_up[0][0]);
        assert!(Effect::Backlash(AxisName::X).signature(&m).is_none());
    }
}
