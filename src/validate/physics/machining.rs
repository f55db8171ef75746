//! One part machined: the commanded passes ([`super::command`]) made real by the machine's axes
//! ([`super::servo`], [`super::backlash`]), carried through the exact kinematic chain with the
//! machine's errors ([`crate::machine::direct::tool_point`], paper 000 eq. 11-12, and
//! [`super::motion`]), the tool's own shape and wear, and the heat of the head; the surface left is
//! the envelope of the tool bodies at the actual poses ([`super::envelope`]).
//!
//! At sample `k` of a pass (path length `s_k`, machining time `t_k = S_k/F` with `S_k` the path
//! from the start of A, through B, plus the pause between the passes):
//! 1. the command `q_c(s_k)`; each axis's position loop follows it in time (`Δt = step/F`), or
//!    the axis is where it is commanded;
//! 2. the lost motion of one axis is added to it (`q + e`, the play taken up by the servo);
//! 3. the C axis's zero offset `dC`: `C = C_cmd + dC`;
//! 4. the tool pose (tip `h = 0` and axis) of the chain whose pivot-to-tip length is `L0 + dL0`,
//!    with the location errors, the error motions at that pose, and the warm-up growth of the head
//!    as an error motion of Z (`E_ZZ = −δ(t)`: the tool moves down, towards the table);
//! 5. the origin: the part origin was set by touching the tip at the reference pose
//!    `(X, Y, Z, B, C) = (0, 0, L0, 0, 0)` before machining, where the static errors (location
//!    errors, error motions, `dL0`) displaced it by `Δ_ref`; every tip is taken relative to it
//!    (`tip − Δ_ref`), as s-shape.md's `physical` mode does;
//! 6. the tool body: radius `10 + dR + g·h − w(S_k)` at height `h` above the tip (a radius error,
//!    a taper, the flank's wear along the path).
//!
//! The deviation at a point is the envelope of those tools along its normal line minus that of
//! the commanded tools (the flank path's own overcut, which the CAM knows: the `overcut` candidate
//! of effects.md), unless the part keeps it ([`Machining::keep_overcut`]). With nothing but the
//! command every deviation is exactly 0 (the same tools, the same arithmetic).

use nalgebra::Vector3;

use crate::machine::direct::{nominal, tool_point};
use crate::machine::inverse::inverse;
use crate::machine::{AxisName, AxisValues, Branch, Chain, ErrorParam, MachineErrors};
use crate::part::{MeasurementPoint, SShape, Surface};
use crate::toolpath::flank::{ToolPose, TOOL_RADIUS};

use super::backlash::LostMotion;
use super::command::CommandedPass;
use super::envelope::{deviation_at, PassTools};
use super::motion::{error_params, PositionError};
use super::servo::AxisLoop;
use super::PhysicsError;

/// The axes of paper 000's machine, in the order of the loops' array.
pub const AXES: [AxisName; 5] = [
    AxisName::X,
    AxisName::Y,
    AxisName::Z,
    AxisName::B,
    AxisName::C,
];

/// Default feed (mm/min) when a part's physics does not set one.
pub const DEFAULT_FEED: f64 = 1500.0;

/// The warm-up of the head: it grows along machine Z towards a steady state,
/// `δ(t) = growth·(1 − exp(−t/T))`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Warmup {
    /// Steady-state growth (mm; + moves the tool towards the table).
    pub growth: f64,
    /// Time constant `T` (min).
    pub minutes: f64,
    /// Pause between the end of A and the start of B (s), the head still warming.
    pub pause_s: f64,
}

/// The wear of the flank along the machined length: the radius shrinks by
/// `w(S) = wear·(β(1 − exp(−S/S₀)) + (1 − β)·S/S_tot) / (β(1 − exp(−S_tot/S₀)) + 1 − β)`
/// (a break-in share `β` over `S₀` mm, then steady wear; `wear` is the total at the end of B).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Wear {
    /// Radius lost by the end of B (mm).
    pub wear: f64,
    /// Share `β` of the break-in phase.
    pub break_in: f64,
    /// Length `S₀` of the break-in (mm of path).
    pub break_in_mm: f64,
}

impl Wear {
    /// Radius lost after `s` mm of path of a total `total` (mm).
    pub fn at(&self, s: f64, total: f64) -> f64 {
        let shape = |s: f64| {
            self.break_in * (1.0 - (-s / self.break_in_mm).exp())
                + (1.0 - self.break_in) * s / total
        };
        self.wear * shape(s) / shape(total)
    }
}

/// What the machine does while it cuts one part, beyond the commanded motion.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Machining {
    /// Feed of the tool tip along the path (mm/min): the clock of the loops and the warm-up.
    pub feed: f64,
    /// ISO 230-1 location errors, through the exact chain.
    pub location: Vec<(ErrorParam, f64)>,
    /// Error motions as functions of axis position.
    pub motions: Vec<PositionError>,
    /// The position loops of X, Y, Z, B, C ([`AXES`] order); `None`: every axis is where it is
    /// commanded.
    pub loops: Option<[AxisLoop; 5]>,
    /// Lost motion of one axis.
    pub backlash: Option<(AxisName, LostMotion)>,
    pub warmup: Option<Warmup>,
    pub wear: Option<Wear>,
    /// Tool radius error `dR` (mm; + a larger tool).
    pub radius_error: f64,
    /// Radius change per mm of height above the tip (mm/mm).
    pub taper: f64,
    /// Zero offset of C (rad).
    pub c_offset: f64,
    /// Pivot-to-tip length error (mm).
    pub pivot_error: f64,
    /// Keep the flank path's own overcut in the deviation.
    pub keep_overcut: bool,
}

impl Default for Machining {
    fn default() -> Self {
        Self {
            feed: DEFAULT_FEED,
            location: Vec::new(),
            motions: Vec::new(),
            loops: None,
            backlash: None,
            warmup: None,
            wear: None,
            radius_error: 0.0,
            taper: 0.0,
            c_offset: 0.0,
            pivot_error: 0.0,
            keep_overcut: false,
        }
    }
}

/// The settings-only model of the machining: the part, its points, paper 000's chain and the two
/// commanded passes (built once; every part is machined on it).
#[derive(Debug, Clone)]
pub struct Workshop {
    pub part: SShape,
    pub points: Vec<MeasurementPoint>,
    /// Pivot-to-tip length `L0` of the programmed machine (mm).
    pub l0: f64,
    pub chain: Chain,
    /// The passes of A and B.
    pub passes: [CommandedPass; 2],
    /// The reference pose where the part origin is set: tip at the origin, tool vertical.
    pub reference: AxisValues,
    /// Each point's deviation left by the commanded tools (the flank path's overcut, mm).
    pub commanded: Vec<f64>,
    /// Each point's pass (0: A, 1: B) and nearest sample.
    near: Vec<(usize, usize)>,
}

impl Workshop {
    /// The workshop of `points` of `part` on paper 000's machine with pivot-to-tip length `l0`
    /// (mm), signed B, the passes sampled every `step` mm of path.
    pub fn new(
        part: &SShape,
        points: &[MeasurementPoint],
        l0: f64,
        step: f64,
    ) -> Result<Self, PhysicsError> {
        let chain = Chain::paper000(l0);
        let passes = [
            CommandedPass::new(part, &chain, Branch::Signed, Surface::A, step)?,
            CommandedPass::new(part, &chain, Branch::Signed, Surface::B, step)?,
        ];
        let reference = inverse(
            &chain,
            &Vector3::zeros(),
            &Vector3::z(),
            Branch::Signed,
            0.0,
        )?;
        let near = points
            .iter()
            .map(|p| {
                let k = p.surface.index();
                (k, passes[k].index_near(p.u))
            })
            .collect();
        let mut w = Self {
            part: part.clone(),
            points: points.to_vec(),
            l0,
            chain,
            passes,
            reference,
            commanded: vec![0.0; points.len()],
            near,
        };
        w.commanded = w.envelope(&Machining::default())?;
        Ok(w)
    }

    /// Total path length of A then B (mm).
    pub fn total_length(&self) -> f64 {
        self.passes[0].length + self.passes[1].length
    }

    /// The deviation (mm, + material left) at every point of the part `m` machines.
    pub fn machine(&self, m: &Machining) -> Result<Vec<f64>, PhysicsError> {
        let e = self.envelope(m)?;
        Ok(if m.keep_overcut {
            e
        } else {
            e.iter().zip(&self.commanded).map(|(a, c)| a - c).collect()
        })
    }

    /// The envelope of the actual tools along every point's normal line (mm).
    fn envelope(&self, m: &Machining) -> Result<Vec<f64>, PhysicsError> {
        let chain = Chain::paper000(self.l0 + m.pivot_error);
        let origin = self.origin_shift(&chain, m)?;
        let mut out = vec![0.0; self.points.len()];
        let total = self.total_length();
        for (pi, pass) in self.passes.iter().enumerate() {
            let q = self.actual_axes(pass, m);
            let before = if pi == 0 { 0.0 } else { self.passes[0].length };
            let pause = if pi == 0 {
                0.0
            } else {
                m.warmup.map_or(0.0, |w| w.pause_s)
            };
            let pose = |k: usize| -> Result<ToolPose, PhysicsError> {
                let mut errors = MachineErrors {
                    values: m.location.clone(),
                };
                errors.values.extend(error_params(&m.motions, &q[k]));
                if let Some(w) = m.warmup {
                    let minutes = (before + pass.s[k]) / m.feed + pause / 60.0;
                    let growth = w.growth * (1.0 - (-minutes / w.minutes).exp());
                    errors.values.push((
                        ErrorParam::Motion {
                            component: AxisName::Z,
                            axis: AxisName::Z,
                            power: 0,
                        },
                        -growth,
                    ));
                }
                let t = tool_point(&chain, &q[k], 0.0, &errors)?;
                Ok(ToolPose {
                    tip: t.point - origin,
                    axis: t.direction.normalize(),
                })
            };
            let radius = |k: usize, h: f64| {
                TOOL_RADIUS + m.radius_error + m.taper * h
                    - m.wear.map_or(0.0, |w| w.at(before + pass.s[k], total))
            };
            let tools = PassTools {
                samples: pass.len(),
                step: pass.step,
                pose: &pose,
                radius: &radius,
            };
            let mut cache = vec![None; pass.len()];
            for (i, p) in self.points.iter().enumerate() {
                let (k, near) = self.near[i];
                if k != pi {
                    continue;
                }
                out[i] = deviation_at(&tools, &p.point, &p.normal, near, &mut cache)?;
            }
        }
        Ok(out)
    }

    /// The actual axis values of every sample of `pass`: loops, lost motion, C offset.
    pub fn actual_axes(&self, pass: &CommandedPass, m: &Machining) -> Vec<AxisValues> {
        let mut q = pass.q.clone();
        if let Some(loops) = &m.loops {
            let dt = pass.step / (m.feed / 60.0);
            for (axis, l) in AXES.iter().zip(loops) {
                let cmd: Vec<f64> = q.iter().map(|v| v.get(*axis)).collect();
                for (v, a) in q.iter_mut().zip(l.follow(&cmd, dt)) {
                    v.set(*axis, a);
                }
            }
        }
        if let Some((axis, lost)) = &m.backlash {
            let pos: Vec<f64> = q.iter().map(|v| v.get(*axis)).collect();
            for (v, e) in q.iter_mut().zip(lost.offsets(&pos, pass.step)) {
                v.set(*axis, v.get(*axis) + e);
            }
        }
        if m.c_offset != 0.0 {
            for v in q.iter_mut() {
                v.c += m.c_offset;
            }
        }
        q
    }

    /// `Δ_ref`: how far the static errors moved the tip at the reference pose, where the part
    /// origin was set (mm).
    fn origin_shift(&self, chain: &Chain, m: &Machining) -> Result<Vector3<f64>, PhysicsError> {
        let mut q = self.reference;
        q.c += m.c_offset;
        let mut errors = MachineErrors {
            values: m.location.clone(),
        };
        errors.values.extend(error_params(&m.motions, &q));
        let real = tool_point(chain, &q, 0.0, &errors)?.point;
        Ok(real - nominal(&self.chain, &self.reference, 0.0).point)
    }
}
