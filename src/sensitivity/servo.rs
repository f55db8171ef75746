//! Servo following error along the flank path (`shared/spec/effects.md`, "Shapes are families":
//! `servo_lag_<axis>` and `servo_common`; paper 002 §4.3 simulates one axis's servo delay).
//!
//! Each axis trails its command by its speed times its position loop's time constant `1/Kv`. At
//! the constant feed `F` the tool tip covers `s = F·t`, so a time lag is a lag in tool-tip path:
//! `L = F/Kv` (mm).
//! - **Mismatch** (`servo_lag_<axis>.l`): axis `i` trailing the others by `l` (mm of path) sits at
//!   `q_i(s − l) ≈ q_i(s) − l·dq_i/ds`, so the defect is `−l·(dq_i/ds)·(d dev/dq_i)`.
//! - **Common rounding** (`servo_common.L2`): a first-order loop `q' = Kv (q_c − q)` gives
//!   `q = q_c(s − L) + (L²/2)·d²q_c/ds² + O(L³)`; a shift of every axis by the same `L` along the
//!   path leaves the tool on the path, so the defect is `(L²/2)·Σ_i (d²q_i/ds²)·(d dev/dq_i)`,
//!   per unit of `L²`.
//!
//! `d dev/dq_i` is the normal displacement of the tool-body point at the contact point per unit
//! of axis `i` ([`super::reversal`]'s `∂x/∂q`, the axis's positioning error motion `E{i}{i}`,
//! exactly a change of its value), dotted with the normal of the mode. The rates follow the
//! model's own inverse kinematics along the path ([`crate::sensitivity::machine_path`]: the outer
//! angle interpolated linearly in `u` on the vertical zone, which is what the controller is
//! commanded): `dq/ds = q_u/s_u` and `d²q/ds² = (q_uu − q_u·s_uu/s_u)/s_u²` with `s_u = |d tip/du|`
//! (reference README, `servo_signatures.csv`). `q_u`, `q_uu` and `s_uu` are central differences in
//! `u` with steps [`STEP_U`] and `2·STEP_U`, Richardson-extrapolated (error `O(h⁴)`); `s_u` is the
//! analytic tip speed ([`crate::toolpath::flank::tool_pose_derivs`]). The built-in points lie at
//! least 5.2 mm of path from the vertical zone's ends, where the rates of C and Y jump; a step of
//! 2·[`STEP_U`] is ≈ 0.15 mm of path.
//! Units: mm, rad; columns in mm per mm of `l`, and mm per mm² of `L²`.

use crate::machine::{AxisKind, AxisName, AxisValues};
use crate::part::{MeasurementPoint, SShape, Surface};
use crate::toolpath::flank::tool_pose_derivs;

use super::defect::SensitivityOptions;
use super::path::machine_path;
use super::reversal::backlash_gains;
use super::SensitivityError;

/// Step of the central differences in `u` (≈ 0.08 mm of tool-tip path on the S-shape's ~300 mm
/// passes): with `2·STEP_U` and Richardson extrapolation the columns agree with the reference's
/// converged ones to 1.1e-8 of their largest value (steps of 1e-3: 8.8e-6; 5e-4: 3.2e-6;
/// test `servo_signatures_match_reference`).
pub const STEP_U: f64 = 2.5e-4;

/// The relative uncertainty of the first-order formulas against servos simulated in time, added
/// in quadrature to a fitted servo lag's std: the reference README (servo_signatures.csv) measures
/// fitted lags 1.6-2.7 % from the true `l` and the signatures 2-7 % RMS from the simulated
/// defects (more for second-order loops and once `L` passes about 0.6 mm): 5 %.
pub const FIRST_ORDER_REL: f64 = 0.05;

/// The servo columns at measurement points: one `servo_lag_<axis>.l` column per axis of the chain
/// (chain order), and the `servo_common.L2` column.
#[derive(Debug, Clone, PartialEq)]
pub struct ServoColumns {
    pub lag: Vec<(AxisName, Vec<f64>)>,
    pub common: Vec<f64>,
}

/// The axis rates of the path at one point: `dq/ds` (mm or rad per mm of path) and `d²q/ds²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathRates {
    pub first: AxisValues,
    pub second: AxisValues,
}

/// `dq/ds` and `d²q/ds²` of the flank path of `surface` at each of `us` (module doc).
pub fn path_rates(
    part: &SShape,
    surface: Surface,
    us: &[f64],
    opts: &SensitivityOptions,
) -> Result<Vec<PathRates>, SensitivityError> {
    let h = STEP_U;
    // Five samples a point, kept inside [0, 1] (one-sided near an end: never at the points).
    let offsets = [-2.0, -1.0, 0.0, 1.0, 2.0];
    let sample_u: Vec<f64> = us
        .iter()
        .flat_map(|&u| {
            let c = u.clamp(2.0 * h, 1.0 - 2.0 * h);
            offsets.map(|o| c + o * h)
        })
        .collect();
    let path = machine_path(part, &opts.chain, surface, opts.branch, &sample_u)?;
    let speed = |u: f64| tool_pose_derivs(part, surface, u).tip_u.norm();
    let axes: Vec<(AxisName, bool)> = opts
        .chain
        .axes()
        .map(|a| (a.name, a.name.kind() == AxisKind::Rotary))
        .collect();
    Ok(us
        .iter()
        .enumerate()
        .map(|(k, &u)| {
            let c = u.clamp(2.0 * h, 1.0 - 2.0 * h);
            let q = |j: usize| &path[5 * k + j].values;
            // the tip speed at the five samples; s_u at the centre, where the rates are taken
            let sp = offsets.map(|o| speed(c + o * h));
            let s_u = sp[2];
            let s_uu = richardson1([sp[0], sp[1], sp[3], sp[4]], h);
            let mut first = AxisValues::default();
            let mut second = AxisValues::default();
            for &(a, rotary) in &axes {
                // Differences from the centre sample, wrapped for a rotary axis.
                let d = |j: usize| {
                    let x = q(j).get(a) - q(2).get(a);
                    if rotary {
                        wrap(x)
                    } else {
                        x
                    }
                };
                let v = [d(0), d(1), d(3), d(4)];
                let q_u = richardson1(v, h);
                let q_uu = richardson2(v, h);
                first.set(a, q_u / s_u);
                second.set(a, (q_uu - q_u * s_uu / s_u) / (s_u * s_u));
            }
            PathRates { first, second }
        })
        .collect())
}

/// `d/du` from the samples at `−2h, −h, +h, +2h`: `(4·D(h) − D(2h))/3`, `D` the central difference.
fn richardson1(v: [f64; 4], h: f64) -> f64 {
    let d1 = (v[2] - v[1]) / (2.0 * h);
    let d2 = (v[3] - v[0]) / (4.0 * h);
    (4.0 * d1 - d2) / 3.0
}

/// `d²/du²` from the differences to the centre at `−2h, −h, +h, +2h`.
fn richardson2(v: [f64; 4], h: f64) -> f64 {
    let d1 = (v[2] + v[1]) / (h * h);
    let d2 = (v[3] + v[0]) / (4.0 * h * h);
    (4.0 * d1 - d2) / 3.0
}

/// An angle difference brought into (−π, π].
fn wrap(x: f64) -> f64 {
    let t = std::f64::consts::TAU;
    x - t * (x / t).round()
}

/// Steps of a [`RateTable`] over `u ∈ [0, 1]` (≈ 0.12 mm of tool-tip path a step).
pub const RATE_TABLE_STEPS: usize = 2600;

/// A point within this many steps of a knot of its surface's curves, or of an end of the path, is
/// solved at the point: the path is only C¹ at a knot (its tool axis follows the curves'
/// tangents) and held at the ends, so the rates' finite differences bend within `2·`[`STEP_U`]
/// of them, faster than a cubic through the nodes follows (3 % of the largest second rate at 1
/// step; 7.1e-8 from 4 steps on).
pub const RATE_TABLE_KNOT_MARGIN: f64 = 4.0;

/// From this many points on, the servo columns read their rates from a [`RateTable`] (5,202
/// nodes, each solved as a point is); below it each point's rates are solved at the point (the
/// built-in 100 points).
pub const RATE_TABLE_POINTS: usize = 4000;

/// [`path_rates`] at the nodes `j/`[`RATE_TABLE_STEPS`] of each surface's path, for a dense
/// scan (issue 31: 5 inverse kinematics and 5 tip speeds a point were a tenth of a
/// 20,000-point scan's CPU). A point's rates are the cubic through the four nodes around it
/// (Lagrange, the end intervals one-sided), or its own where it lies within
/// [`RATE_TABLE_KNOT_MARGIN`] steps of a knot (the vertical zone's ends are knots): within 1e-8
/// of each axis's largest first rate and 7.1e-8 of its largest second rate on paper 000's
/// machine (test `the_rate_table_is_the_points_own_rates`).
#[derive(Debug, Clone, PartialEq)]
pub struct RateTable {
    nodes: [Vec<PathRates>; 2],
    /// The distinct knots of each surface's two curves, the ends among them (where the rates'
    /// differences are held one-sided, [`path_rates`]).
    knots: [Vec<f64>; 2],
}

impl RateTable {
    /// The table of both surfaces' paths on the chain and branch of `opts`, its nodes solved in
    /// blocks side by side on `threads` threads (the same rates).
    pub fn new(
        part: &SShape,
        opts: &SensitivityOptions,
        threads: crate::numerics::parallel::Threads,
    ) -> Result<Self, SensitivityError> {
        const BLOCK: usize = 650;
        let jobs: Vec<(Surface, usize)> = Surface::BOTH
            .into_iter()
            .flat_map(|s| (0..=RATE_TABLE_STEPS).step_by(BLOCK).map(move |j| (s, j)))
            .collect();
        let parts = crate::numerics::parallel::map(threads, &jobs, |&(s, j0)| {
            let us: Vec<f64> = (j0..(j0 + BLOCK).min(RATE_TABLE_STEPS + 1))
                .map(|j| j as f64 / RATE_TABLE_STEPS as f64)
                .collect();
            path_rates(part, s, &us, opts)
        });
        let mut nodes = [Vec::new(), Vec::new()];
        for (&(s, _), part) in jobs.iter().zip(parts) {
            nodes[s.index()].extend(part?);
        }
        let knots = Surface::BOTH.map(|s| {
            let mut k: Vec<f64> = part
                .curves(s)
                .iter()
                .flat_map(|c| c.knots().iter().copied())
                .filter(|&k| (0.0..=1.0).contains(&k))
                .collect();
            k.sort_by(f64::total_cmp);
            k.dedup();
            k
        });
        Ok(Self { nodes, knots })
    }

    /// Whether a point at `u` on `surface` is solved at the point ([`RATE_TABLE_KNOT_MARGIN`]).
    fn near_knot(&self, surface: Surface, u: f64) -> bool {
        let margin = RATE_TABLE_KNOT_MARGIN / RATE_TABLE_STEPS as f64;
        self.knots[surface.index()]
            .iter()
            .any(|k| (u - k).abs() <= margin)
    }

    /// The rates at each of `us` on the path of `surface` of `part` (the table's), the chain's
    /// `axes` (module doc of [`RateTable`]).
    pub fn rates(
        &self,
        part: &SShape,
        surface: Surface,
        us: &[f64],
        opts: &SensitivityOptions,
        axes: &[AxisName],
    ) -> Result<Vec<PathRates>, SensitivityError> {
        let solved: Vec<usize> = (0..us.len())
            .filter(|&i| self.near_knot(surface, us[i]))
            .collect();
        let own = path_rates(
            part,
            surface,
            &solved.iter().map(|&i| us[i]).collect::<Vec<_>>(),
            opts,
        )?;
        let mut out: Vec<PathRates> = us
            .iter()
            .map(|&u| self.interpolated(surface, u, axes))
            .collect();
        for (&i, r) in solved.iter().zip(own) {
            out[i] = r;
        }
        Ok(out)
    }

    /// The cubic through the four nodes around `u`.
    fn interpolated(&self, surface: Surface, u: f64, axes: &[AxisName]) -> PathRates {
        let nodes = &self.nodes[surface.index()];
        let f = u.clamp(0.0, 1.0) * RATE_TABLE_STEPS as f64;
        let j = (f.floor() as usize).min(RATE_TABLE_STEPS - 1);
        let j0 = j.saturating_sub(1).min(RATE_TABLE_STEPS - 3);
        let t = f - j0 as f64;
        // Lagrange weights at t on the nodes j0 .. j0 + 3
        let w = [
            -(t - 1.0) * (t - 2.0) * (t - 3.0) / 6.0,
            t * (t - 2.0) * (t - 3.0) / 2.0,
            -t * (t - 1.0) * (t - 3.0) / 2.0,
            t * (t - 1.0) * (t - 2.0) / 6.0,
        ];
        let mut out = PathRates {
            first: AxisValues::default(),
            second: AxisValues::default(),
        };
        for &a in axes {
            let (mut d1, mut d2) = (0.0, 0.0);
            for (k, wk) in w.iter().enumerate() {
                d1 += wk * nodes[j0 + k].first.get(a);
                d2 += wk * nodes[j0 + k].second.get(a);
            }
            out.first.set(a, d1);
            out.second.set(a, d2);
        }
        out
    }
}

/// The servo columns (module doc) at `points` of axis values `q` (solved with the same `opts`).
pub fn servo_signatures(
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
) -> Result<ServoColumns, SensitivityError> {
    let axes: Vec<AxisName> = opts.chain.axes().map(|a| a.name).collect();
    let gains = backlash_gains(part, points, q, &axes, opts)?;
    servo_signatures_with(part, points, opts, &gains, None)
}

/// [`servo_signatures`] from the gains `(∂x/∂q)·N` of every axis of the chain in its order
/// ([`backlash_gains`] of those axes at the same points and axis values), computed once by a
/// caller that also needs them; the rates from `table` when given ([`RateTable`], same `opts`),
/// else solved at each point.
pub fn servo_signatures_with(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &SensitivityOptions,
    gains: &[Vec<f64>],
    table: Option<&RateTable>,
) -> Result<ServoColumns, SensitivityError> {
    let axes: Vec<AxisName> = opts.chain.axes().map(|a| a.name).collect();
    let n = points.len();
    let mut lag = vec![vec![0.0; n]; axes.len()];
    let mut common = vec![0.0; n];
    for surface in Surface::BOTH {
        let idx: Vec<usize> = (0..n).filter(|&i| points[i].surface == surface).collect();
        if idx.is_empty() {
            continue;
        }
        let us: Vec<f64> = idx.iter().map(|&i| points[i].u).collect();
        let rates = match table {
            Some(t) => t.rates(part, surface, &us, opts, &axes)?,
            None => path_rates(part, surface, &us, opts)?,
        };
        for (&i, r) in idx.iter().zip(&rates) {
            for (a, &axis) in axes.iter().enumerate() {
                lag[a][i] = -r.first.get(axis) * gains[a][i];
                common[i] += 0.5 * r.second.get(axis) * gains[a][i];
            }
        }
    }
    Ok(ServoColumns {
        lag: axes.into_iter().zip(lag).collect(),
        common,
    })
}
