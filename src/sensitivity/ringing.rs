//! The second-order settling of a backlash member that rings, on one segment between two turns
//! ([`super::reversal`]'s `ringing_on`, effects.md "Shapes are families"), in closed form and
//! from a table for the many points of a dense scan.
//!
//! With `a = ζ/τ`, `ω = √(1 − ζ²)/τ`, `A = e₀ − e*` and `B = (e'₀ + aA)/ω` from the segment's
//! start, `e(x) = e* + exp(−a·x)(A cos ωx + B sin ωx)`, `x = s − s₀` (mm of tool-tip path).
//! Written complex: `e − e* = Re[c·exp(λx)]` and `e' = Re[c·λ·exp(λx)]` with `c = A − iB` and
//! `λ = −a + iω`, `|λ| = 1/τ`.
//!
//! **Table** (issue 31: a 20,000-point scan's family evaluates 36 ringing members at every point,
//! an exponential and a sine and cosine each, 0.14 s of CPU): nodes `x_j = x₀ + j·h` with
//! `h = τ·`[`TABLE_STEP`], `c·exp(λx_j)` by the recurrence `w_{j+1} = w_j·exp(λh)` (one complex
//! product a node, restarted from the closed form every [`RESTART`] nodes so its rounding stays
//! below 1e-13 relative), and a point between two nodes by the cubic Hermite interpolant of the
//! values and slopes there. Its error is at most `h⁴/384·max|e''''| ≤ (h/τ)⁴/384·|c|` (de Boor,
//! "A Practical Guide to Splines", 2001, ch. II eq. (17) for the Hermite cubic), 1.0e-9 of the
//! settling's amplitude at the step below. A segment is read from a table only when it holds
//! [`MIN_POINTS`] points or more and needs fewer than [`NODES_PER_POINT`] nodes a point (else the
//! closed form at each point is cheaper: the built-in 100 points always are).
//! Units: mm of path for `x`, `s`, `τ`; the offsets in units of the lost motion.

/// Node step of a table as a share of `τ`: `(1/40)⁴/384 = 1.0e-9` of the amplitude.
pub const TABLE_STEP: f64 = 1.0 / 40.0;

/// Nodes between two restarts of the recurrence from the closed form.
pub const RESTART: usize = 512;

/// Runs of the recurrence a [`Table`] advances side by side.
const INTERLEAVED: usize = 4;

/// A segment is tabulated when it needs at most this many nodes a point it holds (a node costs
/// a complex product, about 3 ns; a point in closed form an exponential and a sine and cosine,
/// about 40 ns; a point from the table about 5 ns).
pub const NODES_PER_POINT: f64 = 8.0;

/// ... and holds at least this many points: a part measured at discrete points (the built-in
/// 100, 25 a curve) keeps the closed form, and its figures their bits.
pub const MIN_POINTS: usize = 256;

/// Below this bound on `|e − e*|` (half an ulp of the offsets, ±1/2) the offset is `e*` exactly.
pub const SETTLED: f64 = 1e-17;

/// The closed form of one segment's settling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settling {
    /// `e*`, the offset it settles to.
    pub target: f64,
    /// `A = e₀ − e*`.
    pub a0: f64,
    /// `B = (e'₀ + aA)/ω`.
    pub b0: f64,
    /// `e'₀`.
    pub rate: f64,
    /// `a = ζ/τ` (per mm).
    pub decay: f64,
    /// `ω = √(1 − ζ²)/τ` (rad per mm).
    pub omega: f64,
    /// `τ`, the natural length (mm): the scale of a [`Table`]'s step.
    pub tau: f64,
}

impl Settling {
    /// The settling from offset `from` and slope `rate` towards `target`, natural length `tau`
    /// (mm) and damping `zeta` (0 < ζ < 1).
    pub fn new(target: f64, from: f64, rate: f64, tau: f64, zeta: f64) -> Self {
        let a0 = from - target;
        let decay = zeta / tau;
        let omega = (1.0 - zeta * zeta).sqrt() / tau;
        Self {
            target,
            a0,
            b0: (rate + decay * a0) / omega,
            rate,
            decay,
            omega,
            tau,
        }
    }

    /// Whether it stays at its target (no offset and no slope to settle).
    pub fn is_still(&self) -> bool {
        self.a0 == 0.0 && self.rate == 0.0
    }

    /// `(e, de/ds)` at `x` mm from the segment's start.
    pub fn at(&self, x: f64) -> (f64, f64) {
        if self.is_still() {
            return (self.target, 0.0);
        }
        let ex = (-self.decay * x).exp();
        if ex * (self.a0.abs() + self.b0.abs()) < SETTLED {
            return (self.target, 0.0);
        }
        let (sn, cs) = (self.omega * x).sin_cos();
        (
            self.target + ex * (self.a0 * cs + self.b0 * sn),
            ex * (self.rate * cs - (self.decay * self.b0 + self.omega * self.a0) * sn),
        )
    }

    /// The phase `c·exp(λx)` at `x` mm from the segment's start, exactly: `(A − iB)(cos ωx +
    /// i sin ωx)·exp(−a x)`, whose real part is `e − e*` (a [`Table`]'s nodes).
    fn phase_at(&self, x: f64) -> (f64, f64) {
        let ex = (-self.decay * x).exp();
        let (sn, cs) = (self.omega * x).sin_cos();
        (
            ex * (self.a0 * cs + self.b0 * sn),
            ex * (self.a0 * sn - self.b0 * cs),
        )
    }

    /// `exp(λh)`: the factor of the phase over a step of `h` mm (a [`Table`]'s recurrence).
    fn phase_step(&self, h: f64) -> (f64, f64) {
        let ex = (-self.decay * h).exp();
        let (sn, cs) = (self.omega * h).sin_cos();
        (ex * cs, ex * sn)
    }

    /// The `x` beyond which `exp(−a·x)·(|A| + |B|) < `[`SETTLED`]: [`Settling::at`]'s rule for
    /// `e*` exactly (to the rounding of the logarithm).
    pub fn settles_at(&self) -> f64 {
        ((self.a0.abs() + self.b0.abs()) / SETTLED).ln() / self.decay
    }

    /// `e` at each of `xs` (mm from the segment's start): from a [`Table`] when it is cheaper
    /// ([`NODES_PER_POINT`]), else in closed form.
    pub fn offsets(&self, xs: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; xs.len()];
        self.offsets_into(xs, &mut out);
        out
    }

    /// [`Settling::offsets`] written to `out` (as long as `xs`).
    pub fn offsets_into(&self, xs: &[f64], out: &mut [f64]) {
        self.offsets_into_with(xs, out, &mut Vec::new());
    }

    /// [`Settling::offsets_into`], a table's nodes in `buffer`: a buffer the caller keeps from one
    /// segment to the next (what it holds on entry does not matter; a table writes every node
    /// it reads), so that a member's tables are not each a fresh allocation zeroed before it
    /// is written (one zeroing of a table's size a segment had been 1.4 % of a 20,000-point
    /// scan's instructions, issue 31). The same offsets.
    pub fn offsets_into_with(&self, xs: &[f64], out: &mut [f64], buffer: &mut Vec<[f64; 2]>) {
        assert_eq!(
            xs.len(),
            out.len(),
            "offsets of {} points into {}",
            xs.len(),
            out.len()
        );
        if self.is_still() {
            out.fill(self.target);
            return;
        }
        let (lo, hi) = xs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            });
        // no node where every point reads e* ([`Table::at`])
        let hi = hi.min(self.settles_at());
        let h = self.tau * TABLE_STEP;
        let nodes = ((hi - lo).max(0.0) / h).ceil() + 2.0;
        // (not finite: a point at an infinite or undefined length, left to the closed form)
        let pays = nodes.is_finite() && nodes <= NODES_PER_POINT * xs.len() as f64;
        if xs.len() < MIN_POINTS || !pays {
            for (e, &x) in out.iter_mut().zip(xs) {
                *e = self.at(x).0;
            }
            return;
        }
        let table = Table::new_in(self, lo, h, nodes as usize, std::mem::take(buffer));
        for (e, &x) in out.iter_mut().zip(xs) {
            *e = table.at(self, x);
        }
        *buffer = table.nodes;
    }
}

/// Values and slopes of `e − e*` at the nodes `x₀ + j·h`, and where it has settled.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    x0: f64,
    h: f64,
    /// `[value, slope]` at each node (side by side: a point reads two nodes, one cache line)
    nodes: Vec<[f64; 2]>,
    /// Beyond this `x` the offset is `e*` ([`Settling::settles_at`]).
    settled: f64,
}

impl Table {
    /// The table of `n ≥ 2` nodes from `x0` by `h` (module doc).
    pub fn new(s: &Settling, x0: f64, h: f64, n: usize) -> Self {
        Self::new_in(s, x0, h, n, Vec::new())
    }

    /// [`Table::new`], its nodes written into `nodes` (its length set to `n`: only what it
    /// grows by is zeroed first; every node is then written, whatever it held).
    pub fn new_in(s: &Settling, x0: f64, h: f64, n: usize, mut nodes: Vec<[f64; 2]>) -> Self {
        let n = n.max(2);
        let (lr, li) = (-s.decay, s.omega);
        let step = s.phase_step(h);
        // the value and Re(λ·w)
        let node = |w: (f64, f64)| [w.0, lr * w.0 - li * w.1];
        // a run of RESTART nodes at a time: its first exactly, the others by the recurrence in a
        // loop with no call in it (the phase stays in registers: a call to `exp` inside the loop
        // had kept it in memory, ~1 % of a 20,000-point scan's CPU, issue 31)
        // (runs are independent: [`INTERLEAVED`] of them advance together, one complex product
        // each a step, so the products' latencies overlap instead of chaining, issue 31; each
        // run's numbers are its own, the same bits)
        nodes.resize(n, [0.0; 2]);
        let mut runs: Vec<&mut [[f64; 2]]> = nodes.chunks_mut(RESTART).collect();
        for (group, lanes) in runs.chunks_mut(INTERLEAVED).enumerate() {
            let first = group * INTERLEAVED;
            let mut w = [(0.0, 0.0); INTERLEAVED];
            for (i, slots) in lanes.iter_mut().enumerate() {
                w[i] = s.phase_at(x0 + ((first + i) * RESTART) as f64 * h);
                slots[0] = node(w[i]);
            }
            // the nodes every lane has advanced together (a last, short group each alone)
            let together = if lanes.len() == INTERLEAVED {
                lanes.iter().map(|l| l.len()).min().unwrap_or(1)
            } else {
                1
            };
            for j in 1..together {
                for (wi, slots) in w.iter_mut().zip(lanes.iter_mut()) {
                    *wi = (wi.0 * step.0 - wi.1 * step.1, wi.0 * step.1 + wi.1 * step.0);
                    slots[j] = node(*wi);
                }
            }
            for (wi, slots) in w.iter_mut().zip(lanes.iter_mut()) {
                for slot in &mut slots[together..] {
                    *wi = (wi.0 * step.0 - wi.1 * step.1, wi.0 * step.1 + wi.1 * step.0);
                    *slot = node(*wi);
                }
            }
        }
        Self {
            x0,
            h,
            nodes,
            settled: s.settles_at(),
        }
    }

    /// `e` at `x` (mm from the segment's start) by the cubic Hermite interpolant between the
    /// nodes around it (the end intervals extended); `e*` exactly once settled.
    pub fn at(&self, s: &Settling, x: f64) -> f64 {
        if x > self.settled {
            return s.target;
        }
        let last = self.nodes.len() - 2;
        let f = (x - self.x0) / self.h;
        // the node at or before `x`: `f`'s integer part, 0 below the first node (`as` truncates
        // and saturates: the floor of `f` clamped at 0 for every `f`, NaN to 0, without the call
        // to `floor` that the baseline x86-64 makes for each point)
        let j = ((f as i64).max(0) as usize).min(last);
        let t = f - j as f64;
        let (t2, t3) = (t * t, t * t * t);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        let ([v0, d0], [v1, d1]) = (self.nodes[j], self.nodes[j + 1]);
        s.target + h00 * v0 + h10 * self.h * d0 + h01 * v1 + h11 * self.h * d1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table's node index by truncation is the floor clamped at 0 for every `f`: fractions,
    /// integers, negatives, zeros of both signs, NaN, infinities and values past `usize`.
    #[test]
    fn the_node_index_is_the_clamped_floor() {
        let last = 1000;
        for f in [
            0.0,
            -0.0,
            0.3,
            1.0,
            1.999_999_999,
            2.5,
            999.9,
            1000.0,
            1e6,
            -0.5,
            -1.0,
            -7.2,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e19,
            1e300,
            -1e300,
        ] {
            let by_floor = (f.floor().max(0.0) as usize).min(last);
            let by_cast = ((f as i64).max(0) as usize).min(last);
            assert_eq!(by_cast, by_floor, "f = {f}");
        }
    }

    /// The closed form's slope is the derivative of its value (central differences, step 1e-5
    /// mm: error ~1e-10 of `|c|/τ`), and it solves `e'' + 2ζe'/τ + e/τ² = e*/τ²`.
    #[test]
    fn the_closed_form_solves_the_settling_equation() {
        let (tau, zeta) = (0.7, 0.3);
        let s = Settling::new(0.5, -0.5, 0.2, tau, zeta);
        let h = 1e-5;
        for x in [0.0, 0.3, 1.1, 2.9] {
            let (e, de) = s.at(x);
            let (ep, dep) = s.at(x + h);
            let (em, dem) = s.at(x - h);
            crate::assert_near!(de, (ep - em) / (2.0 * h), 1e-8);
            let d2 = (dep - dem) / (2.0 * h);
            crate::assert_near!(
                d2 + 2.0 * zeta * de / tau + e / (tau * tau),
                0.5 / (tau * tau),
                1e-6
            );
        }
        assert_eq!(s.at(0.0).0, -0.5);
        assert_eq!(s.at(0.0).1, 0.2);
    }

    /// The table against the closed form at 20,000 points over 40 mm, for the lags of the
    /// family's ends and middle (0.19, 2 and 16.3 mm) and both dampings (ζ 0.52 and 0.28):
    /// within 1.1e-9 of the amplitude `|A| + |B|` (the Hermite bound, 1.0e-9, plus rounding),
    /// and exactly the target once settled.
    #[test]
    fn the_table_is_the_closed_form_to_its_bound() {
        for tau in [0.19, 2.0, 16.3] {
            for zeta in [0.52, 0.28] {
                let s = Settling::new(-0.5, 0.5, 0.0, tau, zeta);
                let xs: Vec<f64> = (0..20_000).map(|i| 0.37 + i as f64 * 0.002).collect();
                let got = s.offsets(&xs);
                let amplitude = s.a0.abs() + s.b0.abs();
                let mut worst = 0.0f64;
                for (&x, &g) in xs.iter().zip(&got) {
                    worst = worst.max((g - s.at(x).0).abs() / amplitude);
                }
                assert!(worst < 1.1e-9, "tau {tau} zeta {zeta}: {worst:e}");
            }
        }
        // settled far out: the target itself
        let s = Settling::new(-0.5, 0.5, 0.0, 0.19, 0.52);
        let xs: Vec<f64> = (0..5_000).map(|i| 50.0 + i as f64 * 0.001).collect();
        assert!(s.offsets(&xs).iter().all(|&e| e == -0.5));
    }

    /// The nodes a run of [`RESTART`] at a time are, bit for bit, those of one loop over the
    /// nodes that sets the phase afresh every [`RESTART`] nodes (the table's loop before issue
    /// 31's runs, written out here on the same phase and step): 2 × RESTART + 300 nodes, two
    /// restarts and a short last run.
    #[test]
    fn the_nodes_by_runs_are_the_one_loop_recurrence() {
        let s = Settling::new(-0.5, 0.5, 0.1, 2.0, 0.28);
        let (x0, h, n) = (0.37, 0.002, 2 * RESTART + 300);
        let table = Table::new(&s, x0, h, n);
        let step = s.phase_step(h);
        let (mut w, mut since, mut want) = ((0.0, 0.0), RESTART, Vec::new());
        for j in 0..n {
            w = if since == RESTART {
                since = 0;
                s.phase_at(x0 + j as f64 * h)
            } else {
                (w.0 * step.0 - w.1 * step.1, w.0 * step.1 + w.1 * step.0)
            };
            since += 1;
            want.push([w.0, -s.decay * w.0 - s.omega * w.1]);
        }
        assert_eq!(table.nodes, want);
    }

    /// Fewer than [`MIN_POINTS`] points, even close together, are evaluated in closed form (the
    /// built-in layout's case): the same bits.
    #[test]
    fn few_points_take_the_closed_form() {
        let s = Settling::new(0.5, -0.5, 0.1, 2.0, 0.28);
        let xs: Vec<f64> = (0..MIN_POINTS - 1).map(|i| 0.5 + 0.01 * i as f64).collect();
        let want: Vec<f64> = xs.iter().map(|&x| s.at(x).0).collect();
        assert_eq!(s.offsets(&xs), want);
        let more: Vec<f64> = (0..MIN_POINTS).map(|i| 0.5 + 0.01 * i as f64).collect();
        let exact: Vec<f64> = more.iter().map(|&x| s.at(x).0).collect();
        assert_ne!(s.offsets(&more), exact);
    }
}
