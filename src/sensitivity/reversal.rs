//! Reversal (backlash) errors along the flank path with a first-order servo lag (paper 002 §4.3,
//! Fig. 16; `shared/spec/effects.md`, candidates `backlash_x` … `backlash_c`, and `backlash_a` of
//! paper 001's A-B head).
//!
//! Each surface is machined in one pass in increasing `u`. An axis with lost motion `b` (mm, or
//! rad for A, B and C) trails its command by `b/2` against its direction of motion: the offset
//! target is `e* = −(b/2)·sgn(dq/du)`, held while the axis is at rest. At a reversal the offset
//! moves to the new target through a first-order lag whose "time" constant is
//! [`LAG_LENGTH`] = 2 mm of tool-tip path: `e(s) = e* + (e(s₀) − e*)·exp(−(s − s₀)/2)`.
//! Each pass starts settled for its first direction of motion.
//!
//! **Where the direction changes** (the reference's convention): on a [`REVERSAL_GRID`]-step grid
//! in `u`, the direction of an axis on a step is the sign of its increment, held through rest
//! (increments ≤ [`REST_TOLERANCE`]). The lag is evaluated at the grid samples around a point
//! and interpolated linearly in `u`. The grid is not solved sample by sample: [`pass`] finds the
//! steps where the direction changes from the axis *rates* `dq/du` (analytic derivatives of the
//! inverse kinematics, [`crate::machine::rates`]) at [`RATE_SAMPLES`] samples, and solves the
//! grid only around each turn (a window about the root of the rate's Hermite interpolant) and
//! across the starts and ends of rest and of the vertical zone. Between turns the lag is in
//! closed form: `e_k = e* + (e_{k_r−1} − e*)·exp(−(s_k − s_{k_r−1})/2)`, exactly the grid's
//! recursion `e_k = e* + (e_{k−1} − e*)·exp(−(s_k − s_{k−1})/2)` with the decays multiplied
//! out. `s` is the tool-tip path length ([`TipLength`]: Gauss–Legendre on the tip speed, not the
//! chords of the grid).
//!
//! The defect at a point is `e(s)·(∂x/∂q)·N`, `x` the tool-body point at the contact point (the
//! rigid tool motion evaluated where the tool touches the wall), `N` the normal of the mode
//! ([`super`]). Units: mm, rad.

use std::collections::HashMap;

use crate::numerics::fast_hash::FastHashMap;
use crate::numerics::parallel::{join, Threads};

use crate::machine::direct::body_point_jacobian;
use crate::machine::inverse::RotaryPair;
use crate::machine::rates::axis_rates;
use crate::machine::{AxisName, AxisValues, ErrorParam, MachineErrors, PathSample};
use crate::part::{MeasurementPoint, SShape, Surface};
use crate::toolpath::flank::tool_pose_derivs;
use crate::toolpath::tip_length::{PassLengths, TipLength};

use super::defect::axis_values;
use super::defect::{Mode, SensitivityOptions};
use super::path::machine_path;
use super::ringing::Settling;
use super::take_up::{Ramp, TurnTravel};
use super::SensitivityError;
use crate::numerics::order::{argsort, sort_by_index};

/// Time constant of the servo lag, in mm of tool-tip path (effects.md).
pub const LAG_LENGTH: f64 = crate::parameter::effect::REFERENCE_LAG;
/// Steps of the `u` grid on which the directions are defined (20001 samples).
pub const REVERSAL_GRID: usize = 20000;
/// Axis increments at most this large between grid samples count as rest (mm or rad): they are
/// rounding noise of the inverse kinematics on stretches where an axis stands still.
pub const REST_TOLERANCE: f64 = 1e-9;

/// Samples of the axis rates per pass (every 80th grid sample; 500 and 125 measured slower: the
/// rates' Jacobians against the windows solved where the rate is weak).
pub const RATE_SAMPLES: usize = 250;
/// A rate at most this (mm or rad per unit u) is rest: its grid increments are ~5e-12, far under
/// [`REST_TOLERANCE`] (the rates' rounding on a rest stretch is ~1e-10).
pub const RATE_REST: f64 = 1e-7;
/// A rate above this moves by more than 10 × [`REST_TOLERANCE`] per grid step: near it every
/// increment counts as motion in the rate's direction.
pub const RATE_STRONG: f64 = 10.0 * REST_TOLERANCE * REVERSAL_GRID as f64;
/// Grid steps solved on each side of a turn's estimated step.
pub const TURN_WINDOW: usize = 3;
/// A coarse interval over which an axis at rest at both ends moves by at most this (mm or rad)
/// is rest throughout.
pub const REST_BELOW: f64 = 1e-11;

/// Where one axis changes direction along a pass, on the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Turns {
    /// Direction of the first motion (+1 or −1; +1 for an axis that never moves).
    pub first: f64,
    /// `(k, d)`: from grid step `k − 1 → k` on, the direction is `d`.
    pub at: Vec<(usize, f64)>,
}

/// One pass (one surface): each axis's turns on the grid, and the tool-tip path length.
#[derive(Debug, Clone)]
pub struct Pass {
    pub surface: Surface,
    /// The chain's axes and, per axis, its [`Turns`].
    pub axes: Vec<AxisName>,
    pub turns: Vec<Turns>,
    /// Tool-tip path length from the start of the pass.
    pub length: TipLength,
    /// Grid samples at which the inverse kinematics was solved (the rate samples among them),
    /// of the grid's 20,001.
    pub solved: usize,
}

impl Pass {
    /// The turns of `axis`, `None` for an axis the chain does not have.
    pub fn turns_of(&self, axis: AxisName) -> Option<&Turns> {
        self.axes
            .iter()
            .position(|&a| a == axis)
            .map(|i| &self.turns[i])
    }
}

/// `u` of grid sample `k`.
pub fn grid_u(k: usize) -> f64 {
    k as f64 / REVERSAL_GRID as f64
}

/// What the rate of one axis says at a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Rate {
    Rest,
    Weak,
    Strong(f64),
}

fn class(r: f64) -> Rate {
    if r.abs() <= RATE_REST {
        Rate::Rest
    } else if r.abs() > RATE_STRONG {
        Rate::Strong(r.signum())
    } else {
        Rate::Weak
    }
}

/// How the grid steps of one coarse interval are found.
#[derive(Debug, Clone, PartialEq)]
enum Plan {
    /// Every grid sample of the interval is solved.
    Full,
    /// Each axis moves one way throughout, rests throughout, or turns once inside the window
    /// `(axis index, first k, last k)` about its rate's root.
    Windows(Vec<(usize, usize, usize)>),
}

/// The derivative `q'(t) = a t² + b t + c` of the cubic Hermite interpolant of `q` on `[0, 1]`
/// (values `q0, q1`, slopes `d0, d1` per unit of the interval), as `[a, b, c]`.
fn hermite_rate(q0: f64, q1: f64, d0: f64, d1: f64) -> [f64; 3] {
    let dq = q1 - q0;
    [
        3.0 * (d0 + d1) - 6.0 * dq,
        6.0 * dq - 4.0 * d0 - 2.0 * d1,
        d0,
    ]
}

/// Whether the Hermite interpolant's rate, of one sign at both ends, takes the other sign inside
/// (at the vertex of the quadratic).
fn hermite_dips(q0: f64, q1: f64, d0: f64, d1: f64) -> bool {
    let [a, b, c] = hermite_rate(q0, q1, d0, d1);
    if a == 0.0 {
        return false;
    }
    let t = -b / (2.0 * a);
    t > 0.0 && t < 1.0 && ((a * t + b) * t + c).signum() != d0.signum()
}

/// Where the derivative of the cubic Hermite interpolant of `q` on `[0, 1]` (values `q0, q1`,
/// slopes `d0, d1` per unit of the interval) changes sign, if it does exactly once.
fn hermite_root(q0: f64, q1: f64, d0: f64, d1: f64) -> Option<f64> {
    let [a, b, c] = hermite_rate(q0, q1, d0, d1);
    let f = |t: f64| (a * t + b) * t + c;
    let (mut lo, mut hi) = (0.0, 1.0);
    if f(lo).signum() == f(hi).signum() {
        return None;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if f(mid).signum() == f(lo).signum() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// The grid samples solved so far, sorted by index.
struct Solved(Vec<(usize, AxisValues)>);

impl Solved {
    fn get(&self, k: usize) -> Option<&AxisValues> {
        self.0
            .binary_search_by_key(&k, |x| x.0)
            .ok()
            .map(|i| &self.0[i].1)
    }

    /// A sample every plan solved (the plans ask for each sample they read).
    fn at(&self, k: usize) -> &AxisValues {
        self.get(k).expect("grid sample solved by its plan")
    }
}

/// The pass of surface `surface`: each axis's turns on the [`REVERSAL_GRID`] grid, as the grid
/// solved at all 20,001 samples gives them (checked in tests/it/sensitivity_reversal.rs for the
/// three chains, both branches and both surfaces), from ~1,000 inverse kinematics (module docs).
///
/// The rates are sampled every `REVERSAL_GRID / RATE_SAMPLES` grid steps. On a coarse interval
/// between two samples, an axis whose rate is [`RATE_STRONG`] with the same sign at both ends
/// (and whose coarse increment agrees) moves that way at every step; one at rest at both ends
/// that moves by at most [`REST_BELOW`] rests; one strong with opposite signs turns once, at the
/// root of the Hermite interpolant's derivative, and the grid is solved in a window of
/// [`TURN_WINDOW`] steps about it (the whole interval when the window does not show exactly that
/// one turn). Every other interval (weak rates, starts and ends of rest, an end of the vertical
/// zone, where the outer angle's rate jumps) is solved at all its grid samples.
pub fn pass(
    part: &SShape,
    surface: Surface,
    opts: &SensitivityOptions,
) -> Result<Pass, SensitivityError> {
    let chain = &opts.chain;
    let n = REVERSAL_GRID;
    let stride = n / RATE_SAMPLES;
    let coarse_k: Vec<usize> = (0..=RATE_SAMPLES).map(|j| j * stride).collect();
    let coarse_u: Vec<f64> = coarse_k.iter().map(|&k| grid_u(k)).collect();
    let coarse = machine_path(part, chain, surface, opts.branch, &coarse_u)?;
    let axes: Vec<AxisName> = chain.axes().map(|a| a.name).collect();
    let outer = RotaryPair::of(chain)?.outer;
    // Rates per unit u at each coarse sample; on the vertical zone the outer angle's rate is the
    // slope of its linear interpolation, from a neighbour in the same zone.
    let rates: Vec<Option<AxisValues>> = (0..coarse.len())
        .map(|j| {
            let fixed = if coarse[j].singular {
                let nb = [j.wrapping_sub(1), j + 1]
                    .into_iter()
                    .find(|&i| i < coarse.len() && coarse[i].singular)?;
                let (a, b) = (j.min(nb), j.max(nb));
                let slope = (coarse[b].values.get(outer) - coarse[a].values.get(outer))
                    / (coarse_u[b] - coarse_u[a]);
                Some((outer, slope))
            } else {
                None
            };
            let d = tool_pose_derivs(part, surface, coarse_u[j]);
            axis_rates(
                chain,
                &coarse[j].values,
                &d.pose.tip,
                &d.tip_u,
                &d.axis_u,
                fixed,
            )
            .ok()
        })
        .collect();
    let h = 1.0 / RATE_SAMPLES as f64;
    let mut plans: Vec<Plan> = (0..RATE_SAMPLES)
        .map(|j| {
            let (Some(r0), Some(r1)) = (&rates[j], &rates[j + 1]) else {
                return Plan::Full;
            };
            if coarse[j].singular != coarse[j + 1].singular {
                return Plan::Full;
            }
            let mut windows = Vec::new();
            for (ai, &a) in axes.iter().enumerate() {
                let dq = coarse[j + 1].values.get(a) - coarse[j].values.get(a);
                match (class(r0.get(a)), class(r1.get(a))) {
                    (Rate::Strong(s0), Rate::Strong(s1)) if s0 == s1 => {
                        // A turn and a return inside the interval: its net motion is too small,
                        // or the Hermite interpolant's rate dips to the other side.
                        let dips = hermite_dips(
                            coarse[j].values.get(a),
                            coarse[j + 1].values.get(a),
                            r0.get(a) * h,
                            r1.get(a) * h,
                        );
                        if dq * s0 <= stride as f64 * REST_TOLERANCE || dips {
                            return Plan::Full;
                        }
                    }
                    (Rate::Strong(_), Rate::Strong(_)) => {
                        let Some(t) = hermite_root(
                            coarse[j].values.get(a),
                            coarse[j + 1].values.get(a),
                            r0.get(a) * h,
                            r1.get(a) * h,
                        ) else {
                            return Plan::Full;
                        };
                        let k = coarse_k[j] + (t * stride as f64).round() as usize;
                        let first = k.saturating_sub(TURN_WINDOW).max(coarse_k[j]);
                        let last = (k + TURN_WINDOW).min(coarse_k[j + 1]);
                        windows.push((ai, first, last));
                    }
                    (Rate::Rest, Rate::Rest) if dq.abs() <= REST_BELOW => {}
                    _ => return Plan::Full,
                }
            }
            Plan::Windows(windows)
        })
        .collect();
    let mut solved = Solved(
        coarse_k
            .iter()
            .zip(&coarse)
            .map(|(&k, s)| (k, s.values))
            .collect(),
    );
    let solve = |ks: Vec<usize>, solved: &mut Solved| {
        let ks: Vec<usize> = ks
            .into_iter()
            .filter(|&k| solved.get(k).is_none())
            .collect();
        if ks.is_empty() {
            return Ok::<(), SensitivityError>(());
        }
        let us: Vec<f64> = ks.iter().map(|&k| grid_u(k)).collect();
        let got: Vec<PathSample> = machine_path(part, chain, surface, opts.branch, &us)?;
        solved
            .0
            .extend(ks.into_iter().zip(got.into_iter().map(|s| s.values)));
        sort_by_index(&mut solved.0, |x| x.0);
        solved.0.dedup_by_key(|x| x.0);
        Ok(())
    };
    let wanted = |plans: &[Plan]| -> Vec<usize> {
        let mut ks = Vec::new();
        for (j, p) in plans.iter().enumerate() {
            match p {
                Plan::Full => ks.extend(coarse_k[j]..=coarse_k[j + 1]),
                Plan::Windows(w) => {
                    for &(_, a, b) in w {
                        ks.extend(a..=b);
                    }
                }
            }
        }
        ks
    };
    solve(wanted(&plans), &mut solved)?;
    // A window must show the turn: motion the old way at its start, the new way at its end, and
    // one change between; otherwise the whole interval is solved.
    let mut again = false;
    for (j, p) in plans.iter_mut().enumerate() {
        let Plan::Windows(w) = p else { continue };
        let ok = w.iter().all(|&(ai, a, b)| {
            let r0 = rates[j].as_ref().map_or(0.0, |r| r.get(axes[ai]));
            let incs: Vec<f64> = (a + 1..=b)
                .map(|k| solved.at(k).get(axes[ai]) - solved.at(k - 1).get(axes[ai]))
                .collect();
            let (Some(&i0), Some(&i1)) = (incs.first(), incs.last()) else {
                return false;
            };
            let changes = incs
                .windows(2)
                .filter(|x| x[0].signum() != x[1].signum())
                .count();
            a < b
                && i0 * r0.signum() > REST_TOLERANCE
                && -i1 * r0.signum() > REST_TOLERANCE
                && changes == 1
        });
        if !ok {
            *p = Plan::Full;
            again = true;
        }
    }
    if again {
        solve(wanted(&plans), &mut solved)?;
    }
    // The grid's rule on every step, in order.
    let turns = axes
        .iter()
        .enumerate()
        .map(|(ai, &a)| {
            let mut d = 0.0;
            let mut first = None;
            let mut at = Vec::new();
            let mut step = |k: usize, dir: f64| {
                if d == 0.0 {
                    first = Some(dir);
                } else if dir != d {
                    at.push((k, dir));
                }
                d = dir;
            };
            let inc = |k: usize| solved.at(k).get(a) - solved.at(k - 1).get(a);
            for (j, p) in plans.iter().enumerate() {
                let (k0, k1) = (coarse_k[j], coarse_k[j + 1]);
                let window = match p {
                    Plan::Full => Some((k0, k1)),
                    Plan::Windows(w) => w.iter().find(|x| x.0 == ai).map(|x| (x.1, x.2)),
                };
                match window {
                    Some((wa, wb)) => {
                        let before = rates[j].as_ref().map_or(0.0, |r| r.get(a)).signum();
                        if wa > k0 {
                            step(k0 + 1, before);
                        }
                        for k in wa + 1..=wb {
                            let x = inc(k);
                            if x.abs() > REST_TOLERANCE {
                                step(k, x.signum());
                            }
                        }
                        if wb < k1 {
                            step(wb + 1, -before);
                        }
                    }
                    None => {
                        if let Some(Rate::Strong(s)) = rates[j].as_ref().map(|r| class(r.get(a))) {
                            step(k0 + 1, s);
                        }
                    }
                }
            }
            Turns {
                first: first.unwrap_or(1.0),
                at,
            }
        })
        .collect();
    Ok(Pass {
        surface,
        axes,
        turns,
        length: TipLength::new(part, surface),
        solved: solved.0.len(),
    })
}

/// Direction of motion of `axis` on each grid step `k-1 → k` (index k; index 0 = the first
/// motion), held through rest; an axis the chain does not have never moves (settled at +1, as
/// [`directions_of`] gives for constant values).
pub fn directions(p: &Pass, axis: AxisName) -> Vec<f64> {
    let mut d = vec![1.0; REVERSAL_GRID + 1];
    if let Some(t) = p.turns_of(axis) {
        let mut cur = t.first;
        let mut next = t.at.iter().peekable();
        for (k, x) in d.iter_mut().enumerate() {
            while let Some(&&(kt, dt)) = next.peek() {
                if kt > k {
                    break;
                }
                cur = dt;
                next.next();
            }
            *x = cur;
        }
    }
    d
}

/// Directions from the axis values at every grid sample (the definition [`pass`] reproduces
/// with fewer inverse kinematics; tests compare the two).
pub fn directions_of(q: &[AxisValues], axis: AxisName) -> Vec<f64> {
    let mut d = vec![0.0; q.len()];
    for k in 1..q.len() {
        let dq = q[k].get(axis) - q[k - 1].get(axis);
        d[k] = if dq.abs() > REST_TOLERANCE {
            dq.signum()
        } else {
            d[k - 1]
        };
    }
    let first = d.iter().copied().find(|x| *x != 0.0).unwrap_or(1.0);
    for x in d.iter_mut() {
        if *x != 0.0 {
            break;
        }
        *x = first;
    }
    d
}

/// Number of reversals of `axis` along the pass.
pub fn reversal_count(p: &Pass, axis: AxisName) -> usize {
    p.turns_of(axis).map_or(0, |t| t.at.len())
}

/// The passes of surfaces A and B ([`Surface::BOTH`] order), for callers that need them for
/// several things (signatures and reversal positions).
pub fn passes(part: &SShape, opts: &SensitivityOptions) -> Result<[Pass; 2], SensitivityError> {
    passes_on(part, opts, Threads::ONE)
}

/// [`passes`], the two side by side on `threads` threads: the same passes.
pub fn passes_on(
    part: &SShape,
    opts: &SensitivityOptions,
    threads: Threads,
) -> Result<[Pass; 2], SensitivityError> {
    let (a, b) = join(
        threads,
        || pass(part, Surface::BOTH[0], opts),
        || pass(part, Surface::BOTH[1], opts),
    );
    Ok([a?, b?])
}

/// One stretch of constant direction of the lag: from grid step `k` on, the offset moves from
/// `from` (its value at sample `k − 1`, path length `s0`) towards `target`.
#[derive(Debug, Clone, PartialEq)]
struct Segment {
    k: usize,
    target: f64,
    from: f64,
    s0: f64,
    /// The play's take-up after the turn ([`Lag::taken_up`]); `None`: the offset switches at
    /// the turn.
    ramp: Option<Ramp>,
    /// `de/ds` at `s0` (a second-order settling's; 0 for the first order, whose state is the
    /// offset alone).
    rate: f64,
}

/// The lagged offsets of a pass per unit lost motion for some axes, in closed form between the
/// turns: all that [`backlash_signatures_lagged`] needs of a pass (it depends on the part, the
/// chain and the branch, not on the points, so it can be kept for other points).
#[derive(Debug, Clone, PartialEq)]
pub struct Lag {
    pub axes: Vec<AxisName>,
    /// The lag's "time" constant, in mm of tool-tip path ([`LAG_LENGTH`] for [`Lag::of`]); of a
    /// second-order settling, its natural length.
    pub tau: f64,
    /// The damping `ζ < 1` of a second-order settling that rings ([`Lag::with_settling`]);
    /// `None` for the first order.
    pub zeta: Option<f64>,
    /// Tool-tip path length of the pass.
    pub length: TipLength,
    segments: Vec<Vec<Segment>>,
}

impl Lag {
    /// The lag of `axes` on pass `p` of `part` (the lags of A and B given together must have the
    /// same axes).
    pub fn of(part: &SShape, p: &Pass, axes: &[AxisName]) -> Self {
        Self::with_length(part, p, axes, LAG_LENGTH)
    }

    /// [`Lag::of`] with the time constant `tau` (mm of tool-tip path) instead of [`LAG_LENGTH`]:
    /// the backlash family of effects.md ("Shapes are families", lags of 0.2-15 mm).
    pub fn with_length(part: &SShape, p: &Pass, axes: &[AxisName], tau: f64) -> Self {
        Self::with_settling(part, p, axes, tau, None)
    }

    /// [`Lag::with_length`] settling in second order when `zeta` is given: the slide's offset
    /// obeys `e'' + 2ζe'/τ + e/τ² = e*/τ²` in path length (a servo whose velocity loop rings,
    /// effects.md "Shapes are families"; `τ` the natural length, `0 < ζ < 1`), its offset and
    /// slope carried across the turns. In closed form between the turns ([`ringing_on`]).
    pub fn with_settling(
        part: &SShape,
        p: &Pass,
        axes: &[AxisName],
        tau: f64,
        zeta: Option<f64>,
    ) -> Self {
        let segments = axes
            .iter()
            .map(|&a| {
                let turns = p.turns_of(a);
                let start = -0.5 * turns.map_or(1.0, |t| t.first);
                let mut segs = vec![Segment {
                    k: 0,
                    target: start,
                    from: start,
                    s0: 0.0,
                    ramp: None,
                    rate: 0.0,
                }];
                for &(k, d) in turns.map_or(&[][..], |t| &t.at[..]) {
                    let s0 = p.length.at(part, grid_u(k - 1));
                    let (from, rate) = match zeta {
                        None => (offset_on(&segs, k - 1, s0, tau), 0.0),
                        Some(z) => ringing_on(&segs, k - 1, s0, tau, z),
                    };
                    segs.push(Segment {
                        k,
                        target: -0.5 * d,
                        from,
                        s0,
                        ramp: None,
                        rate,
                    });
                }
                segs
            })
            .collect();
        Self {
            axes: axes.to_vec(),
            tau,
            zeta,
            length: p.length.clone(),
            segments,
        }
    }

    /// This lag on the axes `axes[a]` with a lost motion `b[a] > 0` (their unit) only, each
    /// with the play's take-up of that `b` ([`super::take_up`]); `travel` the axes' travels
    /// after their turns on this lag's pass ([`super::take_up::travels`], all of this lag's
    /// axes). The axes without one are left out: their columns are this lag's. The take-up is
    /// settled in first order ([`Ramp`]): of a lag that rings, the first order of its length.
    pub fn taken_up(&self, travel: &[Vec<TurnTravel>], b: &[f64]) -> Self {
        let tau = self.tau;
        let kept: Vec<usize> = (0..self.axes.len()).filter(|&a| b[a] > 0.0).collect();
        let segments = kept
            .iter()
            .map(|&a| {
                let old = &self.segments[a];
                let mut segs: Vec<Segment> = vec![old[0].clone()];
                for (g, tr) in old[1..].iter().zip(&travel[a]) {
                    let from = offset_on(&segs, g.k - 1, g.s0, tau);
                    let prev = &segs[segs.len() - 1];
                    let p_r = prev.ramp.as_ref().map_or(prev.target, |r| r.play(g.s0));
                    let d = -2.0 * g.target;
                    segs.push(Segment {
                        k: g.k,
                        target: g.target,
                        from,
                        s0: g.s0,
                        ramp: Some(Ramp::new(tr, d, b[a], p_r, from, tau)),
                        rate: 0.0,
                    });
                }
                segs
            })
            .collect();
        Self {
            axes: kept.iter().map(|&a| self.axes[a]).collect(),
            tau,
            zeta: None,
            length: self.length.clone(),
            segments,
        }
    }

    /// The offset per unit lost motion of axis `axes[a]` at grid sample `k`, where the path
    /// length is `s` (mm).
    pub fn offset(&self, a: usize, k: usize, s: f64) -> f64 {
        match self.zeta {
            None => offset_on(&self.segments[a], k, s, self.tau),
            Some(z) => ringing_on(&self.segments[a], k, s, self.tau, z).0,
        }
    }

    /// The index of `axis` among this lag's axes.
    pub fn position(&self, axis: AxisName) -> Option<usize> {
        self.axes.iter().position(|&a| a == axis)
    }

    /// The offsets of axis `axes[a]` at every grid sample (for tests and plots; the signatures
    /// only need the samples around the points).
    pub fn offsets(&self, part: &SShape, a: usize) -> Vec<f64> {
        (0..=REVERSAL_GRID)
            .map(|k| self.offset(a, k, self.length.at(part, grid_u(k))))
            .collect()
    }
}

/// `e_k = e* + (e_{k_r−1} − e*)·exp(−(s_k − s_{k_r−1})/τ)` on the segment holding `k` (`τ` the
/// lag, [`LAG_LENGTH`] at the reference); exactly `e*` on a settled first segment.
fn offset_on(segs: &[Segment], k: usize, s: f64, tau: f64) -> f64 {
    offset_in(&segs[segment_of(segs, k)], s, tau)
}

/// [`offset_on`] on its segment `g`.
fn offset_in(g: &Segment, s: f64, tau: f64) -> f64 {
    if let Some(r) = &g.ramp {
        // inside the take-up, or settling from its end
        return if s < r.end() {
            r.offset(s, tau)
        } else {
            g.target + (r.end_offset() - g.target) * (-(s - r.end()) / tau).exp()
        };
    }
    if g.from == g.target {
        g.target
    } else {
        g.target + (g.from - g.target) * (-(s - g.s0) / tau).exp()
    }
}

/// The path length from which [`offset_in`] is `g.target` to the last bit: where the settling's
/// remainder `|e₀ − e*|·exp(−x/τ)` has fallen below `|e*|·2⁻⁶⁰`, a sixteenth of half an ulp of
/// `e*` (so `e* + remainder` rounds to `e*` whatever the rounding of the exponential and of the
/// product), from the take-up's end when there is one; infinite when `e* = 0` (no ulp to hide
/// in). A dense scan's first-order members need no exponential past it (most of a short lag's
/// sites, issue 31): the same offsets.
fn settled_from(g: &Segment, tau: f64) -> f64 {
    let (start, left) = match &g.ramp {
        Some(r) => (r.end(), r.end_offset() - g.target),
        None => (g.s0, g.from - g.target),
    };
    if g.target == 0.0 || !g.target.is_finite() || !left.is_finite() || tau.is_nan() || tau <= 0.0 {
        return f64::INFINITY;
    }
    if left == 0.0 {
        return start;
    }
    let x = tau * (left.abs() / (g.target.abs() * SETTLED_SHARE)).ln();
    if x.is_finite() {
        start + x.max(0.0)
    } else {
        f64::INFINITY
    }
}

/// `2⁻⁶⁰`: the share of `|e*|` below which a first-order settling's remainder leaves the offset
/// `e*` to the bit ([`settled_from`]).
const SETTLED_SHARE: f64 = 1.0 / (1u64 << 60) as f64;

/// The offset `e` and its slope `de/ds` of a second-order settling on the segment holding `k`
/// (no take-up), where the path length is `s`: with `a = ζ/τ`, `ω = √(1 − ζ²)/τ`, `A = e₀ − e*`
/// and `B = (e'₀ + aA)/ω` from the segment's start,
/// `e = e* + exp(−a·x)(A cos ωx + B sin ωx)` and
/// `e' = exp(−a·x)(e'₀ cos ωx − (aB + ωA) sin ωx)`, `x = s − s₀`.
fn ringing_on(segs: &[Segment], k: usize, s: f64, tau: f64, zeta: f64) -> (f64, f64) {
    let g = &segs[segment_of(segs, k)];
    settling_of(g, tau, zeta).at(s - g.s0)
}

/// The index of the segment holding grid step `k`.
fn segment_of(segs: &[Segment], k: usize) -> usize {
    segs.partition_point(|g| g.k <= k).max(1) - 1
}

/// The second-order settling of segment `g` ([`Settling`]).
fn settling_of(g: &Segment, tau: f64, zeta: f64) -> Settling {
    Settling::new(g.target, g.from, g.rate, tau, zeta)
}

/// The signature of `backlash_<axis>` at the points per unit `b`: `e(s)·(∂p/∂q)·N`.
pub fn backlash_signature(
    part: &SShape,
    points: &[MeasurementPoint],
    axis: AxisName,
    opts: &SensitivityOptions,
) -> Result<Vec<f64>, SensitivityError> {
    Ok(backlash_signatures(part, points, &[axis], opts)?.remove(0))
}

/// [`backlash_signature`] for several axes at once (the passes are computed once): one vector
/// per axis, in the order of `axes`.
pub fn backlash_signatures(
    part: &SShape,
    points: &[MeasurementPoint],
    axes: &[AxisName],
    opts: &SensitivityOptions,
) -> Result<Vec<Vec<f64>>, SensitivityError> {
    backlash_signatures_on(&passes(part, opts)?, part, points, axes, opts)
}

/// [`backlash_signatures`] on passes already computed by [`passes`] with the same `opts`.
pub fn backlash_signatures_on(
    passes: &[Pass; 2],
    part: &SShape,
    points: &[MeasurementPoint],
    axes: &[AxisName],
    opts: &SensitivityOptions,
) -> Result<Vec<Vec<f64>>, SensitivityError> {
    let lags = [
        Lag::of(part, &passes[0], axes),
        Lag::of(part, &passes[1], axes),
    ];
    let q = axis_values(part, points, opts)?;
    backlash_signatures_lagged(&lags, part, points, &q, opts)
}

/// [`backlash_signatures`] on the lags of the passes of A and B ([`Lag::of`] with the axes wanted
/// and the same `opts`) at points whose axis values `q` are solved
/// ([`crate::sensitivity::defect::axis_values`], same `opts`): one vector per axis of the lags.
pub fn backlash_signatures_lagged(
    lags: &[Lag; 2],
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
) -> Result<Vec<Vec<f64>>, SensitivityError> {
    let gains = backlash_gains(part, points, q, &lags[0].axes, opts)?;
    Ok(lagged_columns(lags, part, points, &gains))
}

/// `(∂x/∂q)·N` of each axis of `axes` at each point (mm per mm or per rad): the normal
/// displacement of the contact point per unit of the axis, the factor of every backlash (and
/// servo) column that does not depend on the lag; one vector per axis.
pub fn backlash_gains(
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    axes: &[AxisName],
    opts: &SensitivityOptions,
) -> Result<Vec<Vec<f64>>, SensitivityError> {
    super::defect::check_poses(points, q)?;
    // `∂x/∂q` of the tool-body point at the contact point `x`: the axis's positioning error
    // motion `E{axis}{axis}` is exactly a change of its value. (On the flank, the contact point
    // and the tool-axis point at the same height differ by `10·N(u,1)`; for C, whose axis is
    // not perpendicular to the tool, their normal displacements differ.) Every axis's column
    // from one Jacobian a point: the chain's factors and products once, each column computed
    // as it would be alone.
    let params: Vec<ErrorParam> = axes.iter().map(|&a| ErrorParam::axis_value(a)).collect();
    let mut out = vec![Vec::with_capacity(points.len()); axes.len()];
    for (pt, q) in points.iter().zip(q) {
        let n = match opts.mode {
            Mode::Physical => pt.normal,
            Mode::Paper => part.frame_at(pt.surface, pt.u, 1.0).n,
        };
        let j = body_point_jacobian(&opts.chain, q, &pt.point, &MachineErrors::none(), &params)?;
        for (a, col) in out.iter_mut().enumerate() {
            col.push(j.column(a).dot(&n));
        }
    }
    Ok(out)
}

/// The backlash columns on the lags `lags` (A and B, same axes) from the gains of
/// [`backlash_gains`] (same axes, same points): `e(s)·(∂x/∂q)·N`.
pub fn lagged_columns(
    lags: &[Lag; 2],
    part: &SShape,
    points: &[MeasurementPoint],
    gains: &[Vec<f64>],
) -> Vec<Vec<f64>> {
    lagged_columns_at(lags, &grid_spots(lags, part, points), gains)
}

/// Where a point falls on the reversal grid of its surface's pass: `t` its fraction between the
/// samples `k − 1` and `k` around it (`k` the first sample at or after its `u`); the places a lag
/// is evaluated at for it, indices into [`GridSpots`]' sites: a first-order lag at the samples
/// `k − 1` and `k` (`linear`), a ringing one at the point's own path length on step `k`
/// (`ringing`). The same for every lag of the passes (their lengths are the passes').
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSpot {
    /// The point's surface: 0 for A, 1 for B.
    surface: usize,
    t: f64,
    linear: [usize; 2],
    ringing: usize,
}

/// A place a lag is evaluated at: the surface's pass, the grid step `k` whose segment holds it,
/// and the tool-tip path length `s` (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Site {
    surface: usize,
    k: usize,
    s: f64,
}

/// The [`GridSpot`] of each point and the distinct [`Site`]s they need: points whose `u` share
/// grid samples share the first-order sites (22,317 for 20,000 points of 40 heights, 36,794 for
/// 200,000 points of 100), a ringing site is a point's own path length. Both lists of sites are
/// in the order of their surface, step and path length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GridSpots {
    spots: Vec<GridSpot>,
    linear: Vec<Site>,
    ringing: Vec<Site>,
}

impl GridSpots {
    /// The number of points.
    pub fn len(&self) -> usize {
        self.spots.len()
    }

    /// Whether there is no point.
    pub fn is_empty(&self) -> bool {
        self.spots.is_empty()
    }

    /// The points `rows` (in that order), with every site kept.
    pub fn select_rows(&self, rows: &[usize]) -> Self {
        Self {
            spots: rows.iter().map(|&i| self.spots[i]).collect(),
            linear: self.linear.clone(),
            ringing: self.ringing.clone(),
        }
    }
}

/// The index of `site` in `sites`, pushed when new (`seen`: the sites so far by their bits).
fn site_index(
    sites: &mut Vec<Site>,
    seen: &mut FastHashMap<(usize, usize, u64), usize>,
    site: Site,
) -> usize {
    *seen
        .entry((site.surface, site.k, site.s.to_bits()))
        .or_insert_with(|| {
            sites.push(site);
            sites.len() - 1
        })
}

/// The [`GridSpots`] of the points on the passes of `lags` (one arc-length evaluation pair a
/// point, shared by every lag of a family): [`GridSpots::of`] their [`grid_places`].
pub fn grid_spots(lags: &[Lag; 2], part: &SShape, points: &[MeasurementPoint]) -> GridSpots {
    GridSpots::of(&grid_places(lags, part, points))
}

/// Where a point falls on the reversal grid, before its sites are shared ([`GridSpots::of`]):
/// its surface (0 for A, 1 for B), the first sample `k` at or after its `u`, its fraction `t`
/// between the samples `k − 1` and `k`, and their path lengths (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridPlace {
    surface: usize,
    k: usize,
    t: f64,
    s: [f64; 2],
}

/// The [`GridPlace`] of each point on the passes of `lags`, point by point (the blocks of a scan
/// side by side give the same places): the path length at a grid sample evaluated once for the
/// points that share it (a scan's heights often do: 22,317 samples for the 40,000 ends of 20,000
/// points).
pub fn grid_places(lags: &[Lag; 2], part: &SShape, points: &[MeasurementPoint]) -> Vec<GridPlace> {
    grid_places_with(
        &PassLengths::Tables(part, [&lags[0].length, &lags[1].length]),
        points,
    )
}

/// [`grid_places`] with the passes' path lengths from `lengths` (the lags' own: every lag of a
/// part has its passes' lengths); a length of a series ([`PassLengths::is_cheap`]) is
/// evaluated at each point, not looked up.
pub fn grid_places_with(lengths: &PassLengths, points: &[MeasurementPoint]) -> Vec<GridPlace> {
    let mut seen: HashMap<(usize, usize), f64> = HashMap::new();
    let cheap = lengths.is_cheap();
    points
        .iter()
        .map(|pt| {
            let surface = pt.surface.index();
            // Linear interpolation in u between the grid samples around the point (the
            // reference's convention; the exact lag from sample k-1 differs by < 1e-4
            // relative): k the first sample at or after u.
            let k = grid_after(pt.u);
            let (u0, u1) = (grid_u(k - 1), grid_u(k));
            let mut at = |k: usize, u: f64| {
                if cheap {
                    lengths.at(surface, u)
                } else {
                    *seen
                        .entry((surface, k))
                        .or_insert_with(|| lengths.at(surface, u))
                }
            };
            GridPlace {
                surface,
                k,
                t: (pt.u - u0) / (u1 - u0),
                s: [at(k - 1, u0), at(k, u1)],
            }
        })
        .collect()
}

impl GridSpots {
    /// The spots of points at `places` ([`grid_places`]), each distinct site once.
    pub fn of(places: &[GridPlace]) -> Self {
        Self::of_on(places, Threads::ONE)
    }

    /// [`GridSpots::of`], the linear and the ringing sites found side by side on `threads`
    /// threads (two independent passes over the places; at 200,000 points the one pass that
    /// found both had been ~40 ms of one thread): the same spots.
    pub fn of_on(places: &[GridPlace], threads: Threads) -> Self {
        // the sites by their bits, hashed by FastHasher (SipHash was a third of this loop at
        // 200,000 points), then in the order of their surface, step and path length (each
        // segment's sites together, in increasing length: a lag's segments are walked in order,
        // and a ringing segment's offsets are one slice, [`ringing_offsets`]), the spots'
        // indices renumbered
        let ((linear, at_linear), (ringing, at_ringing)) = join(
            threads,
            || {
                distinct_sites(places, |&GridPlace { surface, k, s, .. }| {
                    [
                        Site {
                            surface,
                            k: k - 1,
                            s: s[0],
                        },
                        Site {
                            surface,
                            k,
                            s: s[1],
                        },
                    ]
                })
            },
            || {
                distinct_sites(places, |&GridPlace { surface, k, t, s }| {
                    [Site {
                        surface,
                        k,
                        s: s[0] * (1.0 - t) + s[1] * t,
                    }]
                })
            },
        );
        let spots = places
            .iter()
            .zip(at_linear)
            .zip(at_ringing)
            .map(|((g, linear), [ringing])| GridSpot {
                surface: g.surface,
                t: g.t,
                linear,
                ringing,
            })
            .collect();
        GridSpots {
            spots,
            linear,
            ringing,
        }
    }
}

/// The distinct sites of `N` a place (`sites_of`), sorted ([`sort_sites`]), and each place's
/// `N` indices among them.
fn distinct_sites<const N: usize>(
    places: &[GridPlace],
    sites_of: impl Fn(&GridPlace) -> [Site; N],
) -> (Vec<Site>, Vec<[usize; N]>) {
    let mut sites = Vec::new();
    let mut seen = FastHashMap::default();
    let at: Vec<[usize; N]> = places
        .iter()
        .map(|g| sites_of(g).map(|site| site_index(&mut sites, &mut seen, site)))
        .collect();
    let new_of_old = sort_sites(&mut sites);
    let at = at.into_iter().map(|a| a.map(|i| new_of_old[i])).collect();
    (sites, at)
}

/// Sorts `sites` by surface, step and path length (distinct sites: a total order, so the same
/// order whatever their order before); the new index of each site's old one.
///
/// By path length ([`argsort`]: the crate's one copy of the sort code), then into buckets of
/// surface and step in that order (a counting sort, stable): an unstable sort of its own with this
/// comparison had been ~21 kB of the page's wasm (its sorting network inlined the comparison).
fn sort_sites(sites: &mut Vec<Site>) -> Vec<usize> {
    let by_s = argsort(&sites.iter().map(|x| x.s).collect::<Vec<f64>>());
    let steps = sites.iter().map(|x| x.k + 1).max().unwrap_or(0);
    let bucket = |x: &Site| x.surface * steps + x.k;
    // the first place of each bucket
    let mut next = vec![0usize; 2 * steps + 1];
    for x in sites.iter() {
        next[bucket(x) + 1] += 1;
    }
    for b in 1..next.len() {
        next[b] += next[b - 1];
    }
    let mut order = vec![0; sites.len()];
    for i in by_s {
        let b = bucket(&sites[i]);
        order[next[b]] = i;
        next[b] += 1;
    }
    let mut new_of_old = vec![0; sites.len()];
    for (new, &old) in order.iter().enumerate() {
        new_of_old[old] = new;
    }
    *sites = order.iter().map(|&i| sites[i]).collect();
    new_of_old
}

/// [`lagged_columns`] at the points' [`grid_spots`] on these passes.
pub fn lagged_columns_at(lags: &[Lag; 2], spots: &GridSpots, gains: &[Vec<f64>]) -> Vec<Vec<f64>> {
    (0..lags[0].axes.len())
        .map(|a| lagged_column_at(lags, a, spots, &gains[a]))
        .collect()
}

/// The column of axis `axes[a]` of [`lagged_columns_at`], its gain `gain`. A lag that rings
/// ([`Lag::zeta`]) is evaluated at the point's own path length on its step (the step's
/// segment: a turn at step `k` starts at sample `k − 1`), not interpolated linearly between the
/// samples (the two differ by the curvature of the settling over one grid step, ~0.014 mm): in
/// closed form, or from a segment's table of [`super::ringing`] on a dense scan (1e-9 of the
/// amplitude). Each distinct site of [`GridSpots`] is evaluated once.
pub fn lagged_column_at(lags: &[Lag; 2], a: usize, spots: &GridSpots, gain: &[f64]) -> Vec<f64> {
    // the offsets at the sites of the surfaces whose lag is of that kind; none when no
    // surface's lag is (a point reads the kind of its surface)
    let linear = first_order_offsets(lags, a, spots);
    let ringing = ringing_offsets(lags, a, spots);
    let first_order = |g: &GridSpot| linear[g.linear[0]] * (1.0 - g.t) + linear[g.linear[1]] * g.t;
    let rings = |g: &GridSpot| ringing[g.ringing];
    let points = spots.spots.iter().zip(gain);
    // (a member's passes are of one kind but for a given mix: the kind read once, not a point's
    // surface's at each point)
    match (lags[0].zeta.is_some(), lags[1].zeta.is_some()) {
        (false, false) => points.map(|(g, &gain)| first_order(g) * gain).collect(),
        (true, true) => points.map(|(g, &gain)| rings(g) * gain).collect(),
        _ => points
            .map(|(g, &gain)| {
                let e_pt = match lags[g.surface].zeta {
                    None => first_order(g),
                    Some(_) => rings(g),
                };
                e_pt * gain
            })
            .collect(),
    }
}

/// The offsets of axis `axes[a]` at the first-order sites of `spots` of the surfaces whose lag
/// is first-order (0 at the others'), [`offset_on`] each: the sites in order, so each surface's
/// segments are walked once instead of searched for each site; empty when no surface's lag is
/// first-order.
fn first_order_offsets(lags: &[Lag; 2], a: usize, spots: &GridSpots) -> Vec<f64> {
    if lags.iter().all(|p| p.zeta.is_some()) {
        return Vec::new();
    }
    let mut out = Vec::with_capacity(spots.linear.len());
    // the segment of the last site, on its surface, and where that segment has settled
    let mut at: Option<(usize, usize, f64)> = None;
    for x in &spots.linear {
        let p = &lags[x.surface];
        if p.zeta.is_some() {
            out.push(0.0);
            continue;
        }
        let segs = &p.segments[a];
        // [`segment_of`]'s segment: the last whose step is at most the site's (the first when
        // none is), found from the last site's on the same surface (the sites' steps increase)
        let last = match at {
            Some((surface, g, settled)) if surface == x.surface => Some((g, settled)),
            _ => None,
        };
        let mut g = last.map_or(0, |(g, _)| g);
        while g + 1 < segs.len() && segs[g + 1].k <= x.k {
            g += 1;
        }
        // (computed once a segment a site lands in, not for those passed over)
        let settled = match last {
            Some((h, settled)) if h == g => settled,
            _ => settled_from(&segs[g], p.tau),
        };
        at = Some((x.surface, g, settled));
        out.push(if x.s >= settled {
            segs[g].target
        } else {
            offset_in(&segs[g], x.s, p.tau)
        });
    }
    out
}

/// The offsets of axis `axes[a]` at the ringing sites of `spots` of the surfaces whose lag rings
/// (0 at the others'), a segment's sites at a time (one slice of the sorted sites, in increasing
/// path length: [`Settling::offsets_into`], from a table where a dense scan makes that cheaper,
/// issue 31); empty when no surface's lag rings.
fn ringing_offsets(lags: &[Lag; 2], a: usize, spots: &GridSpots) -> Vec<f64> {
    if lags.iter().all(|p| p.zeta.is_none()) {
        return Vec::new();
    }
    let sites = &spots.ringing;
    let mut out = vec![0.0; sites.len()];
    let mut xs = Vec::new();
    // the tables' nodes, one buffer for every segment
    let mut nodes = Vec::new();
    // runs of the sorted sites on one surface's segment: the segment is the one the closed form
    // finds by the first site's step ([`segment_of`]), the run ending at the next segment's step
    let mut start = 0;
    while start < sites.len() {
        let surface = sites[start].surface;
        let p = &lags[surface];
        let segs = &p.segments[a];
        let g = segment_of(segs, sites[start].k);
        let next_k = segs.get(g + 1).map_or(usize::MAX, |n| n.k);
        let end = start
            + sites[start..]
                .iter()
                .take_while(|x| x.surface == surface && x.k < next_k)
                .count();
        if let Some(zeta) = p.zeta {
            let seg = &segs[g];
            xs.clear();
            xs.extend(sites[start..end].iter().map(|x| x.s - seg.s0));
            settling_of(seg, p.tau, zeta).offsets_into_with(&xs, &mut out[start..end], &mut nodes);
        }
        start = end;
    }
    out
}

/// The first grid sample at or after `u`, within `1..=`[`REVERSAL_GRID`] (the partition point
/// of the grid's `u` values).
fn grid_after(u: f64) -> usize {
    let n = REVERSAL_GRID;
    let mut k = ((u * n as f64).ceil().max(0.0) as usize).min(n);
    while k > 0 && grid_u(k - 1) >= u {
        k -= 1;
    }
    while k < n && grid_u(k) < u {
        k += 1;
    }
    k.clamp(1, n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The five axes of the default chain.
    const FIVE_AXES: [AxisName; 5] = [
        AxisName::X,
        AxisName::Y,
        AxisName::Z,
        AxisName::B,
        AxisName::C,
    ];

    /// The closed form between turns is the grid's recursion `e_k = e* + (e_{k−1} − e*)·
    /// exp(−(s_k − s_{k−1})/2)` from a settled start, written out over all 20,001 samples with
    /// the same path lengths: equal to 1e-13 (the products of decays against one exp).
    #[test]
    fn the_closed_form_lag_is_the_recursion_of_its_definition() {
        let part = SShape::iso();
        let opts = SensitivityOptions::default();
        let axes = FIVE_AXES;
        for p in passes(&part, &opts).unwrap() {
            let lag = Lag::of(&part, &p, &axes);
            let s: Vec<f64> = (0..=REVERSAL_GRID)
                .map(|k| p.length.at(&part, grid_u(k)))
                .collect();
            for (a, &axis) in axes.iter().enumerate() {
                let d = directions(&p, axis);
                let mut e = vec![-0.5 * d[0]; d.len()];
                for k in 1..d.len() {
                    let target = -0.5 * d[k];
                    e[k] = target + (e[k - 1] - target) * (-(s[k] - s[k - 1]) / LAG_LENGTH).exp();
                }
                let got = lag.offsets(&part, a);
                let worst = e
                    .iter()
                    .zip(&got)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max);
                assert!(worst < 1e-13, "{axis:?}: {worst:e}");
            }
        }
    }

    /// Past [`settled_from`] a first-order segment's offset is its target to the bit: every
    /// segment of every axis of both passes of the ISO part, at lags from 0.1 to 30 mm, sampled
    /// every 0.05 mm from there to 40 mm further (where the exponential is still far from 0 for
    /// the long lags: the bound, not the underflow, decides).
    #[test]
    fn past_the_settled_length_the_offset_is_the_target_bit_for_bit() {
        let part = SShape::iso();
        let opts = SensitivityOptions::default();
        let axes = FIVE_AXES;
        let mut checked = 0;
        for p in passes(&part, &opts).unwrap() {
            for tau in [0.1, 1.0, 2.0, 7.5, 30.0] {
                let lag = Lag::with_settling(&part, &p, &axes, tau, None);
                for segs in &lag.segments {
                    for g in segs {
                        let from = settled_from(g, tau);
                        if !from.is_finite() {
                            continue;
                        }
                        for k in 0..800 {
                            let s = from + 0.05 * k as f64;
                            assert_eq!(
                                offset_in(g, s, tau).to_bits(),
                                g.target.to_bits(),
                                "τ {tau}: s {s} past {from}"
                            );
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 10_000, "{checked} offsets checked");
    }

    /// The second-order settling in closed form ([`ringing_on`]) against its definition,
    /// `e'' + 2ζe'/τ + e/τ² = e*/τ²` integrated by classical Runge-Kutta (4 steps a grid step,
    /// the target of step `k` the grid's direction there) over all 20,001 samples of both passes
    /// of the ISO part, for a lag of 3 mm that overshoots by 30 % (ζ 0.36): the same offsets to
    /// 1e-9 (RK4's error at h ≈ 0.004 mm is ~(h/τ)⁴ ≈ 1e-12 a step).
    #[test]
    fn the_closed_form_ringing_is_its_differential_equation() {
        let part = SShape::iso();
        let opts = SensitivityOptions::default();
        let (tau, zeta) = (3.0, 0.358_375);
        let axes = [AxisName::X, AxisName::B, AxisName::C];
        for p in passes(&part, &opts).unwrap() {
            let lag = Lag::with_settling(&part, &p, &axes, tau, Some(zeta));
            let s: Vec<f64> = (0..=REVERSAL_GRID)
                .map(|k| p.length.at(&part, grid_u(k)))
                .collect();
            let f =
                |x: [f64; 2], t: f64| [x[1], (t - x[0]) / (tau * tau) - 2.0 * zeta * x[1] / tau];
            for (a, &axis) in axes.iter().enumerate() {
                let d = directions(&p, axis);
                let mut x = [-0.5 * d[0], 0.0];
                let mut worst: f64 = 0.0;
                let got = lag.offsets(&part, a);
                for k in 1..d.len() {
                    let target = -0.5 * d[k];
                    let h = (s[k] - s[k - 1]) / 4.0;
                    for _ in 0..4 {
                        let k1 = f(x, target);
                        let k2 = f([x[0] + 0.5 * h * k1[0], x[1] + 0.5 * h * k1[1]], target);
                        let k3 = f([x[0] + 0.5 * h * k2[0], x[1] + 0.5 * h * k2[1]], target);
                        let k4 = f([x[0] + h * k3[0], x[1] + h * k3[1]], target);
                        for i in 0..2 {
                            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                        }
                    }
                    worst = worst.max((x[0] - got[k]).abs());
                }
                assert!(worst < 1e-9, "{axis:?}: {worst:e}");
                // it rings: past the new target somewhere on the pass when the axis turns
                if !d.windows(2).all(|w| w[0] == w[1]) {
                    assert!(got.iter().any(|&e| e.abs() > 0.55), "{axis:?}");
                }
            }
        }
    }

    /// The Hermite interpolant of a cubic is the cubic: q = t³ − 1.5t² + 0.6t turns and returns
    /// inside (rate 3t² − 3t + 0.6 < 0 between 0.276 and 0.724), q = t² − 0.6t turns at 0.3.
    #[test]
    fn hermite_turns_of_known_cubics() {
        assert!(hermite_dips(0.0, 0.1, 0.6, 0.6));
        assert!(!hermite_dips(0.0, 1.0, 1.0, 1.0));
        let t = hermite_root(0.0, 0.4, -0.6, 1.4).unwrap();
        assert!((t - 0.3).abs() < 1e-12, "{t}");
        assert!(hermite_root(0.0, 1.0, 1.0, 1.0).is_none());
    }

    /// Points that share their grid samples (the built-in 100 twice, the second time in reverse
    /// order, as a scan's heights share their rulings) share their sites: the sites of one copy
    /// serve both, and each point's value, first-order and ringing, on each axis, is the lag
    /// evaluated at that point alone (exactly: the same arithmetic, the sites' segments walked in
    /// order as each point's is searched).
    #[test]
    fn points_on_the_same_samples_share_their_sites() {
        let part = SShape::iso();
        let opts = SensitivityOptions::default();
        let axes = [AxisName::X, AxisName::C];
        let points = crate::part::builtin_points(&part);
        let twice: Vec<MeasurementPoint> =
            points.iter().chain(points.iter().rev()).cloned().collect();
        let p = passes(&part, &opts).unwrap();
        for zeta in [None, Some(0.4)] {
            let lags = [
                Lag::with_settling(&part, &p[0], &axes, 3.0, zeta),
                Lag::with_settling(&part, &p[1], &axes, 3.0, zeta),
            ];
            let one = grid_spots(&lags, &part, &points);
            let two = grid_spots(&lags, &part, &twice);
            // the linear and the ringing sites found side by side: the same spots
            let places = grid_places(&lags, &part, &twice);
            assert_eq!(GridSpots::of_on(&places, Threads::new(2)), two);
            assert_eq!(
                (two.linear.len(), two.ringing.len()),
                (one.linear.len(), one.ringing.len())
            );
            assert!(one.ringing.len() <= points.len() && one.linear.len() <= 2 * points.len());
            let gain = vec![1.0; twice.len()];
            for a in 0..axes.len() {
                let col = lagged_column_at(&lags, a, &two, &gain);
                for (i, pt) in twice.iter().enumerate() {
                    let l = &lags[usize::from(pt.surface != Surface::A)];
                    let k = grid_after(pt.u);
                    let (u0, u1) = (grid_u(k - 1), grid_u(k));
                    let t = (pt.u - u0) / (u1 - u0);
                    let (s0, s1) = (l.length.at(&part, u0), l.length.at(&part, u1));
                    let want = match zeta {
                        None => l.offset(a, k - 1, s0) * (1.0 - t) + l.offset(a, k, s1) * t,
                        Some(_) => l.offset(a, k, s0 * (1.0 - t) + s1 * t),
                    };
                    assert_eq!(col[i], want, "axis {a}, point {i}");
                }
            }
        }
    }

    /// [`sort_sites`] puts distinct sites in the order of (surface, step, path length), −0 before
    /// +0, and gives each old index its new one: 200 sites of 2 surfaces, 7 steps and path
    /// lengths with repeats across steps, in a scrambled order, against the comparison sort.
    #[test]
    fn sites_sort_by_surface_step_and_length() {
        let mut sites: Vec<Site> = (0..200)
            .map(|i| Site {
                surface: (i * 7) % 2,
                k: (i * 11) % 7,
                s: if i == 3 {
                    -0.0
                } else {
                    ((i * 37) % 50) as f64 * 0.5 - 5.0
                },
            })
            .collect();
        sites.push(Site {
            surface: sites[3].surface,
            k: sites[3].k,
            s: 0.0,
        });
        let old = sites.clone();
        let mut want = old.clone();
        want.sort_by(|x, y| {
            (x.surface, x.k)
                .cmp(&(y.surface, y.k))
                .then(x.s.total_cmp(&y.s))
        });
        let new_of_old = sort_sites(&mut sites);
        assert_eq!(sites.len(), want.len());
        for (got, w) in sites.iter().zip(&want) {
            assert_eq!(
                (got.surface, got.k, got.s.to_bits()),
                (w.surface, w.k, w.s.to_bits())
            );
        }
        for (i, x) in old.iter().enumerate() {
            let y = &sites[new_of_old[i]];
            assert_eq!(
                (x.surface, x.k, x.s.to_bits()),
                (y.surface, y.k, y.s.to_bits())
            );
        }
    }

    #[test]
    fn grid_after_is_the_partition_point_of_the_grid() {
        let grid: Vec<f64> = (0..=REVERSAL_GRID).map(grid_u).collect();
        for u in [0.0, 1e-9, 0.3, 0.123_456_789, 6.0 / 13.0, 0.999_99, 1.0] {
            let want = grid.partition_point(|x| *x < u).clamp(1, REVERSAL_GRID);
            assert_eq!(grid_after(u), want, "u = {u}");
        }
    }
}
