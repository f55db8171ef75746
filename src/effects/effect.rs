//! The signature of each candidate effect of `shared/spec/effects.md` on a part model
//! ([`Effect::signature`]; the effect, its id and its parameters with their units are
//! [`crate::parameter::effect`]'s).
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
//! - `tool_wear.w`: the flank wears while it cuts, the effective radius shrinks along the path and
//!   material is left in proportion to the machined length: `+s/s_total` (effects.md).
//! - `servo_lag_<axis>.l` and `servo_common.L2`: the servo's following error
//!   ([`crate::sensitivity::servo`]): `−(dq_i/ds)·(d dev/dq_i)` and `(1/2)·Σ_i (d²q_i/ds²)·(d dev/dq_i)`.
//! - Families (effects.md, "Shapes are families"): `backlash_<axis>` at each lag `tau` of its grid
//!   (the reference 2 mm is the table's) and each overshoot of a servo that rings after the
//!   reversal (none, the table's, then second order, [`crate::effects::family::LagMembers`]),
//!   `thermal_drift` with the warm-up
//!   `g·(1 − exp(−s/(f·s_total)))/(1 − exp(−1/f))` at each `f` of its grid (the linear law the
//!   limit `f = ∞`, the table's), and at each pause `π` between
//!   the passes: the head keeps warming while the machine moves from A to B, so B is machined as
//!   if `π·s_total` more path had been cut before it ([`warm_up_paused`], [`warm_up_basis`]).
//! - `pivot_length.dL0`: a real pivot-to-tip length `L0 + dL0` moves the tool by `−dL0·w` along
//!   its own axis `w`, which has no normal component on a flank-milled wall (`N·w = 0`); the part
//!   origin was set with B = 0, which removed `−dL0·ẑ`, so what shows is `+dL0·ẑ·N = dL0·N_z`.

use nalgebra::Vector3;

use crate::effects::family::{LagBasis, WarmUpBasis};

use crate::machine::AxisName;
use crate::parameter::Effect;

impl Effect {
    /// The signature columns (one per parameter, one value per point, mm per unit of the
    /// parameter) on the part model `m`; the formulas are those of the module doc. `None` when
    /// the model has no column for the effect's axis.
    pub fn signature(self, m: &SignatureModel) -> Option<Vec<Vec<f64>>> {
        let per_point = |f: &dyn Fn(&EffectPoint) -> f64| m.points.iter().map(f).collect();
        Some(match self {
            Effect::ToolRadius => vec![vec![-1.0; m.points.len()]],
            Effect::ToolTaper => vec![vec![-1.0; m.points.len()], per_point(&|p| -p.h)],
            Effect::Overcut => vec![m.envelope.clone()],
            Effect::Backlash(a) => return axis_column(&m.backlash, a),
            Effect::Scale(a) => return axis_column(&m.scale, a),
            Effect::ThermalDrift => vec![thermal_column(m, f64::INFINITY)],
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
            Effect::ToolWear => vec![per_point(&|p| p.s / m.s_total)],
            Effect::ServoLag(a) => return axis_column(&m.servo, a),
            Effect::ServoCommon if m.servo_common.len() == m.points.len() => {
                vec![m.servo_common.clone()]
            }
            Effect::ServoCommon => return None,
        })
    }
}

/// The fraction of the whole drift reached at the fraction `x` of the path with the warm-up
/// constant `f` (effects.md): `(1 − exp(−x/f)) / (1 − exp(−1/f))`, `x` itself for `f = ∞`.
pub fn warm_up(x: f64, f: f64) -> f64 {
    warm_up_paused(x, false, f, 0.0)
}

/// [`warm_up`] with a pause between the passes: the head warms in machining time, and the pause
/// between A and B (`pause`, a share of the cutting path's time) counts for a point of B
/// (`second`), `x' = x + pause`; normalised to the drift at the end of B, `x' = 1 + pause`:
/// `(1 − exp(−x'/f)) / (1 − exp(−(1 + pause)/f))`, `x'/(1 + pause)` for `f = ∞`. With no pause
/// it is [`warm_up`] to the bit.
pub fn warm_up_paused(x: f64, second: bool, f: f64, pause: f64) -> f64 {
    WarmUp::new(f, pause).at(x, second)
}

/// [`warm_up_paused`] at one warm-up constant and pause, for many points: its denominator, the
/// drift at the end of B, computed once (a family's member evaluates it at every point of a
/// dense scan: one `exp_m1` a point of two, issue 31), the same bits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WarmUp {
    f: f64,
    pause: f64,
    /// `1 + pause`, where B ends.
    end: f64,
    /// `exp_m1(−end/f)` (unused for `f = ∞`).
    at_end: f64,
}

impl WarmUp {
    /// The law of warm-up constant `f` and pause `pause` (a share of the cutting path).
    pub fn new(f: f64, pause: f64) -> Self {
        let end = 1.0 + pause;
        Self {
            f,
            pause,
            end,
            at_end: (-end / f).exp_m1(),
        }
    }

    /// The share of the drift at the share `x` of the path, on B when `second`.
    pub fn at(&self, x: f64, second: bool) -> f64 {
        let x = if second { x + self.pause } else { x };
        if self.f.is_infinite() {
            x / self.end
        } else {
            (-x / self.f).exp_m1() / self.at_end
        }
    }
}

/// What every member of the warm-up family is made of ([`WarmUpBasis`]): `x = s/s_total`, the
/// point's pass, and `z = (R_W(q)ᵀẑ)·N` (`N_z` where every workpiece-side rotary axis turns
/// about z).
pub fn warm_up_basis(m: &SignatureModel) -> WarmUpBasis {
    let z: Vec<f64> = match &m.machine_z {
        None => m.points.iter().map(|p| p.n.z).collect(),
        Some(z) => m.points.iter().zip(z).map(|(p, z)| z.dot(&p.n)).collect(),
    };
    WarmUpBasis {
        x: m.points.iter().map(|p| p.s / m.s_total).collect(),
        second: m.points.iter().map(|p| p.second).collect(),
        z,
    }
}

/// `thermal_drift.g` with the warm-up constant `f`: `−warm_up(s/s_total, f)·(R_W(q)ᵀẑ)·N`
/// (module doc; `f = ∞` the linear law of the table).
fn thermal_column(m: &SignatureModel, f: f64) -> Vec<f64> {
    warm_up_basis(m).column(f, 0.0)
}

/// The column of axis `a` among per-axis columns, as a one-column signature (`None` when the
/// model has no column for that axis).
fn axis_column(cols: &[(AxisName, Vec<f64>)], a: AxisName) -> Option<Vec<Vec<f64>>> {
    cols.iter()
        .find(|(b, _)| *b == a)
        .map(|(_, c)| vec![c.clone()])
}

/// `(ẑ × p)·N` per rad: the deviation of a rotation of the part about Z.
fn rotation_z(p: &EffectPoint) -> f64 {
    -p.p.y * p.n.x + p.p.x * p.n.y
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
    /// On the second pass (B), machined after the pause between the passes.
    pub second: bool,
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
    /// What the members of the backlash families are computed from ([`Effect::shape`],
    /// [`Effect::profiled`]); `None` without the kinematics stage.
    pub backlash_family: Option<LagBasis>,
    /// `servo_lag_<axis>.l` column per axis of the chain (mm per mm of path,
    /// [`crate::sensitivity::servo`]).
    pub servo: Vec<(AxisName, Vec<f64>)>,
    /// `servo_common.L2` column (mm per mm²).
    pub servo_common: Vec<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c_index_is_the_negative_of_the_set_up_rotation() {
        let m = SignatureModel {
            points: vec![EffectPoint {
                p: Vector3::new(10.0, 20.0, 5.0),
                n: Vector3::new(0.6, 0.8, 0.0),
                h: 3.0,
                s: 50.0,
                second: false,
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
}
