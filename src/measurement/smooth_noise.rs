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
use crate::numerics::parallel::{map_mut, Threads};
use crate::part::Surface;

/// Degree of the per-curve Legendre basis.
pub const SMOOTH_DEGREE: usize = 5;

/// Legendre polynomials `P_0..P_d` at `t` (Bonnet's recursion).
pub fn legendre(t: f64, d: usize) -> Vec<f64> {
    let mut p = vec![0.0; d + 1];
    legendre_into(t, &mut p);
    p
}

/// [`legendre`] written into `out` (`P_0..P_d`, `d = out.len() − 1`): the same recursion, no
/// allocation (a scan's basis takes two a point).
fn legendre_into(t: f64, out: &mut [f64]) {
    let d = out.len().saturating_sub(1);
    let (mut prev, mut cur) = (1.0, t);
    out[0] = prev;
    if d >= 1 {
        out[1] = cur;
    }
    for k in 1..d {
        let kf = k as f64;
        let next = ((2.0 * kf + 1.0) * t * cur - kf * prev) / (kf + 1.0);
        out[k + 1] = next;
        (prev, cur) = (cur, next);
    }
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
    let none = DMatrix::zeros(points.len(), 0);
    surface_basis_beside(&none, points, degree, height_degree, Threads::ONE)
}

/// `[A | smooth basis]` in one matrix: [`smooth_basis`] of degree `degree` at `points` after the
/// columns of `a` (one row a point). A scan's basis is written in place beside `a`'s columns,
/// its columns side by side on `threads` threads; the per-curve basis of discrete points is
/// built and joined by [`hstack`]. The same entries on any number of threads.
pub fn with_smooth_basis(
    a: &DMatrix<f64>,
    points: &[PointMeta],
    degree: usize,
    threads: Threads,
) -> DMatrix<f64> {
    if is_scan(points) {
        surface_basis_beside(a, points, degree, HEIGHT_DEGREE, threads)
    } else {
        hstack(a, &smooth_basis(points, degree))
    }
}

/// One surface of a scan's smooth basis: its points (rows), its degree in height, and the
/// Legendre values at its points, a point's `degree + 1` along the path (`P_i(t)`) and its
/// `height_degree + 1` across the heights (`P_j(η)`) one after the other.
struct SurfaceBlock {
    rows: Vec<usize>,
    height_degree: usize,
    along: Vec<f64>,
    across: Vec<f64>,
}

/// A column of a scan's smooth basis, `P_i(t)·P_j(η)` on the rows of its surface's
/// [`SurfaceBlock`] (`block`), written into `out`.
struct BasisColumn<'a> {
    block: usize,
    i: usize,
    j: usize,
    out: &'a mut [f64],
}

/// `[A | surface_basis(points, degree, height_degree)]`, the basis written in place: at 200,000
/// points it is 77 MB, which built apart and copied beside `A` on one thread had been ~0.1 s
/// (issue 31). The surfaces' Legendre values are computed once a point; each column of the basis
/// is then the product of two of them on its surface's rows (0 on the other surface's), the
/// columns side by side on `threads` threads.
fn surface_basis_beside(
    a: &DMatrix<f64>,
    points: &[PointMeta],
    degree: usize,
    height_degree: usize,
    threads: Threads,
) -> DMatrix<f64> {
    let (n, p) = (points.len(), a.ncols());
    assert_eq!(a.nrows(), n, "{} rows of A for {n} points", a.nrows());
    let seqs = curve_sequences(points);
    let blocks: Vec<SurfaceBlock> = Surface::BOTH
        .iter()
        .filter_map(|&s| {
            let rows: Vec<usize> = (0..n).filter(|&i| points[i].surface == s).collect();
            if rows.is_empty() {
                return None;
            }
            let lines = seqs
                .iter()
                .filter(|(_, l)| l.first().is_some_and(|&i| points[i].surface == s))
                .count();
            let hd = height_degree.min(lines.saturating_sub(1));
            let range = |f: &dyn Fn(usize) -> f64| {
                rows.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &i| {
                        (a.min(f(i)), b.max(f(i)))
                    })
            };
            let (s0, s1) = range(&|i| points[i].s);
            let (h0, h1) = range(&|i| points[i].h);
            let unit = |v: f64, lo: f64, hi: f64| 2.0 * (v - lo) / (hi - lo).max(1e-12) - 1.0;
            let mut along = vec![0.0; rows.len() * (degree + 1)];
            let mut across = vec![0.0; rows.len() * (hd + 1)];
            for ((&i, t), h) in rows
                .iter()
                .zip(along.chunks_mut(degree + 1))
                .zip(across.chunks_mut(hd + 1))
            {
                legendre_into(unit(points[i].s, s0, s1), t);
                legendre_into(unit(points[i].h, h0, h1), h);
            }
            Some(SurfaceBlock {
                rows,
                height_degree: hd,
                along,
                across,
            })
        })
        .collect();
    let width: usize = blocks
        .iter()
        .map(|b| (degree + 1) * (b.height_degree + 1))
        .sum();
    // zeroed pages, first touched by the thread that writes the column
    let mut data = vec![0.0; n * (p + width)];
    let (left, right) = data.split_at_mut(n * p);
    left.copy_from_slice(a.as_slice());
    // each column of the basis: its surface and its degrees along and across, in order
    let mut columns: Vec<BasisColumn> = blocks
        .iter()
        .enumerate()
        .flat_map(|(k, b)| {
            (0..=degree).flat_map(move |i| (0..=b.height_degree).map(move |j| (k, i, j)))
        })
        .zip(right.chunks_mut(n.max(1)))
        .map(|((block, i, j), out)| BasisColumn { block, i, j, out })
        .collect();
    map_mut(threads, &mut columns, |c| {
        let b = &blocks[c.block];
        let hd = b.height_degree;
        for (r, &row) in b.rows.iter().enumerate() {
            c.out[row] = b.along[r * (degree + 1) + c.i] * b.across[r * (hd + 1) + c.j];
        }
    });
    DMatrix::from_vec(n, p + width, data)
}

/// `(σ, σ_robust, dof)` from the residual of `[A | smooth basis]`.
pub fn smooth_noise(points: &[PointMeta], a: &DMatrix<f64>, y: &DVector<f64>) -> (f64, f64, usize) {
    let x = with_smooth_basis(a, points, SMOOTH_DEGREE, Threads::ONE);
    let (f, r) = smooth_factor(x, y, Threads::ONE);
    smooth_sigmas(&f, &r)
}

/// The factor of `[A | smooth basis]` and the deviations' residual on it.
#[derive(Debug, Clone)]
pub struct SmoothFit {
    pub factor: Factor,
    pub residual: DVector<f64>,
}

/// The factor of `x = [A | b]` ([`with_smooth_basis`]), factorised in place, and the residual
/// of `y` on it.
pub fn smooth_factor(
    x: DMatrix<f64>,
    y: &DVector<f64>,
    threads: Threads,
) -> (Factor, DVector<f64>) {
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

    /// A scan's `[A | basis]` written in place is, bit for bit, the basis built an entry at a
    /// time as before (written out here) and joined to `A`, on 1 and 3 threads: two surfaces of
    /// 5 and 3 lines (B's degree in height capped at 2 by its lines), the surfaces' points
    /// interleaved in the file's order. A discrete layout (two curves a surface) keeps the
    /// per-curve basis.
    #[test]
    fn a_scans_basis_in_place_is_the_basis_joined_to_a() {
        let point = |i: usize, surface: Surface, line: usize, k: usize| PointMeta {
            id: i as u32 + 1,
            curve: format!("{}_L{line}", surface.name()),
            surface,
            u: k as f64 / 30.0,
            h: 2.0 + 6.0 * line as f64,
            s: 40.0 * k as f64 + if surface == Surface::B { 700.0 } else { 0.0 },
            order: i,
            nz: 0.0,
        };
        let mut points = Vec::new();
        for k in 0..31 {
            for line in 0..5 {
                points.push(point(points.len(), Surface::A, line, k));
                if line < 3 {
                    points.push(point(points.len(), Surface::B, line, k));
                }
            }
        }
        let n = points.len();
        let a = DMatrix::from_fn(n, 3, |i, j| ((i * 7 + j * 3) % 11) as f64 - 5.0);
        // the basis as it was built before, an entry at a time: on each surface (A with 5 lines,
        // degree 3 in height; B with 3, degree 2), `P_i(t)·P_j(η)` at column `i·(hd + 1) + j`
        let unit = |v: f64, lo: f64, hi: f64| 2.0 * (v - lo) / (hi - lo).max(1e-12) - 1.0;
        let mut basis = DMatrix::zeros(n, 24 + 18);
        let mut first = 0;
        for (s, hd) in [(Surface::A, 3), (Surface::B, 2)] {
            let rows: Vec<usize> = (0..n).filter(|&i| points[i].surface == s).collect();
            let range = |f: &dyn Fn(&PointMeta) -> f64| {
                rows.iter()
                    .map(|&i| f(&points[i]))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                        (a.min(v), b.max(v))
                    })
            };
            let ((s0, s1), (h0, h1)) = (range(&|p| p.s), range(&|p| p.h));
            for &r in &rows {
                let pt = legendre(unit(points[r].s, s0, s1), SMOOTH_DEGREE);
                let ph = legendre(unit(points[r].h, h0, h1), hd);
                for (i, pi) in pt.iter().enumerate() {
                    for (j, pj) in ph.iter().enumerate() {
                        basis[(r, first + i * (hd + 1) + j)] = pi * pj;
                    }
                }
            }
            first += (SMOOTH_DEGREE + 1) * (hd + 1);
        }
        let joined = hstack(&a, &basis);
        assert_eq!(smooth_basis(&points, SMOOTH_DEGREE), basis);
        for t in [1, 3] {
            let x = with_smooth_basis(&a, &points, SMOOTH_DEGREE, Threads::new(t));
            assert_eq!(x.shape(), joined.shape());
            assert!(
                x.iter()
                    .zip(joined.iter())
                    .all(|(p, q)| p.to_bits() == q.to_bits()),
                "{t} threads"
            );
        }
        let discrete: Vec<PointMeta> = points
            .iter()
            .filter(|p| p.curve.ends_with("L0") || p.curve.ends_with("L1"))
            .cloned()
            .collect();
        let ad = DMatrix::from_fn(discrete.len(), 2, |i, j| (i + j) as f64);
        assert_eq!(
            with_smooth_basis(&ad, &discrete, SMOOTH_DEGREE, Threads::new(2)),
            hstack(&ad, &smooth_basis(&discrete, SMOOTH_DEGREE))
        );
    }

    /// The recursion written in place gives, bit for bit, Bonnet's recursion as a growing list
    /// (the form it replaces) at every degree from 0.
    #[test]
    fn legendre_in_place_is_bonnets_recursion() {
        let growing = |t: f64, d: usize| {
            let mut p = vec![1.0, t];
            for k in 1..d {
                let kf = k as f64;
                let next = ((2.0 * kf + 1.0) * t * p[k] - kf * p[k - 1]) / (kf + 1.0);
                p.push(next);
            }
            p.truncate(d + 1);
            p
        };
        for d in 0..8 {
            for t in [-1.0, -0.37, 0.0, 0.5, 0.913, 1.0] {
                let mut out = vec![f64::NAN; d + 1];
                legendre_into(t, &mut out);
                let want = growing(t, d);
                assert!(
                    out.iter()
                        .zip(&want)
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "degree {d} at {t}: {out:?} vs {want:?}"
                );
                assert_eq!(legendre(t, d), out);
            }
        }
    }

    #[test]
    fn legendre_closed_forms() {
        let t: f64 = 0.3;
        let p = legendre(t, 3);
        assert_near!(p[2], 0.5 * (3.0 * t * t - 1.0), 1e-15);
        assert_near!(p[3], 0.5 * (5.0 * t.powi(3) - 3.0 * t), 1e-15);
    }
}
