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
//!   [`crate::sensitivity::reversal`] on the machine's own axis path ([`crate::effects::machine`]).
//! - `scale_<axis>.k`: `E_XX = k·X`, `E_YY = k·Y`, `E_ZZ = k·(Z − L0)`, the linear term of the
//!   axis's own positioning error motion ([`crate::effects::machine`]).
//! - `thermal_drift.g`: the head grows along machine Z in proportion to machining time, i.e. to
//!   the tool-tip path length `s` from the start of A (through B); a drift `g` over the whole
//!   path moves the tool by `−g·(s/s_total)·ẑ_machine` (towards the table), which in the part
//!   frame is `−g·(s/s_total)·R_W(q)ᵀẑ` (`R_W` the rotation of the workpiece-side chain at the
//!   point's axis values `q`): `−(s/s_total)·(R_W(q)ᵀẑ)·N`. Where every workpiece-side rotary
//!   axis turns about z (paper 000's C table, paper 001's X table) `R_Wᵀẑ = ẑ` and the signature
//!   is `−(s/s_total)·N_z`; on paper 002's B-C tilting table `R_Wᵀẑ` is the tool axis, which
//!   lies in the flank-milled walls: exactly zero.
//! - `setup_error.thetaz`, `.tx`, `.ty`: the measured part rotated by `θz` about Z and shifted by
//!   `t`: a point moves by `θz ẑ × p + t`, deviation `(θz ẑ × p + t)·N` with `ẑ × p = (−y, x, 0)`.
//! - `c_index.dC` and `a_index.dA`: one convention, `q_real = q_cmd + dq`. For a C axis that is
//!   the workpiece-side axis next to the part, about z through the part origin (paper 000's C
//!   table, paper 002's `C'`), `p = Rz(s_C·C)ᵀ(…)` (s-shape.md eq. 8-10, `s_C = −1` when primed)
//!   and the tool's path in the part frame turns by `−s_C·dC`: `∂p/∂C·N = −s_C·(ẑ × p)·N`, on
//!   paper 000 the negative of `setup_error.thetaz` (reference README), on paper 002 (`C'`) the
//!   same as it. Otherwise (paper 001's A axis in the head) the signature is the Jacobian of the
//!   axis's constant angular positioning error (`EAA`, `ECC`: exactly a change of the axis value)
//!   at the tool-body point at the contact point, minus the tip's at the reference pose where the
//!   part origin is set, as for the location errors in `physical` mode
//!   ([`crate::effects::machine::index_signatures`]).
//! - `pivot_length.dL0`: a real pivot-to-tip length `L0 + dL0` moves the tool by `−dL0·w` along
//!   its own axis `w`, which has no normal component on a flank-milled wall (`N·w = 0`); the part
//!   origin was set with B = 0, which removed `−dL0·ẑ`, so what shows is `+dL0·ẑ·N = dL0·N_z`.

use std::fmt;
use std::str::FromStr;

use nalgebra::Vector3;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::effects::GapError;
use crate::machine::chain::AxisKind;
use crate::machine::{AxisName, Chain};

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
    /// Every candidate, in the order of effects.md (then those added for paper 001's A-B head).
    pub const ALL: [Effect; 17] = [
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
            Effect::Backlash(a) | Effect::Scale(a) => no_axis(a),
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
            Effect::AIndex => &[("dA", "rad")],
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
            Effect::AIndex => "zero offset of the A axis",
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
            Effect::ThermalDrift => match &m.machine_z {
                None => vec![per_point(&|p| -(p.s / m.s_total) * p.n.z)],
                Some(z) => vec![m
                    .points
                    .iter()
                    .zip(z)
                    .map(|(p, z)| -(p.s / m.s_total) * z.dot(&p.n))
                    .collect()],
            },
            Effect::SetupError => vec![
                per_point(&rotation_z),
                per_point(&|p| p.n.x),
                per_point(&|p| p.n.y),
            ],
            Effect::CIndex => match m.c_table_sign {
                Some(sign) => vec![per_point(&|p| -sign * rotation_z(p))],
                None => return axis_column(&m.index, AxisName::C),
            },
            Effect::AIndex => return axis_column(&m.index, AxisName::A),
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
/// (backlash and scale, [`crate::effects::machine`]).
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
    /// Machine Z in the part frame at each point, `R_W(q)ᵀẑ` (`thermal_drift`); `None` where it
    /// is `ẑ` at every pose (every workpiece-side rotary axis turns about z).
    pub machine_z: Option<Vec<Vector3<f64>>>,
    /// `s_C` (+1, or −1 when primed) when the C axis is the workpiece-side axis next to the part,
    /// about z through the part origin: `c_index` is then the rotation `−s_C·(ẑ × p)·N`.
    pub c_table_sign: Option<f64>,
    /// `<a>_index` columns from the Jacobian of the axis's constant positioning error (mm/rad),
    /// for the index axes [`SignatureModel::c_table_sign`] does not cover.
    pub index: Vec<(AxisName, Vec<f64>)>,
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
                "a_index"
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
            c_table_sign: Some(1.0),
            ..Default::default()
        };
        let set_up = Effect::SetupError.signature(&m).unwrap();
        let c = Effect::CIndex.signature(&m).unwrap();
        // (ẑ × p)·N = −20·0.6 + 10·0.8 = −4 mm/rad.
        assert!((set_up[0][0] + 4.0).abs() < 1e-12);
        assert_eq!(c[0][0], -set_up[0][0]);
        assert!(Effect::Backlash(AxisName::X).signature(&m).is_none());
        // A primed C (paper 002's `C'`) turns the table the other way.
        let primed = SignatureModel {
            c_table_sign: Some(-1.0),
            ..m
        };
        assert_eq!(
            Effect::CIndex.signature(&primed).unwrap()[0][0],
            set_up[0][0]
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
        // Paper 000: the 15 of effects.md, in their order.
        let paper000 = Chain::paper000(499.889);
        assert_eq!(
            ids(&paper000),
            Effect::ALL[..15].iter().map(|e| e.id()).collect::<Vec<_>>()
        );
        assert!(Effect::left_out(&paper000)
            .iter()
            .all(|(e, _)| matches!(e, Effect::AIndex | Effect::Backlash(AxisName::A))));
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
        assert_eq!(&a[a.len() - 3..], ["pivot_length", "backlash_a", "a_index"]);
        assert_eq!(
            Effect::CIndex.absent_from(&paper001).unwrap(),
            "the machine has no C axis"
        );
    }
}
