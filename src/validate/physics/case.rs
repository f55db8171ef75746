//! The cases of the physics benchmark: what each part carries, drawn from a seeded stream, and the
//! part made from it ([`Generator::part`]).
//!
//! Every part has random location errors (angles uniform in ±[`ANGLE_RANGE`] rad, lengths in
//! ±[`LENGTH_RANGE`] mm) through the exact chain, then one of the [`Kind`]s:
//! - clean parts: nothing else ([`Kind::Clean`]), the part's surface scatter
//!   ([`Kind::CleanScatter`]), or a scattered part measured 2-5 times ([`Kind::Repeats`]);
//! - one effect made by the physics of this folder, at a random shape (lag, response, time
//!   constant, wavelength, ...); the linear axes' error motions (straightness, cyclic and pitch
//!   errors) measured from their ISO 230-1 reference ([`PositionError::from_reference`]), so
//!   that no location error is carried under their name.
//!
//! **Sizes.** Each effect's amplitude is set so that its visible structure (the RMS of what the
//! location errors cannot absorb, given by the caller: the generator knows nothing of the fit) is
//! `ρ` times the detection limit `k σ` of the part's true σ, `ρ` log-uniform in
//! [[`RATIO_MIN`], [`RATIO_MAX`]]: the effect alone is made once at a pilot size, its amplitude
//! scaled, and the part made again at that amplitude (the physics is not linear in every
//! amplitude: the ratio recorded is that of the part made). An amplitude never exceeds its
//! physical bound ([`Physics::size_and_cap`]). The servo loops' shape is the gain mismatch (its common
//! rounding is whatever `Kv` and the feed give); the loops of [`Kind::ServoCommon`] and the
//! flank overcut are not scaled.
//!
//! **Noise** ([`super::noise`]): CMM σ 0.8-2.5 µm (0.3-2 µm with scatter, 0.3-1 µm for repeats),
//! Gaussian (half the parts), Student-t with 3-5 degrees of freedom (a quarter) or with 1 % of
//! points off by 6-10 σ (a quarter); surface scatter 0.5-2.5 µm on the scattered kinds and on half
//! the effect parts.

use std::f64::consts::PI;

use crate::machine::{AxisName, ErrorParam};
use crate::numerics::random::Sampler;

use super::backlash::{LostMotion, Settling};
use super::machining::{Machining, Warmup, Wear, Workshop, AXES};
use super::measuring::{Measuring, Placement};
use super::motion::{Law, PositionError};
use super::noise::{CmmModel, NoiseSpec};
use super::servo::{AxisLoop, Response};
use super::PhysicsError;

/// Range of the angular location errors (± rad).
pub const ANGLE_RANGE: f64 = 3e-4;
/// Range of the length location errors (± mm).
pub const LENGTH_RANGE: f64 = 0.03;
/// Smallest and largest target of visible structure over the detection limit.
pub const RATIO_MIN: f64 = 0.3;
pub const RATIO_MAX: f64 = 6.0;
/// Position-loop gains of the servo kinds (1/s) and feeds (mm/min).
pub const KV_MIN: f64 = 15.0;
pub const KV_MAX: f64 = 60.0;
pub const FEED_MIN: f64 = 1000.0;
pub const FEED_MAX: f64 = 2000.0;
/// The length over which a straightness bow reaches its amplitude (mm): a curvature of the
/// guideway, the same on every axis (a short travel sees little of it).
pub const BOW_HALF_WIDTH_MM: f64 = 250.0;
/// Backlash settling lags (mm of tool-tip path).
pub const LAG_MIN_MM: f64 = 0.2;
pub const LAG_MAX_MM: f64 = 15.0;

/// What a case carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    Clean,
    CleanScatter,
    Repeats,
    Backlash,
    ServoOne,
    ServoCommon,
    ServoAll,
    Warmup,
    Wear,
    ToolRadius,
    ToolTaper,
    Scale,
    CIndex,
    PivotLength,
    Setup,
    Overcut,
    Straightness,
    Cyclic,
    Pitch,
    ProbeLobing,
    PartDrift,
}

impl Kind {
    /// The kinds without an effect, in the order cases take them.
    pub const CLEAN: [Kind; 3] = [Kind::Clean, Kind::CleanScatter, Kind::Repeats];
    /// The kinds with one effect, in the order cases take them.
    pub const EFFECTS: [Kind; 18] = [
        Kind::Backlash,
        Kind::ServoOne,
        Kind::Warmup,
        Kind::Straightness,
        Kind::ToolRadius,
        Kind::Cyclic,
        Kind::Wear,
        Kind::ServoAll,
        Kind::Scale,
        Kind::Pitch,
        Kind::ToolTaper,
        Kind::ProbeLobing,
        Kind::CIndex,
        Kind::ServoCommon,
        Kind::PivotLength,
        Kind::PartDrift,
        Kind::Setup,
        Kind::Overcut,
    ];

    /// The kind of case number `case`: every third case a clean one (the three clean kinds in
    /// turn), the others the effects in turn.
    pub fn of_case(case: usize) -> Kind {
        if case % 3 == 0 {
            Kind::CLEAN[(case / 3) % 3]
        } else {
            Kind::EFFECTS[(case - case / 3 - 1) % Kind::EFFECTS.len()]
        }
    }

    /// The kind's name (as in the JSON).
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Clean => "clean",
            Kind::CleanScatter => "clean_scatter",
            Kind::Repeats => "repeats",
            Kind::Backlash => "backlash",
            Kind::ServoOne => "servo_one",
            Kind::ServoCommon => "servo_common",
            Kind::ServoAll => "servo_all",
            Kind::Warmup => "warmup",
            Kind::Wear => "wear",
            Kind::ToolRadius => "tool_radius",
            Kind::ToolTaper => "tool_taper",
            Kind::Scale => "scale",
            Kind::CIndex => "c_index",
            Kind::PivotLength => "pivot_length",
            Kind::Setup => "setup",
            Kind::Overcut => "overcut",
            Kind::Straightness => "straightness",
            Kind::Cyclic => "cyclic",
            Kind::Pitch => "pitch",
            Kind::ProbeLobing => "probe_lobing",
            Kind::PartDrift => "part_drift",
        }
    }

    /// Whether the kind carries no effect.
    pub fn is_clean(self) -> bool {
        Kind::CLEAN.contains(&self)
    }
}

impl std::fmt::Display for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.as_str())
    }
}

/// The physical effect of a part and its parameters (JSON: `effect` and the fields).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "effect", rename_all = "snake_case")]
pub enum Physics {
    None,
    /// Lost motion of one axis (play `b` mm or rad, settling).
    Backlash {
        axis: AxisName,
        lost: LostMotion,
    },
    /// Position loops of X, Y, Z, B, C: `Kv_i = clamp(kv0·exp(mismatch·spread_i))`.
    Servo {
        feed: f64,
        kv0: f64,
        spread: [f64; 5],
        mismatch: f64,
        response: Response,
        loops: [AxisLoop; 5],
    },
    /// The head warming up; `drift` is what it has grown by the end of B (mm), the part taking
    /// `part_minutes` to machine.
    Warmup {
        warmup: Warmup,
        feed: f64,
        drift: f64,
        part_minutes: f64,
    },
    Wear {
        wear: Wear,
    },
    ToolRadius {
        d_r: f64,
    },
    ToolTaper {
        d_r0: f64,
        g: f64,
    },
    Scale {
        axis: AxisName,
        k: f64,
    },
    CIndex {
        d_c: f64,
    },
    PivotLength {
        d_l0: f64,
    },
    Setup {
        placement: Placement,
    },
    /// The flank path's own overcut kept (fixed by the geometry).
    Overcut,
    Straightness {
        motion: PositionError,
    },
    Cyclic {
        motion: PositionError,
    },
    Pitch {
        motion: PositionError,
    },
    ProbeLobing {
        a: f64,
        phase: f64,
    },
    PartDrift {
        placement: Placement,
        f: f64,
    },
}

/// The loops of a servo case.
fn loops(kv0: f64, spread: &[f64; 5], mismatch: f64, response: Response) -> [AxisLoop; 5] {
    spread.map(|e| AxisLoop {
        kv: (kv0 * (mismatch * e).exp()).clamp(KV_MIN, KV_MAX),
        response,
    })
}

impl Physics {
    /// The same effect with its amplitude times `f` (the loops: their mismatch).
    pub fn scaled(&self, f: f64) -> Physics {
        let p = |x: &Placement| Placement {
            theta_z: x.theta_z * f,
            tx: x.tx * f,
            ty: x.ty * f,
        };
        let m = |x: &PositionError| x.scaled(f);
        match self {
            Physics::None | Physics::Overcut => self.clone(),
            Physics::Backlash { axis, lost } => Physics::Backlash {
                axis: *axis,
                lost: LostMotion {
                    b: lost.b * f,
                    ..*lost
                },
            },
            Physics::Servo {
                feed,
                kv0,
                spread,
                mismatch,
                response,
                ..
            } => Physics::Servo {
                feed: *feed,
                kv0: *kv0,
                spread: *spread,
                mismatch: mismatch * f,
                response: *response,
                loops: loops(*kv0, spread, mismatch * f, *response),
            },
            Physics::Warmup {
                warmup,
                feed,
                drift,
                part_minutes,
            } => Physics::Warmup {
                warmup: Warmup {
                    growth: warmup.growth * f,
                    ..*warmup
                },
                feed: *feed,
                drift: drift * f,
                part_minutes: *part_minutes,
            },
            Physics::Wear { wear } => Physics::Wear {
                wear: Wear {
                    wear: wear.wear * f,
                    ..*wear
                },
            },
            Physics::ToolRadius { d_r } => Physics::ToolRadius { d_r: d_r * f },
            Physics::ToolTaper { d_r0, g } => Physics::ToolTaper {
                d_r0: d_r0 * f,
                g: g * f,
            },
            Physics::Scale { axis, k } => Physics::Scale {
                axis: *axis,
                k: k * f,
            },
            Physics::CIndex { d_c } => Physics::CIndex { d_c: d_c * f },
            Physics::PivotLength { d_l0 } => Physics::PivotLength { d_l0: d_l0 * f },
            Physics::Setup { placement } => Physics::Setup {
                placement: p(placement),
            },
            Physics::Straightness { motion } => Physics::Straightness { motion: m(motion) },
            Physics::Cyclic { motion } => Physics::Cyclic { motion: m(motion) },
            Physics::Pitch { motion } => Physics::Pitch { motion: m(motion) },
            Physics::ProbeLobing { a, phase } => Physics::ProbeLobing {
                a: a * f,
                phase: *phase,
            },
            Physics::PartDrift { placement, f: g } => Physics::PartDrift {
                placement: p(placement),
                f: *g,
            },
        }
    }

    /// The amplitude [`Physics::scaled`] multiplies (its unit: mm, rad, mm/mm, or 1 for the
    /// loops' mismatch) and its physical bound: no part is made beyond it. The bounds are what a
    /// bad machine, probe or setup shows (a few times a typical bad value: a backlash of 50 µm or
    /// 1 mrad, a scale error of 500 µm/m, a warm-up of 0.1 mm over the part, a straightness bow of
    /// 0.1 mm at 250 mm, a cyclic error of 20 µm, a pitch error of 50 µm, a probe lobing of
    /// 15 µm): where even that leaves the effect below its target, the physics says the part
    /// hardly sees it.
    pub fn size_and_cap(&self) -> (f64, f64) {
        let amp = |m: &PositionError| match m.law {
            Law::Linear { k } => k.abs(),
            Law::Bow { a, .. } | Law::Sine { a, .. } => a.abs(),
        };
        let place = |p: &Placement| (p.theta_z.abs() * 100.0).max(p.tx.abs()).max(p.ty.abs());
        match self {
            Physics::None | Physics::Overcut => (0.0, 0.0),
            Physics::Backlash { axis, lost } => (
                lost.b.abs(),
                if matches!(axis, AxisName::B | AxisName::C) {
                    1e-3
                } else {
                    0.05
                },
            ),
            Physics::Servo {
                mismatch, spread, ..
            } => (
                mismatch.abs(),
                if spread.iter().all(|e| *e == 0.0) {
                    0.0
                } else {
                    4f64.ln()
                },
            ),
            Physics::Warmup { drift, .. } => (drift.abs(), 0.1),
            Physics::Wear { wear } => (wear.wear.abs(), 0.05),
            Physics::ToolRadius { d_r } => (d_r.abs(), 0.1),
            Physics::ToolTaper { d_r0, g } => ((d_r0 * d_r0 + (20.0 * g).powi(2)).sqrt(), 0.1),
            Physics::Scale { k, .. } => (k.abs(), 5e-4),
            Physics::CIndex { d_c } => (d_c.abs(), 1e-3),
            Physics::PivotLength { d_l0 } => (d_l0.abs(), 0.2),
            Physics::Setup { placement } => (place(placement), 0.2),
            Physics::Straightness { motion } => (amp(motion), 0.1),
            Physics::Cyclic { motion } => (amp(motion), 0.02),
            Physics::Pitch { motion } => (amp(motion), 0.05),
            Physics::ProbeLobing { a, .. } => (a.abs(), 0.015),
            Physics::PartDrift { placement, .. } => (place(placement), 0.05),
        }
    }

    /// What the effect does to the machining and to the measurement.
    pub fn apply(&self, m: &mut Machining, meas: &mut Measuring) {
        match self {
            Physics::None => {}
            Physics::Backlash { axis, lost } => m.backlash = Some((*axis, *lost)),
            Physics::Servo { feed, loops, .. } => {
                m.feed = *feed;
                m.loops = Some(*loops);
            }
            Physics::Warmup { warmup, feed, .. } => {
                m.feed = *feed;
                m.warmup = Some(*warmup);
            }
            Physics::Wear { wear } => m.wear = Some(*wear),
            Physics::ToolRadius { d_r } => m.radius_error = *d_r,
            Physics::ToolTaper { d_r0, g } => {
                m.radius_error = *d_r0;
                m.taper = *g;
            }
            Physics::Scale { axis, k } => {
                m.motions
                    .push(PositionError::new(*axis, *axis, Law::Linear { k: *k }))
            }
            Physics::CIndex { d_c } => m.c_offset = *d_c,
            Physics::PivotLength { d_l0 } => m.pivot_error = *d_l0,
            Physics::Setup { placement } => meas.placement = Some(*placement),
            Physics::Overcut => m.keep_overcut = true,
            Physics::Straightness { motion }
            | Physics::Cyclic { motion }
            | Physics::Pitch { motion } => m.motions.push(*motion),
            Physics::ProbeLobing { a, phase } => meas.lobing = Some((*a, *phase)),
            Physics::PartDrift { placement, f } => meas.drift = Some((*placement, *f)),
        }
    }
}

/// A part made by the generator, with everything the benchmark needs to judge its analysis.
#[derive(Debug, Clone, serde::Serialize)]
pub struct GeneratedPart {
    pub kind: Kind,
    pub physics: Physics,
    /// The location errors (in the order of the generator's list; rad, mm).
    pub xi: Vec<f64>,
    pub noise: NoiseSpec,
    /// True σ of one analysed deviation (mm).
    pub sigma: f64,
    /// The `ρ` the amplitude was aimed at (0 for the clean kinds).
    pub target_ratio: f64,
    /// The recorded deviations without noise (mm).
    #[serde(skip)]
    pub noise_free: Vec<f64>,
    /// The same part without its effect (the location errors alone; mm).
    #[serde(skip)]
    pub location_only: Vec<f64>,
    /// The servo kinds whose gains differ: the same part with every gain at `kv0` (the common
    /// rounding alone; mm), so that the mismatch's own share can be told.
    #[serde(skip)]
    pub common: Option<Vec<f64>>,
    /// The measurements: one file, or the repeats (mm).
    #[serde(skip)]
    pub measurements: Vec<Vec<f64>>,
}

/// RMS (mm) of what the location errors cannot absorb of a deviation vector at the points.
pub type Visible<'a> = dyn Fn(&[f64]) -> f64 + 'a;

/// The generator: the workshop, the location errors it draws, and how to measure visible
/// structure (from the caller).
pub struct Generator<'a> {
    pub workshop: &'a Workshop,
    /// The machine's location errors, drawn for every part.
    pub location: Vec<ErrorParam>,
    /// RMS of the part of a deviation the location errors cannot absorb (mm).
    pub visible: &'a Visible<'a>,
    /// `k` of the detection limit `k σ`.
    pub detect_factor: f64,
    /// The range (min, max) of each linear axis over the passes (mm), X, Y, Z.
    ranges: [(f64, f64); 3],
}

impl<'a> Generator<'a> {
    pub fn new(
        workshop: &'a Workshop,
        location: Vec<ErrorParam>,
        visible: &'a Visible<'a>,
        detect_factor: f64,
    ) -> Self {
        let range = |a: AxisName| {
            workshop
                .passes
                .iter()
                .flat_map(|p| p.q.iter().map(move |q| q.get(a)))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                })
        };
        Self {
            workshop,
            location,
            visible,
            detect_factor,
            ranges: [range(AxisName::X), range(AxisName::Y), range(AxisName::Z)],
        }
    }

    /// One part of kind `kind` from the stream `rng`.
    pub fn part(&self, kind: Kind, rng: &mut Sampler) -> Result<GeneratedPart, PhysicsError> {
        let xi: Vec<f64> = self
            .location
            .iter()
            .map(|p| {
                let r = if p.is_angular() {
                    ANGLE_RANGE
                } else {
                    LENGTH_RANGE
                };
                rng.uniform(-r, r)
            })
            .collect();
        let noise = draw_noise(kind, rng);
        let sigma = noise.sigma();
        let pilot = if kind.is_clean() {
            Physics::None
        } else {
            self.draw_physics(kind, rng)
        };
        let target_ratio = if kind.is_clean() {
            0.0
        } else {
            rng.log_uniform(RATIO_MIN, RATIO_MAX)
        };
        let location: Vec<(ErrorParam, f64)> = self
            .location
            .iter()
            .copied()
            .zip(xi.iter().copied())
            .collect();
        let physics = self.size(&pilot, target_ratio * self.detect_factor * sigma)?;
        let location_only = self.record(&Physics::None, &location)?;
        let noise_free = match physics {
            Physics::None => location_only.clone(),
            _ => self.record(&physics, &location)?,
        };
        let common = match &physics {
            Physics::Servo { spread, .. } if spread.iter().any(|e| *e != 0.0) => {
                Some(self.record(&physics.scaled(0.0), &location)?)
            }
            _ => None,
        };
        let measurements = noise.measure(&noise_free, rng);
        Ok(GeneratedPart {
            kind,
            physics,
            xi,
            noise,
            sigma,
            target_ratio,
            noise_free,
            location_only,
            common,
            measurements,
        })
    }

    /// The recorded deviations (mm, no noise) of a part with `physics` and location errors.
    pub fn record(
        &self,
        physics: &Physics,
        location: &[(ErrorParam, f64)],
    ) -> Result<Vec<f64>, PhysicsError> {
        let mut m = Machining {
            location: location.to_vec(),
            ..Machining::default()
        };
        let mut meas = Measuring::default();
        physics.apply(&mut m, &mut meas);
        let machined = self.workshop.machine(&m)?;
        Ok(meas.record(&self.workshop.points, &machined))
    }

    /// The effect scaled so that its visible structure is `target` (mm), within its cap.
    fn size(&self, pilot: &Physics, target: f64) -> Result<Physics, PhysicsError> {
        let (size, cap) = pilot.size_and_cap();
        if size == 0.0 || cap == 0.0 {
            return Ok(pilot.clone());
        }
        let alone = self.record(pilot, &[])?;
        // the loops' mismatch: what it adds to their common rounding
        let base = match pilot {
            Physics::Servo { .. } => Some(self.record(&pilot.scaled(0.0), &[])?),
            _ => None,
        };
        let shape: Vec<f64> = match &base {
            Some(b) => alone.iter().zip(b).map(|(a, b)| a - b).collect(),
            None => alone,
        };
        let seen = (self.visible)(&shape);
        let f = if seen > 1e-9 {
            target / seen
        } else {
            f64::INFINITY
        };
        Ok(pilot.scaled(f.min(cap / size)))
    }

    /// An effect of kind `kind` at its pilot size, its shape random.
    fn draw_physics(&self, kind: Kind, rng: &mut Sampler) -> Physics {
        let linear = [AxisName::X, AxisName::Y, AxisName::Z];
        let pick = |rng: &mut Sampler, n: usize| ((rng.unit() * n as f64) as usize).min(n - 1);
        match kind {
            Kind::Clean | Kind::CleanScatter | Kind::Repeats => Physics::None,
            Kind::Backlash => {
                let axis = AXES[pick(rng, 5)];
                let tau = rng.log_uniform(LAG_MIN_MM, LAG_MAX_MM);
                let settling = if rng.unit() < 0.5 {
                    Settling::FirstOrder { tau }
                } else {
                    Settling::Underdamped {
                        tau,
                        zeta: rng.uniform(0.25, 0.7),
                    }
                };
                let b = if matches!(axis, AxisName::B | AxisName::C) {
                    5e-5
                } else {
                    0.005
                };
                Physics::Backlash {
                    axis,
                    lost: LostMotion { b, settling },
                }
            }
            Kind::ServoOne | Kind::ServoCommon | Kind::ServoAll => {
                let feed = rng.uniform(FEED_MIN, FEED_MAX);
                let kv0 = rng.uniform(KV_MIN, KV_MAX);
                let response = if rng.unit() < 2.0 / 3.0 {
                    Response::FirstOrder
                } else {
                    Response::SecondOrder {
                        omega: 2.0 * PI * rng.uniform(20.0, 60.0),
                        zeta: rng.uniform(0.5, 0.9),
                    }
                };
                let mut spread = [0.0; 5];
                match kind {
                    Kind::ServoOne => spread[pick(rng, 5)] = rng.sign(),
                    Kind::ServoAll => spread.iter_mut().for_each(|e| *e = rng.normal()),
                    _ => {}
                }
                let mismatch = if kind == Kind::ServoCommon { 0.0 } else { 0.05 };
                Physics::Servo {
                    feed,
                    kv0,
                    spread,
                    mismatch,
                    response,
                    loops: loops(kv0, &spread, mismatch, response),
                }
            }
            Kind::Warmup => {
                // the time constant a multiple f of the part's machining time (effects.md's
                // family: f large is the linear drift), the growth set by the drift reached
                let feed = rng.uniform(FEED_MIN, FEED_MAX);
                let pause_s = rng.uniform(0.0, 30.0);
                let part_minutes = self.workshop.total_length() / feed + pause_s / 60.0;
                let minutes = part_minutes * rng.log_uniform(0.1, 10.0);
                let drift = 0.005 * rng.sign();
                Physics::Warmup {
                    warmup: Warmup {
                        growth: drift / (1.0 - (-part_minutes / minutes).exp()),
                        minutes,
                        pause_s,
                    },
                    feed,
                    drift,
                    part_minutes,
                }
            }
            Kind::Wear => Physics::Wear {
                wear: Wear {
                    wear: 0.005,
                    break_in: rng.uniform(0.0, 0.6),
                    break_in_mm: rng.log_uniform(10.0, 300.0),
                },
            },
            Kind::ToolRadius => Physics::ToolRadius {
                d_r: 0.005 * rng.sign(),
            },
            Kind::ToolTaper => Physics::ToolTaper {
                d_r0: 0.005 * rng.normal(),
                g: 2.5e-4 * rng.normal(),
            },
            Kind::Scale => Physics::Scale {
                axis: linear[pick(rng, 3)],
                k: 2e-5 * rng.sign(),
            },
            Kind::CIndex => Physics::CIndex {
                d_c: 5e-5 * rng.sign(),
            },
            Kind::PivotLength => Physics::PivotLength {
                d_l0: 0.02 * rng.sign(),
            },
            Kind::Setup => Physics::Setup {
                placement: placement(rng),
            },
            Kind::Overcut => Physics::Overcut,
            Kind::Straightness => {
                let axis = pick(rng, 3);
                let across: Vec<AxisName> =
                    (0..3).filter(|&i| i != axis).map(|i| linear[i]).collect();
                let (lo, hi) = self.ranges[axis];
                Physics::Straightness {
                    motion: PositionError::from_reference(
                        across[pick(rng, 2)],
                        linear[axis],
                        Law::Bow {
                            a: 0.005 * rng.sign(),
                            center: rng.uniform(lo, hi),
                            half_width: BOW_HALF_WIDTH_MM,
                        },
                        (lo, hi),
                    ),
                }
            }
            Kind::Cyclic | Kind::Pitch => {
                let i = pick(rng, 2);
                let axis = linear[i];
                let wavelength = if kind == Kind::Cyclic {
                    rng.log_uniform(25.0, 100.0)
                } else {
                    rng.log_uniform(150.0, 600.0)
                };
                let law = Law::Sine {
                    a: 0.003,
                    wavelength,
                    phase: rng.uniform(0.0, 2.0 * PI),
                };
                let motion = PositionError::from_reference(axis, axis, law, self.ranges[i]);
                if kind == Kind::Cyclic {
                    Physics::Cyclic { motion }
                } else {
                    Physics::Pitch { motion }
                }
            }
            Kind::ProbeLobing => Physics::ProbeLobing {
                a: 0.002,
                phase: rng.uniform(0.0, 2.0 * PI / 3.0),
            },
            Kind::PartDrift => Physics::PartDrift {
                placement: placement(rng),
                f: rng.log_uniform(0.1, 10.0),
            },
        }
    }
}

/// A small rigid motion of the part: 5e-5 rad, 5 µm (normal).
fn placement(rng: &mut Sampler) -> Placement {
    Placement {
        theta_z: 5e-5 * rng.normal(),
        tx: 0.005 * rng.normal(),
        ty: 0.005 * rng.normal(),
    }
}

/// The noise of a part of kind `kind` (module docs).
fn draw_noise(kind: Kind, rng: &mut Sampler) -> NoiseSpec {
    let um = 1e-3;
    let model = |rng: &mut Sampler| {
        let x = rng.unit();
        if x < 0.5 {
            CmmModel::Gaussian
        } else if x < 0.75 {
            CmmModel::StudentT {
                nu: 3 + ((rng.unit() * 3.0) as u32).min(2),
            }
        } else {
            CmmModel::Contaminated {
                rate: 0.01,
                factor_lo: 6.0,
                factor_hi: 10.0,
            }
        }
    };
    match kind {
        Kind::Clean => NoiseSpec {
            cmm_sigma: rng.uniform(0.8, 2.5) * um,
            model: model(rng),
            scatter_sigma: 0.0,
            repeats: 1,
        },
        Kind::CleanScatter => NoiseSpec {
            cmm_sigma: rng.uniform(0.3, 2.0) * um,
            model: model(rng),
            scatter_sigma: rng.uniform(0.5, 2.5) * um,
            repeats: 1,
        },
        Kind::Repeats => NoiseSpec {
            cmm_sigma: rng.uniform(0.3, 1.0) * um,
            model: if rng.unit() < 0.5 {
                CmmModel::Gaussian
            } else {
                CmmModel::StudentT { nu: 5 }
            },
            scatter_sigma: rng.uniform(0.8, 2.5) * um,
            repeats: 2 + ((rng.unit() * 4.0) as usize).min(3),
        },
        _ => {
            let cmm_sigma = rng.uniform(0.8, 2.5) * um;
            let model = model(rng);
            let scatter_sigma = if rng.unit() < 0.5 {
                rng.uniform(0.5, 2.5) * um
            } else {
                0.0
            };
            NoiseSpec {
                cmm_sigma,
                model,
                scatter_sigma,
                repeats: 1,
            }
        }
    }
}
