//! The CMM probe's path between touches, and its replay against the part: where the straight
//! move from one touch to the next would pass near or through the walls, clearance moves
//! (`GOTO`) take the probe up and over.
//!
//! - **The probe** ([`TIP_DIAMETER`] = 4 mm ruby tip; stylus shaft Ø[`SHAFT_DIAMETER`] up to
//!   [`STYLUS_LENGTH`] from the tip centre along the stylus direction `w` of the touch,
//!   [`super::stylus`]: vertical, or tilted away from an overhanging wall): its position is
//!   the tip centre `c`. Where consecutive touches need different orientations, the probe goes
//!   up to [`INDEX_Z`] and the head is indexed there.
//! - **A touch** of the surface point `p` with outward normal `N`: the CMM moves in a straight
//!   line from where it is to the approach point `a = p + (r + d)·N` (`r` the tip radius, `d`
//!   the approach and retract distance [`APPROACH_DISTANCE`], DMIS `SNSET/APPRCH`, `RETRCT`),
//!   probes along `−N` and retracts to `a`. The moves along `N` are the measurement itself and
//!   are not checked.
//! - **The part**: both walls `S(u, v)` (paper 000 eq. 1) continued along their rulings down to
//!   the plate (`v` from [`PLATE_TOP_Z`]`/30` to 1: the stock under Z = 0 down to the plate),
//!   the top face and the two end faces (the segments from A(u, v) to B(u, v)), all sampled
//!   on a grid of at most [`GRID_MM`] mm; and the plate, a box (`fixture`).
//! - **A move between touches** from `a_k` to `a_{k+1}`: kept straight if the probe (tip
//!   sphere and shaft) stays at least [`PROBE_CLEARANCE`] plus the sampling bound from the
//!   part all along it; otherwise replaced by: out along the horizontal part of `N` by the
//!   smallest multiple of [`ESCAPE_STEP`] from which straight up is clear, up to the safe
//!   height [`SAFE_Z`], across, down the same way to the next approach point. The first touch
//!   is reached from [`SAFE_Z`] above it (the program starts with the probe at or above
//!   [`SAFE_Z`], where no straight move comes near the part: its top is at Z = 30), and the
//!   probe leaves the last one the same way.
//!
//! The distance found is to the sampled points at sampled positions; the true one is smaller
//! by at most [`ProbeReplay::sampling_bound`] (half the grid cell's diagonal plus half a step
//! of the move), which the reported `min_distance_certain` subtracts. Units: mm, part frame.

use nalgebra::Vector3;
use serde::Serialize;

use super::fixture::{PLATE_BOTTOM_Z, PLATE_HALF_X, PLATE_HALF_Y, PLATE_TOP_Z};
use super::stylus::Stylus;
use super::PlanError;
use crate::part::{SShape, Surface, HEIGHT};

/// Diameter of the probe's tip (mm).
pub const TIP_DIAMETER: f64 = 4.0;
/// Diameter of the stylus shaft (mm).
pub const SHAFT_DIAMETER: f64 = 2.5;
/// Length of the stylus from the tip centre to the probe body (mm).
pub const STYLUS_LENGTH: f64 = 50.0;
/// Approach and retract distance of a touch (mm): DMIS `SNSET/APPRCH` and `SNSET/RETRCT`.
pub const APPROACH_DISTANCE: f64 = 3.0;
/// The clearance every move between touches keeps from the part and the plate (mm).
pub const PROBE_CLEARANCE: f64 = 2.0;
/// Height of the tip centre (mm, part frame) of the clearance moves across the part.
pub const SAFE_Z: f64 = HEIGHT + 10.0;
/// Height of the tip centre (mm, part frame) where the head turns the stylus: a stylus
/// length above [`SAFE_Z`], so that the tip, swinging about the head, stays above [`SAFE_Z`].
pub const INDEX_Z: f64 = SAFE_Z + STYLUS_LENGTH;
/// Steps of the move out along the normal before going up (mm).
pub const ESCAPE_STEP: f64 = 1.0;
/// Longest move out along the normal tried (mm).
pub const MAX_ESCAPE: f64 = 40.0;
/// Largest spacing of the part's sample grid and of a move's samples (mm).
pub const GRID_MM: f64 = 0.5;
/// Distances beyond this (mm) are reported as this: nothing is near.
pub const FAR: f64 = 10.0;

/// One touch: the nominal surface point and its outward unit normal (mm, part frame), and the
/// stylus's orientation ([`Stylus::for_normal`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Touch {
    pub point: Vector3<f64>,
    pub normal: Vector3<f64>,
    pub stylus: Stylus,
}

impl Touch {
    /// The touch of `point` along `−normal`, the stylus oriented by [`Stylus::for_normal`].
    pub fn new(point: Vector3<f64>, normal: Vector3<f64>) -> Self {
        Touch {
            point,
            normal,
            stylus: Stylus::for_normal(&normal),
        }
    }

    /// The approach point `p + (r + d)·N` (tip centre, mm).
    pub fn approach_point(&self) -> Vector3<f64> {
        self.point + self.normal * (0.5 * TIP_DIAMETER + APPROACH_DISTANCE)
    }
}

/// Sample points with their bounding box (lowest, highest corner).
struct Tile {
    lo: Vector3<f64>,
    hi: Vector3<f64>,
    pts: Vec<Vector3<f64>>,
}

impl Tile {
    fn new(pts: Vec<Vector3<f64>>) -> Self {
        let (lo, hi) = pts.iter().fold(
            (
                Vector3::repeat(f64::INFINITY),
                Vector3::repeat(f64::NEG_INFINITY),
            ),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        Tile { lo, hi, pts }
    }
}

/// The part on its plate, sampled (module docs).
pub struct Obstacles {
    tiles: Vec<Tile>,
    cell_diagonal: f64,
}

/// Tiles of `TILE × TILE` grid cells.
const TILE: usize = 16;

impl Obstacles {
    /// The S-shape's walls, top and end faces down to the plate, and the plate.
    pub fn s_shape_on_plate() -> Self {
        let part = SShape::iso();
        let v0 = PLATE_TOP_Z / HEIGHT;
        let len = Surface::BOTH
            .iter()
            .flat_map(|&s| [part.curve_length(s, 0.0, 8), part.curve_length(s, 1.0, 8)])
            .fold(0.0, f64::max);
        // u is not arc length: the spline's speed varies about 4-fold along the S.
        let nu = (len / GRID_MM).ceil() as usize * 5;
        let nv = ((1.0 - v0) * HEIGHT * 1.25 / GRID_MM).ceil() as usize;
        let u_at = |i: usize| i as f64 / nu as f64;
        let v_at = |j: usize| v0 + (1.0 - v0) * j as f64 / nv as f64;
        let mut tiles = Vec::new();
        let mut diag = 0.0f64;
        // The walls: grid (u_i, v_j) per surface, in tiles; the curves evaluated once per u_i.
        let dv_max = (HEIGHT * (1.0 - v0) * 1.25) / nv as f64;
        let mut columns = Vec::new();
        for s in Surface::BOTH {
            let [c0, c1] = part.curves(s);
            let col: Vec<(Vector3<f64>, Vector3<f64>)> = (0..=nu)
                .map(|i| (c0.point_at(u_at(i)), c1.point_at(u_at(i))))
                .collect();
            let at = |i: usize, v: f64| col[i].0 * (1.0 - v) + col[i].1 * v;
            for i in 1..=nu {
                for v in [v0, 1.0] {
                    let du = (at(i, v) - at(i - 1, v)).norm();
                    diag = diag.max((du * du + dv_max * dv_max).sqrt());
                }
            }
            for i0 in (0..nu).step_by(TILE) {
                for j0 in (0..nv).step_by(TILE) {
                    let mut pts = Vec::new();
                    for i in i0..=(i0 + TILE).min(nu) {
                        for j in j0..=(j0 + TILE).min(nv) {
                            pts.push(at(i, v_at(j)));
                        }
                    }
                    tiles.push(Tile::new(pts));
                }
            }
            columns.push(col);
        }
        // The top face (v = 1) and the end faces (u = 0, 1): segments from A to B.
        let across = |i: usize, v: f64| {
            let (ca, cb) = (&columns[0][i], &columns[1][i]);
            let (a, b) = (ca.0 * (1.0 - v) + ca.1 * v, cb.0 * (1.0 - v) + cb.1 * v);
            let n = ((b - a).norm() / GRID_MM).ceil().max(1.0) as usize;
            (0..=n).map(move |k| a + (b - a) * (k as f64 / n as f64))
        };
        for i0 in (0..nu).step_by(TILE) {
            let pts = (i0..=(i0 + TILE).min(nu))
                .flat_map(|i| across(i, 1.0))
                .collect();
            tiles.push(Tile::new(pts));
        }
        for i in [0, nu] {
            for j0 in (0..nv).step_by(TILE) {
                let pts = (j0..=(j0 + TILE).min(nv))
                    .flat_map(|j| across(i, v_at(j)))
                    .collect();
                tiles.push(Tile::new(pts));
            }
        }
        Obstacles {
            tiles,
            cell_diagonal: diag.max(GRID_MM * std::f64::consts::SQRT_2),
        }
    }

    /// Largest error (mm) of a sampled distance: half the grid cell's diagonal and half a
    /// step of a move.
    pub fn sampling_bound(&self) -> f64 {
        0.5 * self.cell_diagonal + 0.5 * GRID_MM
    }

    /// Smallest distance (mm, at most `cap`) of the probe with its tip centre at `c` and its
    /// stylus along `w` (unit, up from the tip) from the part and the plate (negative: inside).
    pub fn probe_distance(&self, c: &Vector3<f64>, w: &Vector3<f64>, cap: f64) -> f64 {
        let r = 0.5 * TIP_DIAMETER;
        let rs = 0.5 * SHAFT_DIAMETER;
        let top = c + w * STYLUS_LENGTH;
        let mut best = cap
            .min(plate_distance(c) - r)
            .min(plate_distance(&top) - rs);
        let lo = c.inf(&top) - Vector3::repeat(r);
        let hi = c.sup(&top) + Vector3::repeat(r);
        for t in &self.tiles {
            let gap = Vector3::from_fn(|k, _| (t.lo[k] - hi[k]).max(lo[k] - t.hi[k]).max(0.0));
            if gap.norm() >= best {
                continue;
            }
            for p in &t.pts {
                let tip = (p - c).norm() - r;
                let s = (p - c).dot(w).clamp(0.0, STYLUS_LENGTH);
                let shaft = (p - (c + w * s)).norm() - rs;
                best = best.min(tip).min(shaft);
            }
        }
        best
    }

    /// Smallest distance (mm, at most [`FAR`]) over the straight move from `a` to `b` with the
    /// stylus `s`, sampled every [`GRID_MM`] at most; the number of samples.
    pub fn move_distance(&self, a: &Vector3<f64>, b: &Vector3<f64>, s: &Stylus) -> (f64, usize) {
        self.move_distance_until(a, b, s, f64::NEG_INFINITY)
    }

    /// [`Self::move_distance`], stopping at the first sample closer than `floor` (the move is
    /// then known not to keep `floor`; the distance returned is below it).
    fn move_distance_until(
        &self,
        a: &Vector3<f64>,
        b: &Vector3<f64>,
        s: &Stylus,
        floor: f64,
    ) -> (f64, usize) {
        let w = s.direction();
        let n = ((b - a).norm() / GRID_MM).ceil().max(1.0) as usize;
        let mut best = FAR;
        for k in 0..=n {
            let c = a + (b - a) * (k as f64 / n as f64);
            best = best.min(self.probe_distance(&c, &w, best));
            if best < floor {
                return (best, k + 1);
            }
        }
        (best, n + 1)
    }
}

/// Distance (mm) from `c` to the plate (a box; 0 inside).
fn plate_distance(c: &Vector3<f64>) -> f64 {
    let lo = Vector3::new(-PLATE_HALF_X, -PLATE_HALF_Y, PLATE_BOTTOM_Z);
    let hi = Vector3::new(PLATE_HALF_X, PLATE_HALF_Y, PLATE_TOP_Z);
    Vector3::from_fn(|k, _| (lo[k] - c[k]).max(c[k] - hi[k]).max(0.0)).norm()
}

/// What the replay of the probe path found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProbeReplay {
    /// Tip diameter (mm), stylus shaft diameter and length (mm).
    pub tip_diameter: f64,
    pub shaft_diameter: f64,
    pub stylus_length: f64,
    /// Approach and retract distance (mm).
    pub approach_distance: f64,
    /// The clearance required (mm).
    pub clearance: f64,
    /// Height of the tip centre over the part in the clearance moves (mm, part frame).
    pub safe_z: f64,
    /// Height of the tip centre where the head is indexed (mm, part frame).
    pub index_z: f64,
    /// Smallest distance (mm) of the probe from the part and plate over every move between
    /// touches (sampled; at most [`FAR`]).
    pub min_distance: f64,
    /// `min_distance − sampling_bound` (mm): what the moves certainly keep.
    pub min_distance_certain: f64,
    /// Index (0-based) of the touch the move reaching `min_distance` leads to (the number of
    /// touches: the move away from the last).
    pub worst_touch: usize,
    /// Moves between consecutive touches kept straight, and those replaced by clearance moves.
    pub straight_moves: usize,
    pub cleared_moves: usize,
    /// `GOTO` statements written.
    pub gotos: usize,
    /// Changes of the stylus's orientation between touches.
    pub index_changes: usize,
    /// Positions sampled.
    pub samples: usize,
    /// Largest error (mm) of the sampled distance (module docs).
    pub sampling_bound: f64,
}

/// One step of the path between touches: a `GOTO` (tip centre, mm, part frame) or the head
/// indexed to a stylus orientation (`SNSLCT`), done at [`INDEX_Z`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PathStep {
    Goto(Vector3<f64>),
    Index(Stylus),
}

/// The probe path: the steps before each touch and after the last, and its replay.
#[derive(Debug, Clone, PartialEq)]
pub struct ProbePath {
    pub before: Vec<Vec<PathStep>>,
    pub after: Vec<PathStep>,
    pub replay: ProbeReplay,
}

/// The positions of the way up from the approach point of `t`: out along the horizontal part
/// of the normal by `e`, then up to [`SAFE_Z`]; `e` the smallest multiple of [`ESCAPE_STEP`]
/// for which both moves are clear by `need`. With the smallest distance found on them.
fn way_up(
    obs: &Obstacles,
    t: &Touch,
    need: f64,
    samples: &mut usize,
) -> Option<(Vec<Vector3<f64>>, f64)> {
    let a = t.approach_point();
    let h = Vector3::new(t.normal.x, t.normal.y, 0.0);
    let h = if h.norm() > 1e-9 {
        h.normalize()
    } else {
        Vector3::zeros()
    };
    let steps = (MAX_ESCAPE / ESCAPE_STEP).round() as usize;
    for k in 0..=steps {
        let out = a + h * (k as f64 * ESCAPE_STEP);
        let up = Vector3::new(out.x, out.y, SAFE_Z.max(out.z));
        let (d1, n1) = obs.move_distance_until(&a, &out, &t.stylus, need);
        *samples += n1;
        if d1 < need {
            continue;
        }
        let (d2, n2) = obs.move_distance_until(&out, &up, &t.stylus, need);
        *samples += n2;
        if d1.min(d2) >= need {
            let way = if k == 0 { vec![up] } else { vec![out, up] };
            return Some((way, d1.min(d2)));
        }
    }
    None
}

/// The probe path through `touches` in their order (module docs). `ids` name the touches in
/// errors (the plan's point ids).
pub fn probe_path(
    obs: &Obstacles,
    touches: &[Touch],
    ids: &[usize],
) -> Result<ProbePath, PlanError> {
    let bound = obs.sampling_bound();
    let need = PROBE_CLEARANCE + bound;
    let mut r = ProbeReplay {
        tip_diameter: TIP_DIAMETER,
        shaft_diameter: SHAFT_DIAMETER,
        stylus_length: STYLUS_LENGTH,
        approach_distance: APPROACH_DISTANCE,
        clearance: PROBE_CLEARANCE,
        safe_z: SAFE_Z,
        index_z: INDEX_Z,
        min_distance: FAR,
        min_distance_certain: FAR,
        worst_touch: 0,
        straight_moves: 0,
        cleared_moves: 0,
        gotos: 0,
        index_changes: 0,
        samples: 0,
        sampling_bound: bound,
    };
    let note = |r: &mut ProbeReplay, d: f64, k: usize| {
        if d < r.min_distance {
            r.min_distance = d;
            r.worst_touch = k;
        }
    };
    let id = |k: usize| ids.get(k).copied().unwrap_or(k + 1);
    let stuck = |k: usize| PlanError::ProbeNoWayUp {
        id: id(k),
        escape: MAX_ESCAPE,
        clearance: PROBE_CLEARANCE,
    };
    let high = |p: &Vector3<f64>| Vector3::new(p.x, p.y, INDEX_Z);
    let mut before = Vec::with_capacity(touches.len());
    let mut samples = 0;
    let mut ways: Vec<Option<(Vec<Vector3<f64>>, f64)>> = vec![None; touches.len()];
    let mut way = |k: usize, samples: &mut usize| -> Result<(Vec<Vector3<f64>>, f64), PlanError> {
        if ways[k].is_none() {
            ways[k] = Some(way_up(obs, &touches[k], need, samples).ok_or(stuck(k))?);
        }
        Ok(ways[k].clone().unwrap_or_default())
    };
    for (k, t) in touches.iter().enumerate() {
        let b = t.approach_point();
        if let Some(prev) = k.checked_sub(1).map(|j| &touches[j]) {
            if prev.stylus == t.stylus {
                let (d, n) = obs.move_distance_until(&prev.approach_point(), &b, &t.stylus, need);
                samples += n;
                if d >= need {
                    r.straight_moves += 1;
                    note(&mut r, d, k);
                    before.push(Vec::new());
                    continue;
                }
            }
        }
        let (mut down, db) = way(k, &mut samples)?;
        down.reverse();
        let mut steps: Vec<PathStep> = Vec::new();
        let mut worst = db;
        match k.checked_sub(1).map(|j| &touches[j]) {
            Some(prev) if prev.stylus == t.stylus => {
                r.cleared_moves += 1;
                let (up, da) = way(k - 1, &mut samples)?;
                let (top_a, top_b) = (up[up.len() - 1], down[0]);
                let (dt, n) = obs.move_distance(&top_a, &top_b, &t.stylus);
                samples += n;
                if dt < need {
                    return Err(PlanError::ProbeMove {
                        from: id(k - 1),
                        to: id(k),
                        distance: dt,
                        clearance: PROBE_CLEARANCE,
                    });
                }
                worst = worst.min(da).min(dt);
                steps.extend(up.into_iter().map(PathStep::Goto));
            }
            Some(_) => {
                // Another stylus: up to the indexing height, index there.
                r.cleared_moves += 1;
                let (up, da) = way(k - 1, &mut samples)?;
                worst = worst.min(da);
                let top = up[up.len() - 1];
                steps.extend(up.into_iter().map(PathStep::Goto));
                steps.push(PathStep::Goto(high(&top)));
                steps.push(PathStep::Goto(high(&down[0])));
                steps.push(PathStep::Index(t.stylus));
                r.index_changes += 1;
            }
            None => {
                steps.push(PathStep::Goto(high(&down[0])));
                steps.push(PathStep::Index(t.stylus));
            }
        }
        note(&mut r, worst, k);
        steps.extend(down.into_iter().map(PathStep::Goto));
        before.push(steps);
    }
    let after = match touches.last() {
        Some(_) => {
            let (up, d) = way(touches.len() - 1, &mut samples)?;
            note(&mut r, d, touches.len());
            up.into_iter().map(PathStep::Goto).collect()
        }
        None => Vec::new(),
    };
    let gotos = |v: &[PathStep]| v.iter().filter(|s| matches!(s, PathStep::Goto(_))).count();
    r.gotos = before.iter().map(|v| gotos(v)).sum::<usize>() + gotos(&after);
    r.samples = samples;
    r.min_distance_certain = r.min_distance - bound;
    Ok(ProbePath {
        before,
        after,
        replay: r,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The probe's distance from the plate's top, far from the walls, is the tip's height
    /// above it less its radius.
    #[test]
    fn distance_above_the_plate() {
        let obs = Obstacles::s_shape_on_plate();
        let c = Vector3::new(150.0, -110.0, PLATE_TOP_Z + 5.0);
        let d = obs.probe_distance(&c, &Vector3::z(), FAR);
        assert!((d - (5.0 - 0.5 * TIP_DIAMETER)).abs() < 1e-12, "{d}");
    }

    /// A straight move through the middle of the S is not clear; the path goes over it.
    #[test]
    fn a_move_through_the_wall_is_replaced() {
        let obs = Obstacles::s_shape_on_plate();
        let part = SShape::iso();
        let touch = |s: Surface| {
            let f = part.frame_at(s, 0.5, 11.0 / HEIGHT);
            Touch::new(part.point_at(s, 0.5, 11.0 / HEIGHT), f.n)
        };
        let (a, b) = (touch(Surface::A), touch(Surface::B));
        let (d, _) = obs.move_distance(&a.approach_point(), &b.approach_point(), &a.stylus);
        assert!(d < 0.0, "{d}");
        let p = probe_path(&obs, &[a, b], &[1, 2]).unwrap();
        assert_eq!(p.replay.cleared_moves, 1);
        assert!(p.replay.min_distance_certain >= PROBE_CLEARANCE);
        assert!(p.before[1]
            .iter()
            .any(|g| matches!(g, PathStep::Goto(g) if g.z == SAFE_Z)));
    }
}
