//! Noise σ independent of smooth structure: the residual of the baseline augmented with a smooth
//! basis along each curve.
//!
//! On each curve, with `t ∈ [−1, 1]` the tool-path length `s` mapped linearly over the curve's
//! points, the Legendre polynomials `P₀(t) … P_d(t)` (d = [`SMOOTH_DEGREE`]) are added to the
//! baseline design `A`. Any effect that varies smoothly along the curves (a constant such as a
//! tool-radius error, a taper, a drift, a scale error, a waviness longer than about a sixth of the
//! curve), and every combination of the baseline's own signatures, is then fitted away, so
//! `σ² = RSS/(n − rank)` of this augmented fit estimates the measurement noise alone. Also
//! returned, a robust version `1.4826·median|r|·√(n/(n − rank))` that ignores the few points a
//! step (an axis reversal) leaves unfitted.

use nalgebra::{DMatrix, DVector};

use crate::effects::data::PointMeta;
use crate::effects::data::{curve_sequences, is_scan};
use crate::identify::solve::{hstack, Factor};
use crate::measurement::layout::curve_degree;
use crate::numerics::parallel::Threads;
use crate::part::Surface;

/// Degree of the per-curve Legendre basis.
pub const SMOOTH_DEGREE: usize = 5;

/// Legendre polynomials `P_0..P_d` at `t` (Bonnet's recursion).
pub fn legendre(t: f64, d: usize) -> Vec<f64> {
    let mut p = vec![1.0, t];
    for k in 1..d {
        let kf = k as f64;
        let next = ((2.0 * kf + 1.0) * t * p[k] - kf * p[k - 1]) / (kf + 1.0);
        p.push(next);
    }
    p.truncate(d + 1);
    p
}

/// The per-curve smooth basis: on a curve of `m` points the Legendre polynomials up to degree
/// [`curve_degree`]`(m, degree)` (`degree` on the built-in layout's 25 points a curve), so that
/// half of a curve's points always remain to measure the noise ([`crate::measurement::layout`]).
/// A scan's points ([`is_scan`]) have the two-dimensional basis of [`surface_basis`] instead.
pub fn smooth_basis(points: &[PointMeta], degree: usize) -> DMatrix<f64> {
    if is_scan(points) {
        return surface_basis(points, degree, HEIGHT_DEGREE);
    }
    let seqs = curve_sequences(points);
    let widths: Vec<usize> = seqs
        .iter()
        .map(|(_, idx)| curve_degree(idx.len(), degree) + 1)
        .collect();
    let mut m = DMatrix::zeros(points.len(), widths.iter().sum());
    let mut first = 0;
    for ((_, idx), k) in seqs.iter().zip(widths) {
        let lo = idx
            .iter()
            .map(|&i| points[i].s)
            .fold(f64::INFINITY, f64::min);
        let hi = idx
            .iter()
            .map(|&i| points[i].s)
            .fold(f64::NEG_INFINITY, f64::max);
        let span = (hi - lo).max(1e-12);
        for &i in idx {
            let t = 2.0 * (points[i].s - lo) / span - 1.0;
            for (j, v) in legendre(t, k - 1).into_iter().enumerate() {
                m[(i, first + j)] = v;
            }
        }
        first += k;
    }
    m
}

/// Degree in height of a scan's smooth basis ([`surface_basis`]).
pub const HEIGHT_DEGREE: usize = 3;

/// The smooth basis of a scan: on each surface, with `t ∈ [−1, 1]` the tool-path length `s` and
/// `η ∈ [−1, 1]` the contact height `h` mapped linearly over the surface's points, the products
/// `P_i(t)·P_j(η)`, `i ≤ degree`, `j ≤ min(height_degree, lines − 1)`: smooth along the path and
/// over the heights, the same `(degree + 1)(height_degree + 1)` columns a surface whatever the
/// number of lines (a basis per line would grow with them, and its fit as the square).
pub fn surface_basis(points: &[PointMeta], degree: usize, height_degree: usize) -> DMatrix<f64> {
    let seqs = curve_sequences(points);
    let mut blocks: Vec<(Vec<usize>, usize)> = Vec::new();
    for s in Surface::BOTH {
        let idx: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].surface == s)
            .collect();
        if idx.is_empty() {
            continue;
        }
        let lines = seqs
            .iter()
            .filter(|(_, l)| l.first().is_some_and(|&i| points[i].surface == s))
            .count();
        blocks.push((idx, height_degree.min(lines.saturating_sub(1))));
    }
    let width: usize = blocks.iter().map(|(_, hd)| (degree + 1) * (hd + 1)).sum();
    let mut m = DMatrix::zeros(points.len(), width);
    let mut first = 0;
    for (idx, hd) in blocks {
        let range = |f: &dyn Fn(usize) -> f64| {
            idx.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &i| {
                    (a.min(f(i)), b.max(f(i)))
                })
        };
        let (s0, s1) = range(&|i| points[i].s);
        let (h0, h1) = range(&|i| points[i].h);
        let unit = |v: f64, lo: f64, hi: f64| 2.0 * (v - lo) / (hi - lo).max(1e-12) - 1.0;
        for &i in &idx {
            let pt = legendre(unit(points[i].s, s0, s1), degree);
            let ph = legendre(unit(points[i].h, h0, h1), hd);
            for (a, pa) in pt.iter().enumerate() {
                for (b, pb) in ph.iter().enumerate() {
                    m[(i, first + a * (hd + 1) + b)] = pa * pb;
                }
            }
        }
        first += (degree + 1) * (hd + 1);
    }
    m
}

/// `(σ, σ_robust, dof)` from the residual of `[A | smooth basis]`.
pub fn smooth_noise(points: &[PointMeta], a: &DMatrix<f64>, y: &DVector<f64>) -> (f64, f64, usize) {
    let (f, r) = smooth_factor(smooth_basis(points, SMOOTH_DEGREE), a, y, Threads::ONE);
    smooth_sigmas(&f, &r)
}

/// The factor of `[A | smooth basis]` and the deviations' residual on it.
#[derive(Debug, Clone)]
pub struct SmoothFit {
    pub factor: Factor,
    pub residual: DVector<f64>,
}

/// The factor of `[A | b]` and the residual of `y` on it.
pub fn smooth_factor(
    b: DMatrix<f64>,
    a: &DMatrix<f64>,
    y: &DVector<f64>,
    threads: Threads,
) -> (Factor, DVector<f64>) {
    // `[A | b]` factorised in place, `b` dropped first (a dense scan's peak memory, issue 31)
    let x = hstack(a, &b);
    drop(b);
    let f = Factor::of_on(x, None, threads);
    let r = f.unabsorbed_vec(y);
    (f, r)
}

/// `(σ, σ_robust, dof)` from the factor of `[A | b]` and the residual on it.
pub fn smooth_sigmas(f: &Factor, r: &DVector<f64>) -> (f64, f64, usize) {
    let n = r.len();
    let dof = n.saturating_sub(f.rank).max(1);
    let sigma = (r.norm_squared() / dof as f64).sqrt();
    let mut abs: Vec<f64> = r.iter().map(|v| v.abs()).collect();
    abs.sort_by(f64::total_cmp);
    let med = if abs.is_empty() {
        0.0
    } else {
        abs[abs.len() / 2]
    };
    let robust = 1.482_6 * med * (n as f64 / dof as f64).sqrt();
    (sigma, robust, dof)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn legendre_closed_forms() {
        let t: f64 = 0.3;
        let p = legendre(t, 3);
        assert_near!(p[2], 0.5 * (3.0 * t * t - 1.0), 1e-15);
        assert_near!(p[3], 0.5 * (5.0 * t.powi(3) - 3.0 * t), 1e-15);
    }
}
