//! The play taken up after a reversal (paper 002 §4.3, Fig. 16: a backlash behind a first-order
//! servo; `shared/spec/effects.md`, "Shapes are families").
//!
//! An axis with lost motion `b` has a dead band of width `b` between its motor and its slide.
//! Moving one way the slide trails the command by `b/2`. After the command reverses, the slide
//! stands still until the command has travelled `b` back: the play's offset `p = y − q` moves
//! from `p_r` (its value at the turn) towards the new target `−d·b/2` (`d` the new direction) by
//! the axis's own travel `T(s) = d·(q(s) − q_r)` since the turn, and holds there once `T` has
//! taken up the band:
//!
//! `p(s)/b = clamp(p_r/b − d·T(s)/b, −1/2, 1/2)`.
//!
//! Near a turn `T ≈ ½|q''|Δs²`, so the take-up lasts `Δs ≈ √(2b/|q''|)` of tool-tip path: it
//! depends on `b` itself, which is why the backlash family refits its shape with the `b` the
//! diagnosis found ([`crate::analysis`]). With `b → 0` the offset switches at the turn, the
//! catalogue's backlash ([`super::reversal`]).
//!
//! The servo settles the offset as a first-order lag of `τ` mm of path, `de/ds = (p − e)/τ`,
//! integrated exactly for `p` linear between the travel's samples.
//!
//! **The travel** is solved by the inverse kinematics at every [`TAKE_UP_STRIDE`]-th sample of
//! the reversal grid after each turn, over [`TAKE_UP_WINDOW`] mm of path (or to the next turn).
//! Units: mm of tool-tip path; `T`, `b` in the axis's unit (mm or rad); `p`, `e` per unit `b`.

use crate::machine::AxisName;
use crate::part::SShape;

use super::defect::SensitivityOptions;
use super::path::machine_path;
use super::reversal::{grid_u, Pass, REVERSAL_GRID};
use super::SensitivityError;

/// Path after a turn over which the travel is sampled (mm): 1.3 × the family's longest lag
/// (15 mm, effects.md). A take-up not finished there ends at it (the offset then settles to its
/// target as at a switch).
pub const TAKE_UP_WINDOW: f64 = 20.0;
/// Grid steps between the travel's samples (the grid's step is ~0.014 mm of path on the ISO
/// part: ~0.07 mm between samples, 1/30 of the shortest take-up the tests show).
pub const TAKE_UP_STRIDE: usize = 5;

/// One axis's travel in its new direction after one turn.
#[derive(Debug, Clone, PartialEq)]
pub struct TurnTravel {
    /// Tool-tip path length of each sample (mm from the start of the pass); the first is the
    /// turn's (grid sample `k − 1` of the turn `(k, d)`).
    pub s: Vec<f64>,
    /// `T = d·(q − q_r)` at each sample (mm or rad), 0 at the first.
    pub t: Vec<f64>,
}

/// The travel after every turn of each axis of `axes` on pass `p` (one list per axis, one
/// [`TurnTravel`] per turn of [`Pass::turns_of`], in order); an axis the chain does not have
/// has none.
pub fn travels(
    part: &SShape,
    p: &Pass,
    axes: &[AxisName],
    opts: &SensitivityOptions,
) -> Result<Vec<Vec<TurnTravel>>, SensitivityError> {
    let mut out = Vec::with_capacity(axes.len());
    for &a in axes {
        let mut per_turn = Vec::new();
        if let Some(turns) = p.turns_of(a) {
            for (i, &(k, d)) in turns.at.iter().enumerate() {
                let start = k - 1;
                let s0 = p.length.at(part, grid_u(start));
                // to the next turn's sample k − 1 (its turning point), or the grid's end
                let stop = turns.at.get(i + 1).map_or(REVERSAL_GRID, |t| t.0 - 1);
                let mut ks: Vec<usize> = (start..=stop).step_by(TAKE_UP_STRIDE).collect();
                if ks.last() != Some(&stop) {
                    ks.push(stop);
                }
                // the window: samples whose path from the turn is within it, and the first past
                // it
                let mut s = Vec::with_capacity(ks.len());
                let mut us = Vec::with_capacity(ks.len());
                for k in ks {
                    let sk = p.length.at(part, grid_u(k));
                    s.push(sk);
                    us.push(grid_u(k));
                    if sk - s0 > TAKE_UP_WINDOW {
                        break;
                    }
                }
                let q = machine_path(part, &opts.chain, p.surface, opts.branch, &us)?;
                let q0 = q[0].values.get(a);
                per_turn.push(TurnTravel {
                    s,
                    t: q.iter().map(|x| d * (x.values.get(a) - q0)).collect(),
                });
            }
        }
        out.push(per_turn);
    }
    Ok(out)
}

/// The play's offset and its settling over one take-up, per unit `b` (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Ramp {
    /// Path length of each sample (mm), from the turn to the ramp's end (where the band is
    /// taken up, the window ends or the next turn comes).
    s: Vec<f64>,
    /// The play `p/b` at each sample.
    p: Vec<f64>,
    /// The settled offset `e/b` at each sample.
    e: Vec<f64>,
}

impl Ramp {
    /// The take-up after a turn to direction `d` with travel `travel`, lost motion `b` (> 0, the
    /// axis's unit), the play `p_r` and the offset `e_r` (per unit `b`) at the turn, and the
    /// servo's lag `tau` (mm of path).
    pub fn new(travel: &TurnTravel, d: f64, b: f64, p_r: f64, e_r: f64, tau: f64) -> Self {
        let target = -0.5 * d;
        let play = |t: f64| (p_r - d * t / b).clamp(-0.5, 0.5);
        let mut s = vec![travel.s[0]];
        let mut p = vec![p_r];
        let mut e = vec![e_r];
        // the travel that takes the band up: p reaches its target
        let needed = (p_r - target).abs() * b;
        for j in 1..travel.s.len() {
            let (t0, t1) = (travel.t[j - 1], travel.t[j]);
            let (s0, s1) = (travel.s[j - 1], travel.s[j]);
            let (end_s, end_p, done) = if t1 >= needed && t1 > t0 {
                let f = ((needed - t0) / (t1 - t0)).clamp(0.0, 1.0);
                (s0 + f * (s1 - s0), target, true)
            } else {
                (s1, play(t1), false)
            };
            let last = e.len() - 1;
            let next = settle(e[last], p[last], end_p, end_s - s[last], tau);
            s.push(end_s);
            p.push(end_p);
            e.push(next);
            if done {
                break;
            }
        }
        Self { s, p, e }
    }

    /// Path length where the ramp ends (mm).
    pub fn end(&self) -> f64 {
        self.s[self.s.len() - 1]
    }

    /// The offset `e/b` at the ramp's end.
    pub fn end_offset(&self) -> f64 {
        self.e[self.e.len() - 1]
    }

    /// The play `p/b` at `s` (held at the first and last samples outside the ramp).
    pub fn play(&self, s: f64) -> f64 {
        let j = self.s.partition_point(|x| *x <= s);
        if j == 0 {
            return self.p[0];
        }
        if j == self.s.len() {
            return self.p[j - 1];
        }
        let f = (s - self.s[j - 1]) / (self.s[j] - self.s[j - 1]);
        self.p[j - 1] + f * (self.p[j] - self.p[j - 1])
    }

    /// The offset `e/b` at `s` inside the ramp (`s` from the turn to [`Ramp::end`]), for the lag
    /// `tau` the ramp was built with.
    pub fn offset(&self, s: f64, tau: f64) -> f64 {
        let j = self.s.partition_point(|x| *x <= s).max(1);
        if j == self.s.len() {
            return self.end_offset();
        }
        let i = j - 1;
        settle(self.e[i], self.p[i], self.play(s), s - self.s[i], tau)
    }
}

/// The first-order lag `de/ds = (p − e)/τ` over `h` mm with `p` linear from `p0` to `p1`, from
/// `e0`: exact (`e − p + mτ` decays, `m` the slope of `p`).
fn settle(e0: f64, p0: f64, p1: f64, h: f64, tau: f64) -> f64 {
    if h <= 0.0 {
        return e0;
    }
    let m = (p1 - p0) / h;
    p1 - m * tau + (e0 - p0 + m * tau) * (-h / tau).exp()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// A travel `T = ½κΔs²` (κ = 1e-3 per mm², b = 2e-3: the band is taken up after
    /// √(2b/κ) = 2 mm) from a settled offset +1/2 (moving down, turning up, d = +1): the play is
    /// `1/2 − T/b` until 2 mm, then −1/2; the settled offset integrated by small explicit Euler
    /// steps (1e-5 mm) agrees to 1e-4; with b → 0 the ramp is the switch at the turn.
    #[test]
    fn a_quadratic_travel_takes_up_the_band_after_its_square_root_law() {
        let (kappa, b, tau) = (1e-3, 2e-3, 0.7);
        let s: Vec<f64> = (0..=400).map(|j| j as f64 * 0.05).collect();
        let travel = TurnTravel {
            t: s.iter().map(|x| 0.5 * kappa * x * x).collect(),
            s: s.clone(),
        };
        let r = Ramp::new(&travel, 1.0, b, 0.5, 0.5, tau);
        assert_near!(r.end(), (2.0 * b / kappa).sqrt(), 1e-12);
        assert_near!(r.play(1.0), 0.5 - 0.5 * kappa / b, 1e-3);
        assert_near!(r.play(5.0), -0.5, 0.0);
        // explicit Euler on the exact play
        let exact_p = |x: f64| (0.5 - 0.5 * kappa * x * x / b).max(-0.5);
        let (mut e, mut x, h) = (0.5, 0.0, 1e-5);
        while x < 1.5 - 1e-12 {
            e += h * (exact_p(x) - e) / tau;
            x += h;
        }
        assert_near!(r.offset(1.5, tau), e, 1e-4);
        // a tiny band: taken up within the first sample, the offset barely moved
        let quick = Ramp::new(&travel, 1.0, 1e-12, 0.5, 0.5, tau);
        assert!(quick.end() < 1e-3, "{}", quick.end());
        assert_near!(quick.end_offset(), 0.5, 1e-3);
    }
}
