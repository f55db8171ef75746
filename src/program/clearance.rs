//! Replay of a program's moves through the machine model with the tool and its holder as
//! cylinders swept between positions, against the part and a stated base plate: how close
//! does any move outside the cut come to them.
//!
//! - The tool: a cylinder of radius [`TOOL_RADIUS`] (Ø20) and length [`TOOL_LENGTH`] above its
//!   tip, with the flat end; the holder: a cylinder of radius [`HOLDER_RADIUS`] from
//!   [`TOOL_LENGTH`] to [`TOOL_LENGTH`] + [`HOLDER_LENGTH`] above the tip. Their pose at axis
//!   values `q` is the nominal direct kinematics of the chain ([`nominal`]: the model the
//!   analysis uses), in the part frame.
//! - The part: both walls (S(u, v) of paper 000 eq. 1) sampled on a grid of at most
//!   [`GRID_MM`] mm; the base plate: the plane `z =` [`PLATE_TOP_Z`] under it.
//! - A move: sampled so that no point of the tool or holder moves more than [`GRID_MM`] mm
//!   between samples. G00/G01 in machine axes interpolate every axis linearly; in the
//!   tool-centre-point mode the controller interpolates the tip (part frame) and the rotary
//!   axes linearly ([`Interpolation`]).
//!
//! The distance found is to the sampled points at the sampled poses; the true distance is
//! smaller by at most [`Clearance::sampling_bound`] (half the grid cell's diagonal plus half a
//! step of the move), which the reported `min_rapid_certain` subtracts. Units: mm, rad.

use nalgebra::Vector3;
use serde::Serialize;

use super::motion::{Motion, StepKind, PLATE_TOP_Z};
use crate::machine::direct::nominal;
use crate::machine::inverse::solve_linear;
use crate::machine::{AxisKind, AxisName, AxisValues, Chain};
use crate::part::{SShape, Surface};
use crate::toolpath::TOOL_RADIUS;

/// Length of the tool above its tip (mm): the stick-out to the holder.
pub const TOOL_LENGTH: f64 = 60.0;
/// Radius of the holder (mm).
pub const HOLDER_RADIUS: f64 = 25.0;
/// Length of the holder (mm).
pub const HOLDER_LENGTH: f64 = 100.0;
/// The clearance the replay checks (mm).
pub const CHECK_CLEARANCE: f64 = 2.0;
/// Largest spacing of the part's sample grid and of a move's samples (mm).
pub const GRID_MM: f64 = 0.5;
/// Distances beyond this (mm) are reported as this: nothing is near.
pub const FAR: f64 = 50.0;

/// How the controller interpolates a move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// Every machine axis linearly (G00/G01 without TCP).
    MachineAxes,
    /// The tool tip in the part frame and the rotary axes linearly (TCP on).
    TipPoint,
}

/// One position of a replayed program: the machine axes reached, whether it was reached at
/// rapid, and how the move to it is interpolated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Waypoint {
    pub q: AxisValues,
    pub rapid: bool,
    pub interpolation: Interpolation,
}

/// What the replay found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Clearance {
    /// Smallest distance (mm) of the tool or holder from the walls or the plate over every
    /// rapid move (sampled; at most [`FAR`]).
    pub min_rapid: f64,
    /// `min_rapid − sampling_bound`: the distance the rapids certainly keep (mm).
    pub min_rapid_certain: f64,
    /// Index (in the waypoints) of the move where `min_rapid` is reached.
    pub worst_rapid: usize,
    /// Smallest height (mm) of the tool or holder above the plate over every move, cut too.
    pub min_plate: f64,
    /// Feed moves longer than [`crate::budget::discrete::MAX_PASS_STEP`] that do not move the
    /// tool along its own axis: moves across the part at feed (should be 0).
    pub long_feed_moves_across: usize,
    /// Smallest distance (mm) at the outer ends of the feed moves along the tool axis (where
    /// the tool leaves the cut or starts into it).
    pub min_axial_end: f64,
    pub rapid_moves: usize,
    pub feed_moves: usize,
    pub samples: usize,
    /// Largest error (mm) of the sampled distance (module docs).
    pub sampling_bound: f64,
}

/// Points of the grid with their bounding box (lowest, highest corner).
type Chunk = (Vector3<f64>, Vector3<f64>, Vec<Vector3<f64>>);

/// The walls as a grid of points in chunks, each with its bounding box.
pub struct PartGrid {
    chunks: Vec<Chunk>,
    cell_diagonal: f64,
}

impl PartGrid {
    /// Both walls of the S-shape on a grid of at most [`GRID_MM`] mm.
    pub fn s_shape() -> Self {
        let part = SShape::iso();
        let mut chunks = Vec::new();
        let mut diag = 0.0f64;
        for s in Surface::BOTH {
            let len = part
                .curve_length(s, 0.0, 8)
                .max(part.curve_length(s, 1.0, 8));
            // u is not arc length: the spline's speed varies about 4-fold along the S.
            let nu = (len / GRID_MM).ceil() as usize * 5;
            let nv = (crate::part::HEIGHT / GRID_MM).ceil() as usize * 2;
            let mut du = 0.0f64;
            for c in 0..nu.div_ceil(32) {
                let mut pts = Vec::new();
                for i in c * 32..((c + 1) * 32 + 1).min(nu + 1) {
                    let u = i as f64 / nu as f64;
                    for j in 0..=nv {
                        pts.push(part.point_at(s, u, j as f64 / nv as f64));
                    }
                    if i > 0 {
                        let prev = (i - 1) as f64 / nu as f64;
                        for v in [0.0, 1.0] {
                            du =
                                du.max((part.point_at(s, u, v) - part.point_at(s, prev, v)).norm());
                        }
                    }
                }
                let (lo, hi) = bounds(&pts);
                chunks.push((lo, hi, pts));
            }
            let dv = part.section_at(s, 0.5).d.point.norm() / nv as f64 * 1.2;
            diag = diag.max((du * du + dv * dv).sqrt());
        }
        PartGrid {
            chunks,
            cell_diagonal: diag,
        }
    }
}

fn bounds(pts: &[Vector3<f64>]) -> (Vector3<f64>, Vector3<f64>) {
    pts.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}

/// A cylinder: base centre, unit axis, radius, length (mm).
#[derive(Debug, Clone, Copy)]
struct Cylinder {
    base: Vector3<f64>,
    axis: Vector3<f64>,
    radius: f64,
    length: f64,
}

impl Cylinder {
    /// Distance (mm) from `p`; negative inside (by the radial depth).
    fn distance(&self, p: &Vector3<f64>) -> f64 {
        let a = p - self.base;
        let s = a.dot(&self.axis);
        let r = (a - self.axis * s).norm();
        if (0.0..=self.length).contains(&s) {
            r - self.radius
        } else {
            let ds = if s < 0.0 { -s } else { s - self.length };
            let dr = (r - self.radius).max(0.0);
            (ds * ds + dr * dr).sqrt()
        }
    }
    fn bounds(&self) -> (Vector3<f64>, Vector3<f64>) {
        let top = self.base + self.axis * self.length;
        let r = Vector3::repeat(self.radius);
        (self.base.inf(&top) - r, self.base.sup(&top) + r)
    }
    /// Lowest z (mm) of the cylinder.
    fn lowest_z(&self) -> f64 {
        let across = (1.0 - self.axis.z * self.axis.z).max(0.0).sqrt();
        let low = |c: Vector3<f64>| c.z - self.radius * across;
        low(self.base).min(low(self.base + self.axis * self.length))
    }
}

fn box_gap(a: &(Vector3<f64>, Vector3<f64>), lo: &Vector3<f64>, hi: &Vector3<f64>) -> f64 {
    let d = Vector3::from_fn(|k, _| (lo[k] - a.1[k]).max(a.0[k] - hi[k]).max(0.0));
    d.norm()
}

fn bodies(chain: &Chain, q: &AxisValues) -> [Cylinder; 2] {
    let t = nominal(chain, q, 0.0);
    let w = t.direction;
    [
        Cylinder {
            base: t.point,
            axis: w,
            radius: TOOL_RADIUS,
            length: TOOL_LENGTH,
        },
        Cylinder {
            base: t.point + w * TOOL_LENGTH,
            axis: w,
            radius: HOLDER_RADIUS,
            length: HOLDER_LENGTH,
        },
    ]
}

/// Smallest distance (mm, at most `cap`) of the tool and holder at `q` from the walls.
fn wall_distance(chain: &Chain, q: &AxisValues, grid: &PartGrid, cap: f64) -> f64 {
    let mut best = cap;
    for body in bodies(chain, q) {
        let b = body.bounds();
        for (lo, hi, pts) in &grid.chunks {
            if box_gap(&b, lo, hi) >= best {
                continue;
            }
            for p in pts {
                best = best.min(body.distance(p));
            }
        }
    }
    best
}

fn plate_height(chain: &Chain, q: &AxisValues) -> f64 {
    bodies(chain, q)
        .iter()
        .map(|c| c.lowest_z() - PLATE_TOP_Z)
        .fold(f64::INFINITY, f64::min)
}

/// Axis values a fraction `t` of the way from `a` to `b` under `interp`.
fn between(
    chain: &Chain,
    a: &AxisValues,
    b: &AxisValues,
    t: f64,
    interp: Interpolation,
) -> AxisValues {
    let mut q = AxisValues::default();
    for n in AxisName::ALL {
        q.set(n, a.get(n) + t * (b.get(n) - a.get(n)));
    }
    if interp == Interpolation::TipPoint {
        let (ta, tb) = (nominal(chain, a, 0.0).point, nominal(chain, b, 0.0).point);
        if let Ok(s) = solve_linear(chain, &q, &(ta + (tb - ta) * t)) {
            return s;
        }
    }
    q
}

/// Samples of a move: no tool or holder point moves more than [`GRID_MM`] between them.
fn samples_of(chain: &Chain, a: &AxisValues, b: &AxisValues) -> usize {
    let reach = TOOL_LENGTH + HOLDER_LENGTH;
    let lin = [0.0, reach]
        .iter()
        .map(|&h| (nominal(chain, b, h).point - nominal(chain, a, h).point).norm())
        .fold(0.0, f64::max);
    let rot: f64 = AxisName::ALL
        .iter()
        .filter(|n| n.kind() == AxisKind::Rotary)
        .map(|&n| (b.get(n) - a.get(n)).abs() * 1000.0)
        .sum();
    (((lin + rot) / GRID_MM).ceil() as usize).clamp(1, 50_000)
}

/// Replays `path` from `start` (module docs).
pub fn replay(chain: &Chain, start: &AxisValues, path: &[Waypoint], grid: &PartGrid) -> Clearance {
    let mut c = Clearance {
        min_rapid: FAR,
        min_rapid_certain: FAR,
        worst_rapid: 0,
        min_plate: f64::INFINITY,
        long_feed_moves_across: 0,
        min_axial_end: FAR,
        rapid_moves: 0,
        feed_moves: 0,
        samples: 0,
        sampling_bound: 0.5 * grid.cell_diagonal + 0.5 * GRID_MM,
    };
    let mut from = *start;
    for (k, w) in path.iter().enumerate() {
        let n = samples_of(chain, &from, &w.q);
        if w.rapid {
            c.rapid_moves += 1;
            for i in 0..=n {
                let q = between(chain, &from, &w.q, i as f64 / n as f64, w.interpolation);
                let d = wall_distance(chain, &q, grid, c.min_rapid).min(plate_height(chain, &q));
                if d < c.min_rapid {
                    c.min_rapid = d;
                    c.worst_rapid = k;
                }
                c.min_plate = c.min_plate.min(plate_height(chain, &q));
            }
            c.samples += n + 1;
        } else {
            c.feed_moves += 1;
            let (ta, tb) = (nominal(chain, &from, 0.0), nominal(chain, &w.q, 0.0));
            let d = tb.point - ta.point;
            // Off the axis by less than 1 µm (the words' rounding): along it.
            let along = d.cross(&ta.direction).norm() <= 1e-3
                && (tb.direction - ta.direction).norm() <= 1e-9;
            if d.norm() > crate::budget::discrete::MAX_PASS_STEP && !along {
                c.long_feed_moves_across += 1;
            }
            if along && d.norm() > crate::budget::discrete::MAX_PASS_STEP {
                let outer = if d.z > 0.0 { &w.q } else { &from };
                c.min_axial_end = c
                    .min_axial_end
                    .min(wall_distance(chain, outer, grid, FAR).min(plate_height(chain, outer)));
            }
            c.min_plate = c
                .min_plate
                .min(plate_height(chain, &from))
                .min(plate_height(chain, &w.q));
        }
        from = w.q;
    }
    c.min_rapid_certain = c.min_rapid - c.sampling_bound;
    c
}

/// The waypoints of a [`Motion`] as written in machine axes (the home retract left out: the
/// replay starts at [`Motion::start`]).
pub fn waypoints(m: &Motion) -> Vec<Waypoint> {
    m.steps
        .iter()
        .filter(|s| s.kind != StepKind::Home)
        .map(|s| Waypoint {
            q: s.q,
            rapid: s.kind == StepKind::Rapid,
            interpolation: Interpolation::MachineAxes,
        })
        .collect()
}
