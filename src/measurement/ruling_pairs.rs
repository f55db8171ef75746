//! Noise σ from the two heights of a ruling: the estimator that structure along the tool path
//! cannot inflate.
//!
//! A flank pass cuts each ruling of the surface at one instant, with the tool's side along it
//! (s-shape.md: the ruling is the tool axis). Whatever moves the tool at that instant (a
//! location error, a servo lag, a backlash settling, a thermal drift, a straightness or cyclic
//! error of an axis, a waviness of the path) moves the whole contact line at once: the defect
//! along a ruling is an affine function of the height, `d(h) = a(s) + b(s)·h` (to the twist of
//! the normal along the ruling, a few percent of `a`), whatever `a(s)` and `b(s)` do along the
//! path. Two points of one ruling at two heights therefore share `a(s)`, while their
//! measurement noise (the CMM's, and the surface's own point-to-point scatter) is independent.
//! Their difference `δ_k = r_i − r_j` cancels every such structure but the smooth tilt term
//! `b(s)·Δh`, and the successive differences of `δ` along the path cancel that: the robust
//! semivariogram at lag 1 of the `δ` sequences ([`robust_semivariogram`], the largest tenth of
//! the squared differences trimmed, so a local mark at one height does not count) is `2σ²`
//! for noise.
//!
//! `r` is the residual of the baseline fit, `r = (I − H) y` with `H = Q Qᵀ` the projection on
//! the location errors' columns (`Q` orthonormal): the noise of `δ_k` then has the variance
//! `σ² (2 − H_ii − H_jj + 2 H_ij)`, so each difference is divided by
//! `√((2 − H_ii − H_jj + 2 H_ij) / 2)` first, which makes the estimate unbiased for `σ²`.
//!
//! Pairs: on each surface the curves (point labels) are ordered by their mean contact height;
//! each point of one curve is paired with the point of the next curve (at least
//! [`MIN_HEIGHT_GAP_MM`] higher) nearest in `u`, when that point is within
//! [`PAIR_U_FRACTION`] of the local spacing in `u` of both curves and not already paired. The
//! built-in layout (ids 1-25 with 26-50, 51-75 with 76-100) gives 50 pairs; a layout with one
//! height per surface gives none, and [`crate::measurement::noise`] falls back to the residual's
//! own estimators.
//!
//! Behaviour, measured on paper 000's machine with the 100 built-in points, σ = 1.5 µm
//! (the mean of σ̂/σ over 40-200 parts, BENCHMARKS.md "σ that structure cannot inflate"):
//! 1.00 on clean parts; 1.00-1.12 with the time-domain servo defects of
//! `reference/servo_signatures.csv` or a waviness of 100-150 mm along the path at two to three
//! times the detection limit, where the residual's own variogram nugget reads 2.5-7 (and a
//! 60 mm waviness, two points a period, 1.2-1.5 against 9-14). [`PAIR_DOF_PER_DIFFERENCE`]
//! gives its spread.

use nalgebra::DMatrix;
use serde::Serialize;

use crate::effects::data::PointMeta;
use crate::measurement::noise::trimmed_semivariogram;
use crate::numerics::order::{groups_in_order, sort_by_key_f64};
use crate::part::Surface;

/// Smallest difference of mean contact height (mm) between two curves of a surface for their
/// points to be paired.
pub const MIN_HEIGHT_GAP_MM: f64 = 2.0;

/// Largest mismatch in `u` of a pair, as a fraction of the smaller local spacing in `u` of the
/// two curves (the built-in layout's pairs are within 0.1).
pub const PAIR_U_FRACTION: f64 = 0.25;

/// Fraction of the squared successive differences kept.
pub const PAIR_KEEP: f64 = 0.9;
/// `E[X | X ≤ q]` for `X ~ χ²₁` and `P(X ≤ q)` = [`PAIR_KEEP`].
pub const PAIR_TRIMMED_CHI2_1: f64 = 0.623_015_5;

/// Fewest pairs for an estimate.
pub const MIN_PAIRS: usize = 12;

/// Effective degrees of freedom of σ̂² per successive difference of `δ`: the relative spread of
/// σ̂ is `1/√(2ν)`; measured 0.131 with the built-in layout's 46 differences (200 clean parts),
/// so `ν ≈ 29 = 0.63 × 46`.
pub const PAIR_DOF_PER_DIFFERENCE: f64 = 0.63;

/// σ from the pairs of points on the two heights of a ruling.
#[derive(Debug, Clone, Serialize)]
pub struct PairSigma {
    /// The estimate (mm).
    pub sigma: f64,
    /// Pairs used.
    pub pairs: usize,
    /// Successive differences of the pair differences the estimate rests on.
    pub differences: usize,
    /// Effective degrees of freedom of σ̂² ([`PAIR_DOF_PER_DIFFERENCE`] per difference).
    pub dof: f64,
}

/// The pairs of point indices `(lower, upper)` of the points' rulings, one sequence per pair
/// of curves, in increasing `u`.
pub fn ruling_pairs(points: &[PointMeta]) -> Vec<Vec<(usize, usize)>> {
    let mut out = Vec::new();
    for surface in [Surface::A, Surface::B] {
        // curves of this surface, by mean contact height (grouped in one pass: a scan's 200,000
        // points on 80 lines had each been compared with the labels so far, issue 31)
        let mut curves: Vec<(f64, Vec<usize>)> = groups_in_order(
            points
                .iter()
                .enumerate()
                .filter(|(_, p)| p.surface == surface)
                .map(|(i, p)| (i, p.curve.as_str())),
        )
        .into_iter()
        .map(|(_, idx)| (0.0, idx))
        .collect();
        for (h, idx) in &mut curves {
            sort_by_key_f64(idx, |&i| points[i].u);
            *h = idx.iter().map(|&i| points[i].h).sum::<f64>() / idx.len() as f64;
        }
        sort_by_key_f64(&mut curves, |c| c.0);
        for w in curves.windows(2) {
            let ((h0, lo), (h1, hi)) = (&w[0], &w[1]);
            if h1 - h0 < MIN_HEIGHT_GAP_MM || lo.len() < 2 || hi.len() < 2 {
                continue;
            }
            let seq = pair_curves(points, lo, hi);
            if !seq.is_empty() {
                out.push(seq);
            }
        }
    }
    out
}

/// Local spacing in `u` around position `k` of a curve sorted by `u`: the smaller gap to a
/// neighbour.
fn spacing(points: &[PointMeta], idx: &[usize], k: usize) -> f64 {
    let u = |k: usize| points[idx[k]].u;
    let before = (k > 0).then(|| u(k) - u(k - 1));
    let after = (k + 1 < idx.len()).then(|| u(k + 1) - u(k));
    match (before, after) {
        (Some(a), Some(b)) => a.min(b),
        (Some(a), None) | (None, Some(a)) => a,
        (None, None) => 0.0,
    }
}

fn pair_curves(points: &[PointMeta], lo: &[usize], hi: &[usize]) -> Vec<(usize, usize)> {
    let mut used = vec![false; hi.len()];
    let mut seq = Vec::new();
    for (a, &i) in lo.iter().enumerate() {
        let u = points[i].u;
        // nearest in u on the upper curve (sorted): the insertion point or the one before it
        let at = hi.partition_point(|&j| points[j].u < u);
        let best = [at.checked_sub(1), (at < hi.len()).then_some(at)]
            .into_iter()
            .flatten()
            .min_by(|&x, &y| {
                (points[hi[x]].u - u)
                    .abs()
                    .total_cmp(&(points[hi[y]].u - u).abs())
            });
        let Some(b) = best else { continue };
        let tolerance = PAIR_U_FRACTION * spacing(points, lo, a).min(spacing(points, hi, b));
        if !used[b] && (points[hi[b]].u - u).abs() <= tolerance {
            used[b] = true;
            seq.push((i, hi[b]));
        }
    }
    seq
}

/// σ from the ruling pairs of `points` and the baseline residual `r` (mm), `q` an orthonormal
/// basis of the baseline's columns (`n × rank`); `None` with fewer than [`MIN_PAIRS`] pairs.
pub fn pair_sigma(points: &[PointMeta], r: &[f64], q: &DMatrix<f64>) -> Option<PairSigma> {
    pair_sigma_kept(points, r, q, PAIR_KEEP, PAIR_TRIMMED_CHI2_1)
}

/// [`pair_sigma`] keeping the fraction `keep` of the squared differences (`c` its constant).
pub fn pair_sigma_kept(
    points: &[PointMeta],
    r: &[f64],
    q: &DMatrix<f64>,
    keep: f64,
    c: f64,
) -> Option<PairSigma> {
    let seqs = ruling_pairs(points);
    let pairs: usize = seqs.iter().map(Vec::len).sum();
    if pairs < MIN_PAIRS {
        return None;
    }
    let rows = RowProducts::new(q);
    let h = |i: usize, j: usize| rows.at(i, j);
    let deltas: Vec<Vec<f64>> = seqs
        .iter()
        .map(|seq| {
            seq.iter()
                .map(|&(i, j)| {
                    let var = (2.0 - h(i, i) - h(j, j) + 2.0 * h(i, j)) / 2.0;
                    (r[i] - r[j]) / var.max(1e-6).sqrt()
                })
                .collect()
        })
        .collect();
    let differences: usize = deltas.iter().map(|d| d.len().saturating_sub(1)).sum();
    let gamma = trimmed_semivariogram(&deltas, 1, keep, c)?;
    Some(PairSigma {
        sigma: (gamma / 2.0).sqrt(),
        pairs,
        differences,
        dof: PAIR_DOF_PER_DIFFERENCE * differences as f64,
    })
}

/// The products `q_i·q_j` of a matrix's rows, from a copy of its rows side by side (in `q` a
/// row's terms are a column's length apart: each pair's three products had read `3·2·rank`
/// cache lines across a dense scan's basis, issue 31), each summed from 0 in the columns'
/// order as nalgebra's `row(i).dot(&row(j))` sums it: the same bits.
struct RowProducts {
    rows: Vec<f64>,
    p: usize,
}

impl RowProducts {
    fn new(q: &DMatrix<f64>) -> Self {
        let p = q.ncols();
        let mut rows = vec![0.0; q.nrows() * p];
        for (k, col) in q.column_iter().enumerate() {
            for (i, v) in col.iter().enumerate() {
                rows[i * p + k] = *v;
            }
        }
        Self { rows, p }
    }

    /// `q_i·q_j`.
    fn at(&self, i: usize, j: usize) -> f64 {
        let p = self.p;
        let (a, b) = (
            &self.rows[i * p..(i + 1) * p],
            &self.rows[j * p..(j + 1) * p],
        );
        a.iter().zip(b).fold(0.0, |s, (x, y)| s + x * y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::random::Sampler;

    /// Two curves of 20 points on surface A at heights 15 and 29, the upper one's `u` shifted by
    /// `shift` of the spacing.
    fn points(shift: f64) -> Vec<PointMeta> {
        (0..40)
            .map(|i| {
                let (k, upper) = (i % 20, i >= 20);
                let u = (k as f64 + if upper { shift } else { 0.0 }) / 20.0;
                PointMeta {
                    id: i as u32 + 1,
                    curve: if upper { "A_Z25" } else { "A_Z11" }.into(),
                    surface: Surface::A,
                    u,
                    h: if upper { 29.0 } else { 15.0 },
                    s: 600.0 * u,
                    order: i,
                    nz: 0.0,
                }
            })
            .collect()
    }

    /// [`RowProducts`] are nalgebra's `row(i).dot(&row(j))` bit for bit (rows of 9 terms of many
    /// magnitudes, signed zeros among them). Tolerance: none.
    #[test]
    fn row_products_side_by_side_are_the_rows_dots_bit_for_bit() {
        let q = DMatrix::from_fn(500, 9, |i, j| {
            if (i + 2 * j) % 13 == 0 {
                -0.0
            } else {
                ((i * 7 + j * 13) % 17) as f64 * 10f64.powi((i % 5) as i32 - 2) - 0.3 * j as f64
            }
        });
        let rows = RowProducts::new(&q);
        for (i, j) in [(0, 1), (3, 3), (499, 7), (42, 250), (13, 26)] {
            let got = rows.at(i, j);
            assert_eq!(got.to_bits(), q.row(i).dot(&q.row(j)).to_bits(), "{i}, {j}");
        }
    }

    #[test]
    fn pairs_the_same_ruling_and_refuses_a_far_one() {
        assert_eq!(ruling_pairs(&points(0.1))[0].len(), 20);
        // half a spacing apart: no point is on the same ruling
        assert!(ruling_pairs(&points(0.5)).is_empty());
    }

    #[test]
    fn ignores_any_structure_shared_by_the_ruling() {
        // a defect a(s) + b(s)·h of any shape along the path, plus noise σ = 1: σ̂ ≈ 1 where
        // the residual itself has an RMS of about 30
        let pts = points(0.0);
        let q = DMatrix::zeros(40, 0);
        let mut rng = Sampler::new(3);
        let mut mean = 0.0;
        let runs = 200;
        for _ in 0..runs {
            let r: Vec<f64> = pts
                .iter()
                .map(|p| {
                    let a = 30.0 * (p.s / 7.0).sin() + 40.0 * (p.s > 300.0) as u8 as f64;
                    let b = 0.05 * (p.s / 200.0).cos();
                    a + b * p.h + rng.normal()
                })
                .collect();
            mean += pair_sigma(&pts, &r, &q).expect("20 pairs").sigma / runs as f64;
        }
        // 200 parts of 19 differences: the mean within 3 standard errors (0.16/√200 each)
        assert!((mean - 1.0).abs() < 0.04, "mean σ̂ = {mean}");
    }
}
