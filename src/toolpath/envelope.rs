//! The machined surface as the envelope of the cylindrical tool along the flank path, and the
//! deviation it leaves at any surface point (paper 000 §3.1 eq. 3-5, §4.1 Fig. 13).
//!
//! **Method (Fig. 13, made exact).** At a surface point `P` with outward normal `N`, the line
//! `P + t·N` is intersected with the tool at path parameter `u'` (a solid cylinder of radius `ρ`
//! standing on its tip `E(u')` with axis `w(u') = R(u')`, eq. 2). With `a = P - E` and `x⊥` the
//! part of `x` perpendicular to `w`, the line enters the lateral surface at the smaller root of
//! `|a⊥ + t·N⊥|² = ρ²`; the flat end `h = (a + tN)·w ≥ 0` is respected. The machined surface
//! along the line is where the first tool enters, so
//!
//! `deviation(P) = min over u' ∈ [0,1] of t_enter(u')`   (mm; + material left, - overcut).
//!
//! The paper samples `u'` with a step < 0.1 mm (error ≈ step²/8R, eq. 7); here `t_enter` is
//! scanned on a table of 4000 poses near `P` and the minimum is then refined by Brent's method
//! on the exact pose of eq. 2 to a `u'` bracket of 1e-8 ([`BRENT_U_TOL`]; golden section to 1e-12
//! before issue 31: the same depths to 1e-14 mm), so the result does not depend on a path step
//! (its error is far below 1e-9 mm). At the minimiser `∂t_enter/∂u' = 0`, which is the
//! envelope condition eq. 5, `(dT_tool/du + h·dR/du)·n_M = 0` at the contact point `M`, with `n_M`
//! the tool's radial normal and `h` the height of `M` above the tip; the tests check it.
//!
//! A tool-radius error `dR` (radius `10 + dR`, path unchanged) shifts the deviation by about `-dR`
//! (exactly `-dR` times a factor 1/cos of the small angle between `N` and `n_M`): a larger tool
//! overcuts.

use nalgebra::Vector3;
use serde::Serialize;

use super::flank::{tool_pose, tool_pose_derivs, ToolPose, TOOL_RADIUS};
use super::ToolpathError;
use crate::numerics::order::sort_by_key_f64;
use crate::part::{builtin_points, Curve, MeasurementPoint, RuledPart, SShape, Surface, HEIGHT};

/// Number of intervals of the pose table (`u'` step 1/4000, about 0.17 mm of path).
const TABLE_STEPS: usize = 4000;
/// Half-width of the `u'` window first scanned around the point's own `u` for any tool shape
/// ([`FlankPath::deviation_with`]), widened while the deepest pose sits on its edge.
const WINDOW: f64 = 0.02;
/// The first window of the cylinder's scan ([`FlankPath::deviation_at`],
/// [`FlankPath::deviation_estimate`]: 41 table poses, 20 steps either side), widened as
/// [`WINDOW`] is and, where no pose in it reaches the point, to [`WINDOW`]. The deepest table
/// pose lies within 7 steps of the point's own `u` on the S-shape and on it on the cones (1.48 M
/// points of the S-shape, 0.5 M of M3_15 and M3_45: `u` every table step, `v` −0.1..1.1, 0.1 mm
/// either side of the surface): this window and [`WINDOW`] find the same pose at every one of
/// them, so the same deviations (161 poses a point had been 3 % of a 200,000-point scan's CPU,
/// issue 31).
const CYLINDER_WINDOW: f64 = 0.005;
/// Brent's stop ([`brent_min`]) in [`FlankPath::deviation_with`]: the `u'` bracket about the
/// best pose, 1.7e-7 mm of path. Function values locate a minimum only to ~√ε relative (1e-8
/// in `u'`), where Brent's parabolas turn to noise and fall back to golden steps; the depth at
/// the minimum is flat to second order: 1.7e-7 mm off it changes it by ~(1.7e-7)²/2ρ ≈ 1e-15
/// mm.
pub const BRENT_U_TOL: f64 = 1e-8;
/// Golden-section stop of the surface-maximum search in `u` and `v` (the deviation is flat to
/// second order there, so this locates its value to ~1e-12 mm).
const SEARCH_TOL: f64 = 1e-7;

/// The interval of `t` where the line `p + t·n` is inside the infinite cylinder of radius
/// `radius` around the axis of `pose`, or `None` when it misses it.
pub fn cylinder_interval(
    pose: &ToolPose,
    radius: f64,
    p: &Vector3<f64>,
    n: &Vector3<f64>,
) -> Option<(f64, f64)> {
    // Plain scalar arithmetic (this is the inner loop of every envelope scan):
    // a⊥·n⊥ = a·n - (a·w)(n·w), |a⊥|² = |a|² - (a·w)², |n⊥|² = |n|² - (n·w)².
    let (w, tip) = (&pose.axis, &pose.tip);
    let a = [p.x - tip.x, p.y - tip.y, p.z - tip.z];
    let aw = a[0] * w.x + a[1] * w.y + a[2] * w.z;
    let nw = n.x * w.x + n.y * w.y + n.z * w.z;
    let an = a[0] * n.x + a[1] * n.y + a[2] * n.z;
    let aa = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    let nn = n.x * n.x + n.y * n.y + n.z * n.z;
    let qa = nn - nw * nw;
    let qb = an - aw * nw;
    let qc = aa - aw * aw - radius * radius;
    if qa < 1e-300 {
        return (qc <= 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY));
    }
    let disc = qb * qb - qa * qc;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    // numerically stable roots of qa t² + 2 qb t + qc = 0
    let q = -(qb + sq.copysign(qb));
    let (r1, r2) = if q != 0.0 {
        (q / qa, qc / q)
    } else {
        (0.0, 0.0)
    };
    Some((r1.min(r2), r1.max(r2)))
}

/// Where the line `P + tN` first enters the solid cylinder of radius `radius` standing on
/// `pose.tip` (heights `h ≥ 0` along `pose.axis`), or `None` when it misses it.
pub fn line_entry(pose: &ToolPose, radius: f64, p: &Vector3<f64>, n: &Vector3<f64>) -> Option<f64> {
    let (mut lo, mut hi) = cylinder_interval(pose, radius, p, n)?;
    // flat end: h(t) = a·w + t n·w ≥ 0
    let w = pose.axis;
    let (h0, dh) = ((p - pose.tip).dot(&w), n.dot(&w));
    if dh.abs() < 1e-300 {
        if h0 < 0.0 {
            return None;
        }
    } else if dh > 0.0 {
        lo = lo.max(-h0 / dh);
    } else {
        hi = hi.min(-h0 / dh);
    }
    (lo <= hi && lo.is_finite()).then_some(lo)
}

/// The tool poses at `u' = i/`[`TABLE_STEPS`], `i = 0..=TABLE_STEPS` (eq. 2): the scan table of
/// a [`FlankPath`].
pub fn pose_table(part: &dyn RuledPart, s: Surface) -> Vec<ToolPose> {
    (0..=TABLE_STEPS)
        .map(|i| tool_pose(part, s, i as f64 / TABLE_STEPS as f64))
        .collect()
}

/// The flank path of one surface with a table of poses for the scan.
#[derive(Debug, Clone)]
pub struct FlankPath<'a> {
    part: &'a dyn RuledPart,
    surface: Surface,
    table: std::borrow::Cow<'a, [ToolPose]>,
}

/// The deepest cut at a point and the tool position that makes it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnvelopeHit {
    /// `(machined - nominal)·N` (mm): + material left, - overcut
    pub deviation: f64,
    /// path parameter `u'` of the tool position that cuts deepest
    pub u_tool: f64,
    /// height of the contact point `M = P + deviation·N` above that tool's tip (mm)
    pub height: f64,
}

impl<'a> FlankPath<'a> {
    /// The eq. 2 path of surface `s` (the S-shape's, or any other [`RuledPart`]'s).
    pub fn new(part: &'a dyn RuledPart, s: Surface) -> Self {
        Self {
            part,
            surface: s,
            table: pose_table(part, s).into(),
        }
    }

    /// The path with its table already computed: `table` must be [`pose_table`] of the same
    /// part and surface (it depends on nothing else, so it can be kept between files).
    pub fn with_table(part: &'a dyn RuledPart, s: Surface, table: &'a [ToolPose]) -> Self {
        Self {
            part,
            surface: s,
            table: table.into(),
        }
    }

    pub fn surface(&self) -> Surface {
        self.surface
    }
    pub fn part(&self) -> &'a dyn RuledPart {
        self.part
    }

    /// Scans the pose table around `u_near` (window ±`half`, doubled while the minimum sits on
    /// its edge, and while no pose reaches the point until it is [`WINDOW`]): index of the
    /// deepest table pose and the entries at it and its two neighbours.
    fn scan<F: Fn(&ToolPose) -> Option<f64> + ?Sized>(
        &self,
        p: &Vector3<f64>,
        u_near: f64,
        entry: &F,
        mut half: f64,
    ) -> Result<(usize, [Option<f64>; 3]), ToolpathError> {
        let entry = |i: usize| entry(&self.table[i]);
        loop {
            let lo_i = ((u_near - half).max(0.0) * TABLE_STEPS as f64).floor() as usize;
            let hi_i =
                (((u_near + half).min(1.0) * TABLE_STEPS as f64).ceil() as usize).min(TABLE_STEPS);
            let mut best: Option<(usize, f64)> = None;
            for i in lo_i..=hi_i {
                if let Some(t) = entry(i) {
                    if best.is_none_or(|(_, b)| t < b) {
                        best = Some((i, t));
                    }
                }
            }
            let Some((k, t)) = best else {
                if half < WINDOW {
                    half *= 2.0;
                    continue;
                }
                return Err(ToolpathError::NoToolReaches {
                    x: p.x,
                    y: p.y,
                    z: p.z,
                });
            };
            let on_edge = (k == lo_i && lo_i > 0) || (k == hi_i && hi_i < TABLE_STEPS);
            if on_edge && half < 0.5 {
                half *= 2.0;
                continue;
            }
            let prev = if k > 0 { entry(k - 1) } else { None };
            let next = if k < TABLE_STEPS { entry(k + 1) } else { None };
            return Ok((k, [prev, Some(t), next]));
        }
    }

    /// Deviation along `n` at `p` for a cylinder of radius `radius` (mm): the table scan, then
    /// Brent refinement ([`brent_min`]) on the exact poses between the neighbours of the best one.
    pub fn deviation_at(
        &self,
        p: &Vector3<f64>,
        n: &Vector3<f64>,
        u_near: f64,
        radius: f64,
    ) -> Result<EnvelopeHit, ToolpathError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(ToolpathError::BadRadius { radius });
        }
        let entry = |pose: &ToolPose| line_entry(pose, radius, p, n);
        self.deviation_from(p, n, u_near, &entry, CYLINDER_WINDOW)
    }

    /// The deepest entry of the line `p + t·n` into the tools of this path, for any tool shape:
    /// `entry(pose)` gives where the line enters the tool at that pose (or `None`). `u_near` is
    /// the path parameter around which to scan (the point's own `u`, first ±[`WINDOW`] about
    /// it). Generic over the entry, so the cylinder's ([`FlankPath::deviation_at`]) is inlined in
    /// the scan of the table poses, the envelope's inner loop (through a `dyn Fn` the envelope
    /// had been 5.7 % of a 20,000-point scan's CPU, inlined 3.1 %, issue 31); a `&dyn Fn` is
    /// taken too.
    pub fn deviation_with<F: Fn(&ToolPose) -> Option<f64> + ?Sized>(
        &self,
        p: &Vector3<f64>,
        n: &Vector3<f64>,
        u_near: f64,
        entry: &F,
    ) -> Result<EnvelopeHit, ToolpathError> {
        self.deviation_from(p, n, u_near, entry, WINDOW)
    }

    /// [`Self::deviation_with`], the scan's first window ±`half`.
    fn deviation_from<F: Fn(&ToolPose) -> Option<f64> + ?Sized>(
        &self,
        p: &Vector3<f64>,
        n: &Vector3<f64>,
        u_near: f64,
        entry: &F,
        half: f64,
    ) -> Result<EnvelopeHit, ToolpathError> {
        let (k, _) = self.scan(p, u_near, entry, half)?;
        let at = |u: f64| entry(&tool_pose(self.part, self.surface, u));
        let step = 1.0 / TABLE_STEPS as f64;
        let a = (k as f64 - 1.0).max(0.0) * step;
        let b = ((k as f64 + 1.0) * step).min(1.0);
        let (u, t) = brent_min(&|u| at(u).unwrap_or(f64::INFINITY), a, b, BRENT_U_TOL);
        let pose = tool_pose(self.part, self.surface, u);
        let height = (p + n * t - pose.tip).dot(&pose.axis);
        Ok(EnvelopeHit {
            deviation: t,
            u_tool: u,
            height,
        })
    }

    /// A fast estimate of [`FlankPath::deviation_at`]'s deviation: the table minimum improved by
    /// a parabola through it and its neighbours (error ≪ step²/8ρ ≈ 4e-4 mm, eq. 7); for searches.
    pub fn deviation_estimate(
        &self,
        p: &Vector3<f64>,
        n: &Vector3<f64>,
        u_near: f64,
        radius: f64,
    ) -> Result<f64, ToolpathError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(ToolpathError::BadRadius { radius });
        }
        let entry = |pose: &ToolPose| line_entry(pose, radius, p, n);
        let (_, [prev, t, next]) = self.scan(p, u_near, &entry, CYLINDER_WINDOW)?;
        let t = t.unwrap_or(f64::INFINITY);
        Ok(match (prev, next) {
            (Some(a), Some(c)) if a + c - 2.0 * t > 0.0 => {
                t - (c - a).powi(2) / (8.0 * (a + c - 2.0 * t))
            }
            _ => t,
        })
    }

    /// Deviation at the surface point `S(u, v)` along its outward normal, tool radius `radius`.
    pub fn deviation_at_uv(
        &self,
        u: f64,
        v: f64,
        radius: f64,
    ) -> Result<EnvelopeHit, ToolpathError> {
        let f = self.part.frame_at(self.surface, u, v);
        self.deviation_at(&f.point, &f.n, u, radius)
    }
}

/// Golden-section minimum of `f` on `[a, b]`: `(argmin, min)`; the ends are candidates too.
pub(crate) fn golden_min(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> (f64, f64) {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (fa0, fb0, a0, b0) = (f(a), f(b), a, b);
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    while (b - a) > tol {
        if fc <= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    let best = if fc <= fd { (c, fc) } else { (d, fd) };
    lowest_with_ends(best, [(a0, fa0), (b0, fb0)])
}

/// `best`, or an end of the interval whose value is lower (the minimisers' last step).
fn lowest_with_ends(best: (f64, f64), ends: [(f64, f64); 2]) -> (f64, f64) {
    ends.into_iter()
        .fold(best, |b, cand| if cand.1 < b.1 { cand } else { b })
}

/// Brent's minimum of `f` on `[a, b]` (R. P. Brent, *Algorithms for Minimization without
/// Derivatives*, 1973, ch. 5): golden-section steps where a parabola through the three best
/// points is not trusted, the parabola's vertex where it is; stops when the bracket about the
/// best point is within `tol`; `(argmin, min)`, the ends candidates too. On the envelope's
/// smooth depth it takes 9-16 evaluations of `f` where [`golden_min`] takes ~62 to 1e-12 (a
/// dense scan's 20,000 points, issue 31; the unit test); a non-finite value (the line misses the
/// tool) forces a golden step.
pub(crate) fn brent_min(f: &impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> (f64, f64) {
    const G: f64 = 0.381_966_011_250_105_1; // (3 − √5)/2
    let (fa0, fb0, a0, b0) = (f(a), f(b), a, b);
    let (mut lo, mut hi) = (a, b);
    let mut x = lo + G * (hi - lo);
    let mut fx = f(x);
    let (mut w, mut fw, mut v, mut fv) = (x, fx, x, fx);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    let tol1 = 0.5 * tol;
    let tol2 = tol;
    loop {
        let m = 0.5 * (lo + hi);
        if (x - m).abs() <= tol2 - 0.5 * (hi - lo) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 {
            let r = (x - w) * (fx - fv);
            let q0 = (x - v) * (fx - fw);
            let mut p = (x - v) * q0 - (x - w) * r;
            let mut q = 2.0 * (q0 - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            let last = e;
            e = d;
            if p.is_finite()
                && q.is_finite()
                && p.abs() < (0.5 * q * last).abs()
                && p > q * (lo - x)
                && p < q * (hi - x)
            {
                d = p / q;
                let u = x + d;
                if u - lo < tol2 || hi - u < tol2 {
                    d = tol1.copysign(m - x);
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= m { lo - x } else { hi - x };
            d = G * e;
        }
        let u = if d.abs() >= tol1 {
            x + d
        } else {
            x + tol1.copysign(d)
        };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                lo = x;
            } else {
                hi = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                lo = u;
            } else {
                hi = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    lowest_with_ends((x, fx), [(a0, fa0), (b0, fb0)])
}

/// The envelope deviation at one built-in point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PointDeviation {
    pub id: usize,
    pub curve: Curve,
    /// mm, + material left, - overcut
    pub deviation: f64,
}

/// Deviation of the flank path at the given points for a tool of radius `TOOL_RADIUS + d_r`.
pub fn points_deviation(
    part: &SShape,
    points: &[MeasurementPoint],
    d_r: f64,
) -> Result<Vec<PointDeviation>, ToolpathError> {
    let paths = [
        FlankPath::new(part, Surface::A),
        FlankPath::new(part, Surface::B),
    ];
    points_deviation_on(&paths, points, d_r)
}

/// [`points_deviation`] on the flank paths of A and B (in that order).
pub fn points_deviation_on(
    paths: &[FlankPath; 2],
    points: &[MeasurementPoint],
    d_r: f64,
) -> Result<Vec<PointDeviation>, ToolpathError> {
    points
        .iter()
        .map(|p| {
            let path = &paths[p.surface.index()];
            let hit = path.deviation_at(&p.point, &p.normal, p.u, TOOL_RADIUS + d_r)?;
            Ok(PointDeviation {
                id: p.id,
                curve: p.curve,
                deviation: hit.deviation,
            })
        })
        .collect()
}

/// Deviation of the nominal flank path (eq. 2, radius 10 mm) at the 100 built-in points.
pub fn builtin_envelope(part: &SShape) -> Result<Vec<PointDeviation>, ToolpathError> {
    points_deviation(part, &builtin_points(part), 0.0)
}

/// The largest overcut over a whole surface (Z 0..30) and where it is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SurfaceMax {
    pub surface: Surface,
    /// largest overcut, as a positive number (mm) = -min deviation
    pub max_overcut: f64,
    pub u: f64,
    /// height of the point (mm)
    pub z: f64,
}

/// Largest overcut of the flank path on surface `s` over `u ∈ [0,1]`, `Z ∈ [0, 30]`.
///
/// A grid of 501 × 11 points is searched with [`FlankPath::deviation_estimate`]; the best 4 local
/// minima are refined on the exact deviation by alternating golden-section searches in `u` (±2 grid
/// steps) and `v` (±2 grid steps within [0, 1]) until they move less than 1e-6.
pub fn surface_max_overcut(part: &SShape, s: Surface) -> Result<SurfaceMax, ToolpathError> {
    const NU: usize = 500;
    const NV: usize = 10;
    const CANDIDATES: usize = 4;
    let path = FlankPath::new(part, s);
    let exact = |u: f64, v: f64| {
        path.deviation_at_uv(u, v, TOOL_RADIUS)
            .map(|h| h.deviation)
            .unwrap_or(f64::INFINITY)
    };
    let estimate = |u: f64, v: f64| {
        let f = part.frame_at(s, u, v);
        path.deviation_estimate(&f.point, &f.n, u, TOOL_RADIUS)
            .unwrap_or(f64::INFINITY)
    };
    let mut grid = vec![vec![0.0; NV + 1]; NU + 1];
    for (i, row) in grid.iter_mut().enumerate() {
        for (j, d) in row.iter_mut().enumerate() {
            *d = estimate(i as f64 / NU as f64, j as f64 / NV as f64);
        }
    }
    // local minima of the deviation on the grid
    let mut cands = Vec::new();
    for i in 0..=NU {
        for j in 0..=NV {
            let d = grid[i][j];
            let mut is_min = d.is_finite();
            for (di, dj) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
                let (ii, jj) = (i as i64 + di, j as i64 + dj);
                if ii >= 0 && ii <= NU as i64 && jj >= 0 && jj <= NV as i64 {
                    is_min &= d <= grid[ii as usize][jj as usize];
                }
            }
            if is_min {
                cands.push((d, i, j));
            }
        }
    }
    sort_by_key_f64(&mut cands, |c| c.0);
    cands.truncate(CANDIDATES);
    let (du, dv) = (1.0 / NU as f64, 1.0 / NV as f64);
    let mut best = (f64::INFINITY, 0.0, 0.0);
    for &(_, i, j) in &cands {
        let (mut u, mut v) = (i as f64 * du, j as f64 * dv);
        let (u_lo, u_hi) = ((u - 2.0 * du).max(0.0), (u + 2.0 * du).min(1.0));
        let (v_lo, v_hi) = ((v - 2.0 * dv).max(0.0), (v + 2.0 * dv).min(1.0));
        let mut d = exact(u, v);
        for _ in 0..30 {
            let (u_new, _) = golden_min(&|x| exact(x, v), u_lo, u_hi, SEARCH_TOL);
            let (v_new, d_new) = golden_min(&|y| exact(u_new, y), v_lo, v_hi, SEARCH_TOL);
            let moved = (u_new - u).abs() + (v_new - v).abs();
            (u, v, d) = (u_new, v_new, d_new);
            if moved < 10.0 * SEARCH_TOL {
                break;
            }
        }
        if d < best.0 {
            best = (d, u, v);
        }
    }
    if !best.0.is_finite() {
        return Err(ToolpathError::NoToolReaches {
            x: f64::NAN,
            y: f64::NAN,
            z: f64::NAN,
        });
    }
    Ok(SurfaceMax {
        surface: s,
        max_overcut: -best.0,
        u: best.1,
        z: best.2 * HEIGHT,
    })
}

/// Residual of the envelope condition eq. 5 at a hit: `(dT_tool/du + h·dR/du)·n_M` (mm), with
/// `n_M` the tool's radial unit normal at the contact point `M = p + deviation·n`. It is 0 (to
/// rounding) when the hit is on the envelope rather than at an end of the path.
pub fn envelope_condition<P: RuledPart + ?Sized>(
    part: &P,
    s: Surface,
    p: &Vector3<f64>,
    n: &Vector3<f64>,
    hit: &EnvelopeHit,
) -> f64 {
    let d = tool_pose_derivs(part, s, hit.u_tool);
    let m = p + n * hit.deviation;
    let rel = m - d.pose.tip;
    let h = rel.dot(&d.pose.axis);
    let n_m = (rel - d.pose.axis * h).normalize();
    (d.tip_u + d.axis_u * h).dot(&n_m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn line_entry_closed_form() {
        // vertical cylinder radius 2 on the origin, line along +x from (-5, 0, 1): enters at t = 3
        let pose = ToolPose {
            tip: Vector3::zeros(),
            axis: Vector3::z(),
        };
        let t = line_entry(&pose, 2.0, &Vector3::new(-5.0, 0.0, 1.0), &Vector3::x()).unwrap();
        assert_near!(t, 3.0, 1e-14);
        // below the tip: misses
        assert!(line_entry(&pose, 2.0, &Vector3::new(-5.0, 0.0, -1.0), &Vector3::x()).is_none());
        // slanted line through the flat end: (0,0,-1) + t(0,0.6,0.8)/1 enters at h = 0, t = 1.25
        let t = line_entry(
            &pose,
            2.0,
            &Vector3::new(0.0, 0.0, -1.0),
            &Vector3::new(0.0, 0.6, 0.8),
        )
        .unwrap();
        assert_near!(t, 1.25, 1e-14);
    }

    #[test]
    fn golden_finds_parabola_minimum() {
        let (x, f) = golden_min(&|x: f64| (x - 0.3).powi(2) + 1.0, 0.0, 1.0, 1e-12);
        // function values alone locate a minimum to about sqrt(machine epsilon)
        assert_near!(x, 0.3, 1e-7);
        assert_near!(f, 1.0, 1e-15);
    }

    /// Brent's method to [`BRENT_U_TOL`] finds what golden section finds to 1e-12 (the minimum's
    /// location to 1e-7, its value to 1e-12 relative: 1e-14 mm), on functions scaled as the envelope's
    /// depth (curvature ~1e3 mm per unit `u'`², depth ~1e-2 mm): a parabola, an asymmetric
    /// smooth function (`1e3·(cosh(x − 0.7) − 1) + x³`), a function infinite on part of the
    /// interval, and a minimum at an end (where Brent falls back to golden steps); in at most
    /// half golden's evaluations for an interior minimum.
    #[test]
    fn brent_finds_what_golden_finds() {
        use std::cell::Cell;
        type Case<'a> = (&'a dyn Fn(f64) -> f64, f64, f64, bool);
        let cases: [Case; 4] = [
            (&|x: f64| 1e3 * (x - 0.3).powi(2) + 0.01, 0.0, 1.0, true),
            (
                &|x: f64| 1e3 * ((x - 0.7).cosh() - 1.0) + x.powi(3),
                -1.0,
                2.0,
                true,
            ),
            (
                &|x: f64| {
                    if x < 0.45 {
                        f64::INFINITY
                    } else {
                        1e3 * (x - 0.5).powi(2) + 0.02
                    }
                },
                0.0,
                1.0,
                true,
            ),
            (&|x: f64| x, 0.2, 0.9, false),
        ];
        for (f, a, b, interior) in cases {
            let (ng, nb) = (Cell::new(0), Cell::new(0));
            let g = golden_min(
                &|x| {
                    ng.set(ng.get() + 1);
                    f(x)
                },
                a,
                b,
                1e-12,
            );
            let r = brent_min(
                &|x| {
                    nb.set(nb.get() + 1);
                    f(x)
                },
                a,
                b,
                BRENT_U_TOL,
            );
            assert!((g.0 - r.0).abs() < 1e-7, "{g:?} vs {r:?}");
            assert!(
                (g.1 - r.1).abs() <= 1e-12 * g.1.abs().max(1e-2),
                "{g:?} vs {r:?}"
            );
            if interior {
                assert!(2 * nb.get() <= ng.get(), "{} vs {}", nb.get(), ng.get());
            }
        }
    }

    /// The characteristic point of eq. 5 at tool position `u'` and height `h`:
    /// `M = E + h·w + ρ·n_M`, `n_M ⊥ w`, `(T_tool' + h·R')·n_M = 0`, `n_M` facing the part
    /// (`n_M·N < 0`).
    fn characteristic_point(
        part: &SShape,
        s: Surface,
        u: f64,
        h: f64,
        n_part: &Vector3<f64>,
    ) -> Vector3<f64> {
        let d = tool_pose_derivs(part, s, u);
        let w = d.pose.axis;
        let q = d.tip_u + d.axis_u * h;
        let mut n_m = w.cross(&(q - w * q.dot(&w))).normalize();
        if n_m.dot(n_part) > 0.0 {
            n_m = -n_m;
        }
        d.pose.tip + w * h + n_m * TOOL_RADIUS
    }

    #[test]
    fn deviation_equals_the_characteristic_curve_of_eq5() {
        // Independent check of the minimisation: solve eq. 5 directly for the point of the
        // envelope (a characteristic point M(u', h)) on the normal line of P, by Newton in
        // (u', h) on (M - P) × N = 0, and compare (M - P)·N with the deviation.
        let part = SShape::iso();
        let mut worst: f64 = 0.0;
        let paths = [
            FlankPath::new(&part, Surface::A),
            FlankPath::new(&part, Surface::B),
        ];
        // the 100 points and the bottom edges (where the largest overcuts are); not the very ends,
        // where the deepest tool is the last one of the path and eq. 5 need not hold
        let mut pts = builtin_points(&part);
        for s in Surface::BOTH {
            for i in 1..40 {
                let u = i as f64 / 40.0;
                let mut q = MeasurementPoint::at(&part, 0, Curve::AZ11, u, 0.0);
                let f = part.frame_at(s, u, 0.0);
                (q.surface, q.point, q.normal) = (s, f.point, f.n);
                pts.push(q);
            }
        }
        for p in pts {
            let path = &paths[p.surface.index()];
            let hit = path
                .deviation_at(&p.point, &p.normal, p.u, TOOL_RADIUS)
                .unwrap();
            // the contact point lies on the tool surface
            let pose = tool_pose(&part, p.surface, hit.u_tool);
            let rel = p.point + p.normal * hit.deviation - pose.tip;
            let radial = (rel - pose.axis * rel.dot(&pose.axis)).norm();
            assert_near!(radial, TOOL_RADIUS, 1e-9);
            // eq. 5 residual (mm per unit u, |dT_tool/du| is hundreds of mm): small, limited by
            // how well function values locate the minimiser
            let r = envelope_condition(&part, p.surface, &p.point, &p.normal, &hit);
            assert!(r.abs() < 1e-3, "point {}: eq. 5 residual {r}", p.id);
            // Newton on the characteristic
            let e1 = p.normal.cross(&Vector3::z()).normalize();
            let e2 = p.normal.cross(&e1);
            let res = |u: f64, h: f64| {
                let m = characteristic_point(&part, p.surface, u, h, &p.normal) - p.point;
                nalgebra::Vector2::new(m.dot(&e1), m.dot(&e2))
            };
            let (mut u, mut h) = (hit.u_tool, hit.height);
            for _ in 0..20 {
                let r0 = res(u, h);
                let (du, dh) = (1e-7, 1e-5);
                let ju = (res(u + du, h) - res(u - du, h)) / (2.0 * du);
                let jh = (res(u, h + dh) - res(u, h - dh)) / (2.0 * dh);
                let j = nalgebra::Matrix2::from_columns(&[ju, jh]);
                let step = j.lu().solve(&(-r0)).unwrap();
                u += step[0];
                h += step[1];
                if step.norm() < 1e-14 {
                    break;
                }
            }
            let m = characteristic_point(&part, p.surface, u, h, &p.normal);
            let t = (m - p.point).dot(&p.normal);
            worst = worst.max((t - hit.deviation).abs());
            assert!((u - hit.u_tool).abs() < 1e-6, "point {}", p.id);
            assert!(hit.height > 0.0 && hit.height < 35.0);
        }
        println!("max |envelope - characteristic| = {worst:e} mm");
        assert!(worst < 1e-9, "envelope vs characteristic: {worst:e} mm");
    }

    #[test]
    fn tool_radius_error_shifts_the_deviation_by_minus_dr() {
        // s-shape.md / paper 000 §3.2: a tool larger by dR overcuts by about dR.
        let part = SShape::iso();
        let pts = builtin_points(&part);
        let d0 = points_deviation(&part, &pts, 0.0).unwrap();
        let d1 = points_deviation(&part, &pts, 0.01).unwrap();
        for (a, b) in d0.iter().zip(&d1) {
            // exactly -dR up to the 1/cos of the small angle between N and n_M (< 5e-9 mm here)
            assert_near!(b.deviation - a.deviation, -0.01, 1e-7);
        }
    }

    #[test]
    fn the_cylinders_narrow_window_finds_the_wide_windows_cut() {
        // CYLINDER_WINDOW's claim, on a coarser grid than its doc's (every 10th table step, v
        // −0.1..1.1, 0.1 mm either side): the first window ±0.005 and ±WINDOW give the same
        // deviation, tool position and height, bit for bit, on the S-shape and the cones.
        use crate::part::ConeFrustum;
        let parts: [&dyn RuledPart; 3] = [
            &SShape::iso(),
            &ConeFrustum::m3_15(true),
            &ConeFrustum::m3_45(false),
        ];
        let mut n = 0;
        for (k, part) in parts.into_iter().enumerate() {
            for &s in part.surfaces() {
                let path = FlankPath::new(part, s);
                for iu in (0..=TABLE_STEPS).step_by(10) {
                    let u = (iu as f64 / TABLE_STEPS as f64 + 1.1e-4).min(1.0);
                    for iv in [-3, 0, 7, 15, 22, 30, 33] {
                        let f = part.frame_at(s, u, iv as f64 / 30.0);
                        for off in [-0.1, 0.0, 0.1] {
                            let p = f.point + f.n * off;
                            let narrow = path.deviation_at(&p, &f.n, u, TOOL_RADIUS).unwrap();
                            let entry = |pose: &ToolPose| line_entry(pose, TOOL_RADIUS, &p, &f.n);
                            let wide = path.deviation_with(&p, &f.n, u, &entry).unwrap();
                            assert_eq!(narrow, wide, "part {k} {s:?} u {u} v {iv}/30 off {off}");
                            n += 1;
                        }
                    }
                }
            }
        }
        assert_eq!(n, 3 * 401 * 7 * 3 + 401 * 7 * 3);
    }
}
