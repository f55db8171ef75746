//! Position loops integrated in time: how an axis follows its command (paper 002 §4.3 simulates
//! the servo delay of an axis by a first-order system; Jiang et al., its ref. 14, test exactly
//! this on the S-shape).
//!
//! - **First order** (a P position loop of gain `Kv` around an ideal velocity loop):
//!   `q_a' = Kv (q_c − q_a)`. For a command linear in time between samples (slope `m`) the
//!   following error `e = q_c − q_a` obeys `e' = m − Kv e`, integrated exactly:
//!   `e_{k+1} = m/Kv + (e_k − m/Kv)·exp(−Kv Δt)`. On a ramp the axis trails by `m/Kv`, i.e. by
//!   `F/Kv` mm of tool-tip path.
//! - **Second order** (the same position loop around a velocity loop that is itself second
//!   order): `v_a'' + 2ζω v_a' + ω² v_a = ω² Kv (q_c − q_a)`, `q_a' = v_a` (the reference
//!   README's `sim_d`: ω = 2π·30 Hz, ζ = 0.7); its ramp lag is still `1/Kv`. Integrated by
//!   classical Runge–Kutta on sub-steps of at most [`RK_STEP_S`], the command linear in time
//!   between samples.
//!
//! Every loop starts at rest, settled on the first command (the feed switched on at `t = 0`, no
//! acceleration ramp), as the reference's simulations do. Units: the axis's own (mm or rad),
//! seconds, 1/s.

/// Largest Runge–Kutta sub-step of the second-order loop (s): `ω·h ≤ 0.02` at 30 Hz, where the
/// method's error per step (`(ωh)⁵/120`) is below 1e-10 of the state.
pub const RK_STEP_S: f64 = 1e-4;

/// How an axis's position loop responds.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "loop", rename_all = "snake_case")]
pub enum Response {
    /// `q_a' = Kv (q_c − q_a)`.
    FirstOrder,
    /// A second-order velocity loop of natural angular frequency `omega` (rad/s) and damping
    /// `zeta` inside the position loop.
    SecondOrder { omega: f64, zeta: f64 },
}

/// One axis's position loop: gain `kv` (1/s) and response.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AxisLoop {
    pub kv: f64,
    pub response: Response,
}

impl AxisLoop {
    /// A first-order loop of gain `kv` (1/s).
    pub fn first_order(kv: f64) -> Self {
        Self {
            kv,
            response: Response::FirstOrder,
        }
    }

    /// The axis position at every sample of `command` (samples `dt` seconds apart, the command
    /// linear between them), starting at rest on `command[0]`.
    pub fn follow(&self, command: &[f64], dt: f64) -> Vec<f64> {
        match self.response {
            Response::FirstOrder => first_order(command, dt, self.kv),
            Response::SecondOrder { omega, zeta } => {
                second_order(command, dt, self.kv, omega, zeta)
            }
        }
    }
}

fn first_order(command: &[f64], dt: f64, kv: f64) -> Vec<f64> {
    let decay = (-kv * dt).exp();
    let mut out = Vec::with_capacity(command.len());
    let Some(&first) = command.first() else {
        return out;
    };
    out.push(first);
    let mut e = 0.0;
    for w in command.windows(2) {
        let lag = (w[1] - w[0]) / dt / kv;
        e = lag + (e - lag) * decay;
        out.push(w[1] - e);
    }
    out
}

fn second_order(command: &[f64], dt: f64, kv: f64, omega: f64, zeta: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(command.len());
    let Some(&first) = command.first() else {
        return out;
    };
    out.push(first);
    // state: position, velocity, acceleration
    let mut x = [first, 0.0, 0.0];
    let subs = (dt / RK_STEP_S).ceil().max(1.0) as usize;
    let h = dt / subs as f64;
    let rate = |x: &[f64; 3], qc: f64| {
        [
            x[1],
            x[2],
            omega * omega * (kv * (qc - x[0]) - x[1]) - 2.0 * zeta * omega * x[2],
        ]
    };
    for w in command.windows(2) {
        let slope = (w[1] - w[0]) / dt;
        for j in 0..subs {
            let t0 = j as f64 * h;
            let qc = |t: f64| w[0] + slope * t;
            let k1 = rate(&x, qc(t0));
            let k2 = rate(&add(&x, &k1, h / 2.0), qc(t0 + h / 2.0));
            let k3 = rate(&add(&x, &k2, h / 2.0), qc(t0 + h / 2.0));
            let k4 = rate(&add(&x, &k3, h), qc(t0 + h));
            for i in 0..3 {
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        out.push(x[0]);
    }
    out
}

fn add(x: &[f64; 3], k: &[f64; 3], h: f64) -> [f64; 3] {
    [x[0] + h * k[0], x[1] + h * k[1], x[2] + h * k[2]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// On a ramp of slope `m` a first-order loop settles `m/Kv` behind (closed form), and the
    /// second-order loop of the same `Kv` too (its ramp lag is still `1/Kv`).
    #[test]
    fn a_ramp_is_followed_one_over_kv_behind() {
        let (dt, m, kv) = (5e-4, 25.0, 40.0);
        let ramp: Vec<f64> = (0..4000).map(|k| m * k as f64 * dt).collect();
        let a = AxisLoop::first_order(kv).follow(&ramp, dt);
        assert_near!(ramp[3999] - a[3999], m / kv, 1e-9);
        // exact at every sample: e(t) = (m/Kv)(1 − exp(−Kv t))
        let t = 100.0 * dt;
        assert_near!(ramp[100] - a[100], m / kv * (1.0 - (-kv * t).exp()), 1e-12);
        let second = AxisLoop {
            kv,
            response: Response::SecondOrder {
                omega: 2.0 * std::f64::consts::PI * 30.0,
                zeta: 0.7,
            },
        };
        let b = second.follow(&ramp, dt);
        assert_near!(ramp[3999] - b[3999], m / kv, 1e-7);
    }
}
