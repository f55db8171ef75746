//! Lost motion of one axis: a play (dead band) between the motor and the slide, and the servo's
//! settling once the play is taken up (paper 002 §4.3, Fig. 16: a backlash model behind a
//! first-order servo).
//!
//! **Play.** The slide `y` stays where it is while the command `q` moves inside a band of width
//! `b` around it, and is dragged at the band's edge: `y_k = clamp(y_{k−1}, q_k − b/2, q_k + b/2)`.
//! Moving up, the slide trails by `b/2`; after a reversal it stands still until the command has
//! travelled `b` back, so the offset `p = y − q` changes from `−b/2` to `+b/2` over a command
//! travel of `b` (a step in time only when the axis reverses fast). Each pass starts settled for
//! its first direction of motion (effects.md).
//!
//! **Settling.** The offset reaches the slide through the servo: `e` follows `p` by a linear
//! response in path length `s` (mm of tool-tip path, the clock of a pass at constant feed):
//! - first order, lag `τ`: `de/ds = (p − e)/τ`, integrated exactly for `p` linear between
//!   samples;
//! - underdamped, `e'' + 2ζ e'/τ + e/τ² = p/τ²` (natural length `τ`, damping `ζ < 1`: the slide
//!   overshoots and rings after each reversal), by Runge–Kutta on sub-steps of at most `τ/20`.
//!
//! The actual axis position is `q + e`. Units: the axis's own (mm or rad); `τ` in mm of path.

/// How the lost motion settles after a reversal.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "response", rename_all = "snake_case")]
pub enum Settling {
    /// First-order lag of `tau` mm of tool-tip path.
    FirstOrder { tau: f64 },
    /// Second order of natural length `tau` mm and damping `zeta` (< 1: rings).
    Underdamped { tau: f64, zeta: f64 },
}

/// Play `b` and its settling on one axis.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LostMotion {
    /// Width of the play (mm, or rad for a rotary axis).
    pub b: f64,
    pub settling: Settling,
}

impl LostMotion {
    /// The offset `e_k` of the slide from the command at each sample of `q` (the axis command
    /// every `step` mm of tool-tip path).
    pub fn offsets(&self, q: &[f64], step: f64) -> Vec<f64> {
        let p = play(q, self.b);
        match self.settling {
            Settling::FirstOrder { tau } => first_order(&p, step, tau),
            Settling::Underdamped { tau, zeta } => underdamped(&p, step, tau, zeta),
        }
    }
}

/// The play's offset `y − q` at each sample, settled at the start for the first motion.
pub fn play(q: &[f64], b: f64) -> Vec<f64> {
    let half = 0.5 * b;
    let first_direction = q
        .windows(2)
        .map(|w| w[1] - w[0])
        .find(|d| *d != 0.0)
        .map_or(1.0, f64::signum);
    let mut out = Vec::with_capacity(q.len());
    let Some(&q0) = q.first() else {
        return out;
    };
    let mut y = q0 - half * first_direction;
    for &qk in q {
        y = y.clamp(qk - half, qk + half);
        out.push(y - qk);
    }
    out
}

fn first_order(p: &[f64], step: f64, tau: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(p.len());
    let Some(&first) = p.first() else {
        return out;
    };
    let decay = (-step / tau).exp();
    // e follows p; with p linear between samples (slope m per mm), e − p + mτ decays.
    let mut e = first;
    out.push(e);
    for w in p.windows(2) {
        let m = (w[1] - w[0]) / step;
        let gap = e - w[0] + m * tau;
        e = w[1] - m * tau + gap * decay;
        out.push(e);
    }
    out
}

fn underdamped(p: &[f64], step: f64, tau: f64, zeta: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(p.len());
    let Some(&first) = p.first() else {
        return out;
    };
    let subs = (20.0 * step / tau).ceil().max(1.0) as usize;
    let h = step / subs as f64;
    let mut x = [first, 0.0];
    out.push(first);
    let rate = |x: &[f64; 2], pk: f64| [x[1], (pk - x[0]) / (tau * tau) - 2.0 * zeta * x[1] / tau];
    for w in p.windows(2) {
        let m = (w[1] - w[0]) / step;
        for j in 0..subs {
            let s0 = j as f64 * h;
            let at = |s: f64| w[0] + m * s;
            let k1 = rate(&x, at(s0));
            let k2 = rate(
                &[x[0] + h / 2.0 * k1[0], x[1] + h / 2.0 * k1[1]],
                at(s0 + h / 2.0),
            );
            let k3 = rate(
                &[x[0] + h / 2.0 * k2[0], x[1] + h / 2.0 * k2[1]],
                at(s0 + h / 2.0),
            );
            let k4 = rate(&[x[0] + h * k3[0], x[1] + h * k3[1]], at(s0 + h));
            x[0] += h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]);
            x[1] += h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]);
        }
        out.push(x[0]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// A command up then down: the slide trails by b/2 going up, stands still for b of command
    /// travel after the reversal, then trails by b/2 the other way.
    #[test]
    fn play_switches_over_a_command_travel_of_b() {
        let b = 0.01;
        let q: Vec<f64> = (0..=200)
            .map(|k| {
                if k <= 100 {
                    k as f64 * 1e-3
                } else {
                    0.2 - k as f64 * 1e-3
                }
            })
            .collect();
        let p = play(&q, b);
        assert_near!(p[50], -b / 2.0, 1e-15);
        // 5 samples (5e-3 of command) after the reversal: halfway through the band
        assert_near!(p[105], 0.0, 1e-12);
        assert_near!(p[150], b / 2.0, 1e-15);
        // settled response of a step: first order reaches 1 − e⁻¹ of it after τ
        let step: Vec<f64> = (0..=1000)
            .map(|k| if k < 100 { 0.0 } else { 1.0 })
            .collect();
        let e = first_order(&step, 0.01, 1.0);
        assert!(e[99].abs() < 1e-12);
        // one τ after the step (a ramp over 1 % of τ): 1 − e⁻¹ to within that 1 %
        assert!(
            (e[200] - (1.0 - (-1.0f64).exp())).abs() < 0.01,
            "{}",
            e[200]
        );
        let u = underdamped(&step, 0.01, 1.0, 0.3);
        let peak = u.iter().copied().fold(0.0, f64::max);
        // overshoot of a second-order step, at 3.3 τ: exp(−ζπ/√(1−ζ²)) = 0.372 at ζ = 0.3
        assert!((peak - 1.372).abs() < 0.01, "{peak}");
    }
}
