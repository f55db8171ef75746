//! Arc length of a parametric curve and its inverse (the parameter at a given length).
//!
//! `L(u) = ∫_{u0}^{u} |C'(t)| dt` by 5-point Gauss–Legendre on `per_span` equal pieces of each
//! interval between consecutive `breaks` (for a B-spline: its distinct knots, where the speed is
//! smooth inside each interval, so the rule converges geometrically). The inverse `u(L)` is found
//! by Newton's method `u ← u - (L(u) - L*)/|C'(u)|`, safeguarded by bisection inside the piece.
//! Units: those of the curve (mm); `u` unitless.

use super::GeometryError;

const GL_X: [f64; 5] = [
    0.0,
    -0.538_469_310_105_683_1,
    0.538_469_310_105_683_1,
    -0.906_179_845_938_664,
    0.906_179_845_938_664,
];
const GL_W: [f64; 5] = [
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_47,
    0.478_628_670_499_366_47,
    0.236_926_885_056_189_08,
    0.236_926_885_056_189_08,
];

/// 5-point Gauss–Legendre integral of `f` over `[a, b]`.
fn gauss5(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    GL_X.iter()
        .zip(GL_W)
        .map(|(x, w)| w * f(mid + half * x))
        .sum::<f64>()
        * half
}

/// The cumulative table of an arc length without its speed function: owned data that can be
/// kept (a settings cache), evaluated with the same speed passed again.
#[derive(Debug, Clone, PartialEq)]
pub struct LengthTable {
    /// piece boundaries, increasing
    nodes: Vec<f64>,
    /// `L(nodes[i])`
    cumulative: Vec<f64>,
}

impl LengthTable {
    /// Builds the table; `breaks` are the increasing interval ends (duplicates are ignored).
    pub fn new(speed: &impl Fn(f64) -> f64, breaks: &[f64], per_span: usize) -> Self {
        let mut b = breaks.to_vec();
        b.dedup();
        let per_span = per_span.max(1);
        let mut nodes = vec![b[0]];
        for w in b.windows(2) {
            for k in 1..=per_span {
                nodes.push(w[0] + (w[1] - w[0]) * k as f64 / per_span as f64);
            }
        }
        let mut cumulative = vec![0.0];
        for w in nodes.windows(2) {
            let last = cumulative[cumulative.len() - 1];
            cumulative.push(last + gauss5(speed, w[0], w[1]));
        }
        Self { nodes, cumulative }
    }

    /// Total length (mm).
    pub fn total(&self) -> f64 {
        self.cumulative[self.cumulative.len() - 1]
    }

    /// The pieces' boundaries and the length at each ([`super::length_series`]).
    pub(super) fn pieces(&self) -> (&[f64], &[f64]) {
        (&self.nodes, &self.cumulative)
    }

    /// Index of the piece holding `u` (clamped).
    pub(super) fn piece(&self, u: f64) -> usize {
        let k = self.nodes.partition_point(|n| *n <= u);
        k.saturating_sub(1).min(self.nodes.len() - 2)
    }

    /// `u` clamped to the domain.
    pub(super) fn clamp(&self, u: f64) -> f64 {
        u.clamp(self.nodes[0], self.nodes[self.nodes.len() - 1])
    }

    /// `L(u)` from the start of the domain (mm), `speed` the one the table was built with; `u`
    /// is clamped to the domain.
    pub fn length_at(&self, speed: &impl Fn(f64) -> f64, u: f64) -> f64 {
        let u = self.clamp(u);
        let k = self.piece(u);
        self.cumulative[k] + gauss5(speed, self.nodes[k], u)
    }
}

/// A cumulative arc-length table of a curve given by its speed `|C'(u)|`.
pub struct ArcLength<F: Fn(f64) -> f64> {
    speed: F,
    table: LengthTable,
}

impl<F: Fn(f64) -> f64> ArcLength<F> {
    /// Builds the table; `breaks` are the increasing interval ends (duplicates are ignored).
    pub fn new(speed: F, breaks: &[f64], per_span: usize) -> Self {
        let table = LengthTable::new(&speed, breaks, per_span);
        Self { speed, table }
    }

    /// Total length (mm).
    pub fn total(&self) -> f64 {
        self.table.total()
    }

    /// `L(u)` from the start of the domain (mm); `u` is clamped to the domain.
    pub fn length_at(&self, u: f64) -> f64 {
        self.table.length_at(&self.speed, u)
    }

    /// The parameter `u` with `L(u) = length` (mm), to `|ΔL| < 1e-12 mm`.
    pub fn param_at(&self, length: f64) -> Result<f64, GeometryError> {
        let total = self.total();
        if !(0.0..=total).contains(&length) {
            return Err(GeometryError::ArcLengthOutOfRange { length, total });
        }
        let t = &self.table;
        let k = t
            .cumulative
            .partition_point(|c| *c <= length)
            .saturating_sub(1)
            .min(t.nodes.len() - 2);
        let (mut lo, mut hi) = (t.nodes[k], t.nodes[k + 1]);
        let frac = (length - t.cumulative[k]) / (t.cumulative[k + 1] - t.cumulative[k]);
        let mut u = lo + frac * (hi - lo);
        for _ in 0..100 {
            let err = t.cumulative[k] + gauss5(&self.speed, t.nodes[k], u) - length;
            if err.abs() < 1e-12 {
                return Ok(u);
            }
            if err > 0.0 {
                hi = u;
            } else {
                lo = u;
            }
            let newton = u - err / (self.speed)(u);
            u = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if hi - lo < 1e-15 {
                return Ok(u);
            }
        }
        Ok(u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn circle_quarter_has_closed_form_length() {
        // C(u) = 5 (cos(πu/2), sin(πu/2)): speed 5π/2, length at u = 5πu/2.
        let a = ArcLength::new(|_| 2.5 * std::f64::consts::PI, &[0.0, 0.5, 1.0], 2);
        assert_near!(a.total(), 2.5 * std::f64::consts::PI, 1e-13);
        assert_near!(a.param_at(a.total() * 0.3).unwrap(), 0.3, 1e-13);
    }

    #[test]
    fn inverse_of_a_non_uniform_speed() {
        // C(u) = (u, u²): speed sqrt(1 + 4u²), L(u) = (u s + asinh(2u)/2)/2.
        let speed = |u: f64| (1.0 + 4.0 * u * u).sqrt();
        let exact = |u: f64| 0.5 * (u * speed(u) + 0.5 * (2.0 * u).asinh());
        let a = ArcLength::new(speed, &[0.0, 0.25, 0.5, 0.75, 1.0], 4);
        for i in 0..=20 {
            let u = i as f64 / 20.0;
            assert_near!(a.length_at(u), exact(u), 1e-13);
            assert_near!(a.param_at(exact(u)).unwrap(), u, 1e-12);
        }
        assert!(a.param_at(-1.0).is_err());
    }
}
