//! The shape of a family (effects.md, "Shapes are families"): a backlash's lag, a warm-up
//! constant. The amplitude enters the deviation linearly and the shape does not, so the fit is a
//! variable projection: at each value of the shape grid the amplitude is eliminated by least
//! squares on top of the baseline (Frisch–Waugh–Lovell, [`super::which`]), leaving the residual
//! sum of squares as a function of the shape alone, `RSS(τ)`, searched over the grid.
//!
//! - **A second parameter** (the warm-up's pause between the passes, a backlash's take-up) is
//!   profiled out: at each
//!   shape value the profile takes the least `RSS` over its grid; the member of the estimate is
//!   the one that gives it.
//! - **Estimate**: the grid value of least `RSS`, refined by the parabola through it and its two
//!   neighbours in the grid's coordinate (`ln τ`; for the warm-up the index, whose last value is
//!   the linear law `f = ∞`).
//! - **Interval** (95 %): the hull of the profile's set `{τ : (RSS(τ) − RSS_min)/s² ≤ F₀.₉₅(1, n − p − q)}`, `s²`
//!   the larger of the decision's σ² (the part's σ when it is fixed) and `RSS_min/(n − p − q)`, its ends
//!   interpolated linearly between the grid values where the profile crosses the bound; an end
//!   that reaches the grid's is open (the part cannot bound the shape on that side).
//! - **The search's cost** (effects.md: "the significance test must account for the search"): the
//!   Bonferroni factor of the diagnosis counts a family as its number of effectively independent
//!   shapes `m_eff` (Li & Ji 2005: `m_eff = Σ_k [1(λ_k ≥ 1) + (λ_k − ⌊λ_k⌋)]` over the eigenvalues
//!   `λ_k` of the correlation matrix of the family's unabsorbed signatures), not as one candidate:
//!   1 for identical shapes, the grid's size for unrelated ones.

use nalgebra::{DMatrix, DMatrixViewMut, DVector, SymmetricEigen};
use serde::Serialize;

use crate::effects::data::Candidate;
use crate::identify::solve::{gram_of_columns, hstack, tr_mul, Factor};
use crate::machine::Unit;
use crate::numerics::parallel::{join, map_mut, Threads};
use crate::numerics::stats;
use crate::toolpath::envelope::brent_min;

/// Confidence of the shape's interval.
pub const SHAPE_CONFIDENCE: f64 = 0.95;
/// The estimate of a family whose members can be computed between the grid's values: to this
/// bracket in the grid's coordinate (1/1000 of a grid step).
pub const EXACT_TOL: f64 = 1e-3;
/// Members of a family projected off the baseline together ([`scan_family`], below a dense
/// scan's rows: [`scan_block_size`]).
const SCAN_BLOCK: usize = 8;
/// The most members of a block on a dense scan ([`scan_block_size`]): projected in their own
/// columns, a block costs no memory of its own.
const DENSE_SCAN_BLOCK: usize = 10;
/// Bisection steps of an interval's end between two grid values (1/4096 of a step).
pub const ROOT_STEPS: usize = 12;

/// A fitted shape parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeFit {
    /// `tau` or `f` ([`crate::parameter::Shape`]).
    pub name: &'static str,
    pub unit: Unit,
    /// The estimate (a grid value refined by a parabola; `inf` for the linear law).
    pub value: f64,
    /// The ends of the 95 % profile interval; `low_open`/`high_open`: the interval reaches the
    /// grid's end on that side (the shape is not bounded there by this part).
    pub low: f64,
    pub high: f64,
    pub low_open: bool,
    pub high_open: bool,
    /// The grid value of least RSS, and the index of its member (the signature the fit uses).
    pub grid_value: f64,
    #[serde(skip)]
    pub grid_index: usize,
    /// The profiled parameter's value at that member (the warm-up's pause between the passes, a
    /// backlash's take-up); not in the interval: the profile is the least over it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profiled: Option<Profiled>,
    /// The shape's reference value (the table's signature).
    pub reference: f64,
    /// Effectively independent shapes of the grid on this part (`m_eff`, module doc).
    pub effective_shapes: f64,
}

/// A second shape parameter at the member the fit chose ([`crate::effects::Family::profiled`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Profiled {
    /// `pause` (the warm-up's, between the passes) or `take_up` (a backlash's lost motion whose
    /// take-up the member has, [`crate::effects::builtin::take_up_shape`]).
    pub name: &'static str,
    pub unit: Unit,
    /// Its grid value at the chosen member.
    pub value: f64,
}

/// Columns' parts outside the baseline (`u = s − QQᵀs`, [`Factor::unabsorbed`]) with the norms of
/// the columns themselves (what the rank of `u` is judged against): all a Frisch–Waugh–Lovell fit
/// needs of them ([`Unabsorbed::rss`]). Columns held fixed while a family's member is searched
/// are unabsorbed once ([`Unabsorbed::beside`]: the same numbers, column by column).
#[derive(Clone)]
pub struct Unabsorbed {
    pub u: DMatrix<f64>,
    pub norms: Vec<f64>,
}

impl Unabsorbed {
    pub fn of(factor: &Factor, s: &DMatrix<f64>) -> Self {
        Self {
            norms: (0..s.ncols()).map(|j| s.column(j).norm()).collect(),
            u: factor.unabsorbed(s),
        }
    }

    /// `[self | other]`.
    pub fn beside(&self, other: &Unabsorbed) -> Self {
        Self {
            u: hstack(&self.u, &other.u),
            norms: self.norms.iter().chain(&other.norms).copied().collect(),
        }
    }

    /// The residual sum of squares of the baseline plus these columns on the baseline residual
    /// `r0` (Frisch–Waugh–Lovell), and the rank they add.
    #[cfg_attr(target_arch = "wasm32", target_feature(enable = "simd128"))]
    pub fn rss(&self, r0: &DVector<f64>) -> (f64, usize) {
        let fu = Factor::new(&self.u, Some(&self.norms));
        let theta = fu.solve(r0);
        ((r0 - &self.u * theta).norm_squared(), fu.rank)
    }
}

/// The residual sum of squares of the baseline plus the columns `s` on the baseline residual
/// `r0` (Frisch–Waugh–Lovell), and the rank `s` adds.
fn fwl(factor: &Factor, r0: &DVector<f64>, s: &DMatrix<f64>) -> (f64, usize) {
    Unabsorbed::of(factor, s).rss(r0)
}

/// A family searched on the baseline: its `m_eff` (module doc) and, on the baseline residual,
/// each member's residual sum of squares and the rank it adds ([`Unabsorbed::rss`]), both from
/// one unabsorbed part a member (a member's column is computed once: a backlash's ring with a
/// sine and a cosine a point).
#[derive(Clone)]
pub struct FamilyScan {
    pub effective_shapes: f64,
    /// `None` for a candidate of one shape, or when no residual was given.
    pub members: Option<Vec<(f64, usize)>>,
}

/// [`FamilyScan`] of `c` on the baseline `factor` (`m_eff` 1 for a candidate of one shape), the
/// members' fits on the residual `r0` when given.
pub fn scan_family(factor: &Factor, r0: Option<&DVector<f64>>, c: &Candidate) -> FamilyScan {
    scan_family_on(factor, r0, c, Threads::ONE, &mut Vec::new())
}

/// [`scan_family`], the family's blocks of members side by side on `threads` threads: the same
/// numbers (each block is the same product whatever the threads). A family's blocks, not whole
/// families, are shared out: the directions kept for `m_eff` are `n × members` (86 MB for a
/// backlash family at 200,000 points), one family's at a time, each block writing its own
/// columns, in `scratch`: a buffer the caller keeps from one family to the next, grown to
/// `n × members` when shorter (what it holds on entry does not matter).
pub fn scan_family_on(
    factor: &Factor,
    r0: Option<&DVector<f64>>,
    c: &Candidate,
    threads: Threads,
    scratch: &mut Vec<f64>,
) -> FamilyScan {
    let Some(family) = &c.family else {
        return FamilyScan {
            effective_shapes: 1.0,
            members: None,
        };
    };
    // One direction per member: the unabsorbed part of its first column (the families here have
    // one parameter), normalised; members the baseline absorbs entirely add nothing. The members
    // are projected [`SCAN_BLOCK`] at a time (two blocked products per block instead of two
    // matrix-vector products a member: the baseline's basis, 9 MB at 20,000 points, read once a
    // block); the correlations as one blocked product `DᵀD`.
    let n = c.signature.matrix.nrows();
    let size = scan_block_size(n, family.len());
    // member j's direction in column j (zeros when absorbed), each block in its own columns, in
    // the caller's buffer: every block writes all of its columns, so a buffer a family before
    // left needs no zeros (a new one for each family had been 86 MB of fresh pages at 200,000
    // points, a fault every 4 kB, issue 31)
    let len = n * family.len();
    if scratch.len() < len {
        *scratch = vec![0.0; len];
    }
    let mut blocks: Vec<(usize, &mut [f64])> = scratch[..len]
        .chunks_mut((n * size).max(1))
        .enumerate()
        .map(|(b, cols)| (b * size, cols))
        .collect();
    // each member's fit on the residual (when asked) and whether the baseline leaves it a
    // direction
    let scan_block =
        |(start, cols): &mut (usize, &mut [f64])| -> Vec<(Option<(f64, usize)>, bool)> {
            let block: Vec<_> = (*start..family.len().min(*start + size))
                .map(|j| family.member(j))
                .collect();
            scan_block_of(factor, r0, &block, cols)
        };
    let scanned: Vec<_> = map_mut(threads, &mut blocks, scan_block)
        .into_iter()
        .flatten()
        .collect();
    let mut members = r0.map(|_| Vec::with_capacity(family.len()));
    let mut dirs = DMatrixViewMut::from_slice(&mut scratch[..len], n, family.len());
    // the kept directions moved to the front, in the members' order
    let mut k = 0;
    for (j, (fit, kept)) in scanned.into_iter().enumerate() {
        if let (Some(fit), Some(m)) = (fit, members.as_mut()) {
            m.push(fit);
        }
        if kept {
            if k < j {
                dirs.swap_columns(k, j);
            }
            k += 1;
        }
    }
    if k == 0 {
        return FamilyScan {
            effective_shapes: 1.0,
            members,
        };
    }
    // the members kept, in place (a copy would be 86 MB more at 200,000 points, issue 31)
    let kept = &scratch[..n * k];
    // (on a dense scan by row blocks side by side: one product of 200,000 × 54 had been a
    // tenth of a second of one thread a family)
    let corr = if n < crate::gap::span_gram::GRAM_MIN_ROWS {
        let dirs = DMatrix::from_column_slice(n, k, kept);
        tr_mul(&dirs, &dirs)
    } else {
        gram_of_columns(kept, n, k, threads)
    };
    let eig = SymmetricEigen::new(corr).eigenvalues;
    let m_eff = eig
        .iter()
        .map(|&l| {
            let l = l.max(0.0);
            (if l >= 1.0 { 1.0 } else { 0.0 }) + (l - l.floor())
        })
        .sum::<f64>()
        .max(1.0);
    FamilyScan {
        effective_shapes: m_eff,
        members,
    }
}

/// The members of a family projected together: [`SCAN_BLOCK`], or on a dense scan (from
/// [`crate::gap::span_gram::GRAM_MIN_ROWS`] rows on) the family in equal blocks of at most
/// [`DENSE_SCAN_BLOCK`] (two of 27 for a backlash's 54 members: the baseline's basis, 115 MB at
/// 200,000 points, read twice a block, four times a family instead of fourteen, issue 31). The
/// blocks depend on the rows and the members alone, not on the threads.
fn scan_block_size(n: usize, members: usize) -> usize {
    if n < crate::gap::span_gram::GRAM_MIN_ROWS {
        return SCAN_BLOCK;
    }
    let blocks = members.div_ceil(DENSE_SCAN_BLOCK).max(1);
    members.div_ceil(blocks).max(1)
}

/// A block of members projected off the baseline ([`Factor::unabsorb_in_place`]), each
/// member's fit on `r0` (when given) from its unabsorbed columns, and its direction (its first
/// column's unabsorbed part, normalised, or zeros when the baseline absorbs it) written to its
/// column of `cols`. Members of one column each (every family here) are projected in their own
/// columns of `cols`, with no copy of the block or of its projection; members of several
/// columns in a copy of the block's columns side by side.
#[cfg_attr(target_arch = "wasm32", target_feature(enable = "simd128"))]
fn scan_block_of(
    factor: &Factor,
    r0: Option<&DVector<f64>>,
    block: &[std::borrow::Cow<'_, DMatrix<f64>>],
    cols: &mut [f64],
) -> Vec<(Option<(f64, usize)>, bool)> {
    let n = factor.basis.nrows();
    let width: usize = block.iter().map(|s| s.ncols()).sum();
    let in_place = width == block.len();
    let mut copy = if in_place {
        DMatrix::zeros(n, 0)
    } else {
        DMatrix::zeros(n, width)
    };
    {
        let mut x = if in_place {
            nalgebra::DMatrixViewMut::from_slice(&mut cols[..n * width], n, width)
        } else {
            copy.as_view_mut()
        };
        let mut at = 0;
        for s in block {
            x.columns_mut(at, s.ncols()).copy_from(s.as_ref());
            at += s.ncols();
        }
        factor.unabsorb_in_place(x);
    }
    let mut at = 0;
    block
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let w = s.ncols();
            let u = if in_place {
                DMatrix::from_column_slice(n, 1, &cols[i * n..(i + 1) * n])
            } else {
                copy.columns(at, w).into_owned()
            };
            at += w;
            let un = Unabsorbed {
                u,
                norms: (0..w).map(|j| s.column(j).norm()).collect(),
            };
            let fit = r0.map(|r0| un.rss(r0));
            let nu = un.u.column(0).norm();
            let kept = nu > 1e-12 * un.norms[0].max(1e-300);
            let dir = &mut cols[i * n..(i + 1) * n];
            if kept {
                for (d, u) in dir.iter_mut().zip(un.u.column(0).iter()) {
                    *d = u / nu;
                }
            } else {
                dir.fill(0.0);
            }
            (fit, kept)
        })
        .collect()
}

/// The first and last indices of `z` within `bound` (`best` among them): the hull of the
/// profile's confidence set on the grid.
fn hull(z: &[f64], bound: f64, best: usize) -> (usize, usize) {
    let lo = z.iter().position(|v| *v <= bound).unwrap_or(best).min(best);
    let hi = z
        .iter()
        .rposition(|v| *v <= bound)
        .unwrap_or(best)
        .max(best);
    (lo, hi)
}

/// The upper `1 − confidence` quantile of `F(1, dof)`, by bisection on its survival function.
pub(crate) fn f_quantile(confidence: f64, dof: f64) -> f64 {
    stats::sf_inverse(|f| stats::f_sf(f, 1.0, dof), 1.0 - confidence, 1e4)
}

/// The grid coordinate in which the profile is interpolated: `ln τ`, or the index when the grid
/// holds the linear law (`inf`).
fn coordinates(grid: &[f64]) -> Vec<f64> {
    if coords_are_logs(grid) {
        grid.iter().map(|v| v.ln()).collect()
    } else {
        (0..grid.len()).map(|k| k as f64).collect()
    }
}

/// A grid coordinate back to the shape's value (linear interpolation of the values between the
/// grid's neighbours; between the last finite value and the index coordinate's `inf` end,
/// linear in the value's inverse).
fn value_at(grid: &[f64], coords: &[f64], x: f64) -> f64 {
    let last = grid.len() - 1;
    let x = x.clamp(coords[0], coords[last]);
    let k = coords.partition_point(|c| *c <= x).clamp(1, last);
    let (c0, c1) = (coords[k - 1], coords[k]);
    let t = if c1 > c0 { (x - c0) / (c1 - c0) } else { 0.0 };
    let (v0, v1) = (grid[k - 1], grid[k]);
    if t >= 1.0 {
        return v1;
    }
    if t <= 0.0 {
        return v0;
    }
    if v1.is_infinite() {
        // between the last finite warm-up and the linear law (`1/f = 0`): linear in `1/f`, the
        // coordinate in which the law is smooth there, so an end or an estimate between them
        // is a finite `f` (before, the nearer of the two: a warm-up of 4.9, past the grid's
        // last 2.2, got the interval [∞, ∞] that left it out)
        return v0 / (1.0 - t);
    }
    if coords_are_logs(grid) {
        (v0.ln() + t * (v1.ln() - v0.ln())).exp()
    } else {
        v0 + t * (v1 - v0)
    }
}

/// Whether the grid's coordinate is `ln` of its values (every value finite and positive).
fn coords_are_logs(grid: &[f64]) -> bool {
    grid.iter().all(|v| v.is_finite() && *v > 0.0)
}

/// The shape of the family of `c` that fits the baseline residual `r0` best, with its interval;
/// `None` for a candidate of one shape. `n` points, `p` the baseline's rank, `given_s2` the
/// decision's σ² when fixed; `members` each member's fit when already scanned
/// ([`scan_family`]). A computed family's searches evaluate two members at a time on `threads`
/// threads (the same numbers whatever the threads).
#[allow(clippy::too_many_arguments)]
pub fn fit_shape(
    factor: &Factor,
    r0: &DVector<f64>,
    c: &Candidate,
    p: usize,
    given_s2: Option<f64>,
    effective_shapes: f64,
    members: Option<Vec<(f64, usize)>>,
    threads: Threads,
) -> Option<ShapeFit> {
    let family = c.family.as_ref()?;
    let grid = &family.shape.grid;
    if !family.is_complete() || grid.len() < 2 {
        return None;
    }
    // each member's fit ([`FamilyScan::members`] when scanned on this residual)
    let every: Vec<(f64, usize)> = match members {
        Some(m) if m.len() == family.len() => m,
        _ => (0..family.len())
            .map(|k| fwl(factor, r0, &family.member(k)))
            .collect(),
    };
    // the profile over the shape: at each of its values the least RSS over the profiled
    // parameter's (module doc), and the member that gives it
    let m = family.profiled_len();
    let chosen: Vec<usize> = (0..grid.len())
        .map(|i| {
            (i * m..(i + 1) * m)
                .min_by(|&a, &b| every[a].0.total_cmp(&every[b].0))
                .unwrap_or(i * m)
        })
        .collect();
    let prof: Vec<(f64, usize)> = chosen.iter().map(|&k| every[k]).collect();
    let best = (0..prof.len())
        .min_by(|&a, &b| prof[a].0.total_cmp(&prof[b].0))
        .unwrap_or(0);
    let (rss_min, q) = prof[best];
    let n = r0.len();
    let dof = (n.saturating_sub(p + q)).max(1) as f64;
    // σ² of the profile: the part's (when fixed), or the fit's residual mean square when that
    // is larger (structure the family does not model widens the interval instead of being read
    // as a sharp shape)
    let s2 = given_s2
        .unwrap_or(0.0)
        .max(rss_min / dof)
        .max(f64::MIN_POSITIVE);
    let bound = f_quantile(SHAPE_CONFIDENCE, dof);
    let mut z: Vec<f64> = prof.iter().map(|(r, _)| (r - rss_min) / s2).collect();
    let coords = coordinates(grid);
    // the parabola through the least and its neighbours: its vertex is the estimate, and the
    // profile is measured from the vertex's value (below the grid's least)
    let mut refined = coords[best];
    let mut curvature = None;
    if best > 0 && best + 1 < grid.len() {
        let (x0, x1, x2) = (coords[best - 1], coords[best], coords[best + 1]);
        let (y0, y1, y2) = (z[best - 1], z[best], z[best + 1]);
        let den = (x0 - x1) * (x0 - x2) * (x1 - x2);
        let a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / den;
        let b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / den;
        if a > 0.0 {
            refined = (-b / (2.0 * a)).clamp(x0, x2);
            let c = y1 - a * x1 * x1 - b * x1;
            let vertex = (a * refined * refined + b * refined + c).min(0.0);
            for v in &mut z {
                *v -= vertex;
            }
            curvature = Some(a);
        }
    }
    // the interval's ends: the first and last grid values within the bound (the hull of the
    // confidence set: a profile with two minima, e.g. a lag with and without the play's take-up,
    // keeps both); between the least and a neighbour already past it, the parabola's root
    let cross = |from: usize, to: usize| -> f64 {
        let (xa, xb, za, zb) = (coords[from], coords[to], z[from], z[to]);
        if zb > za {
            xa + ((bound - za) / (zb - za)).clamp(0.0, 1.0) * (xb - xa)
        } else {
            xb
        }
    };
    let (lo_k, hi_k) = hull(&z, bound, best);
    let half = curvature.map(|a| (bound / a).sqrt());
    let low_open = lo_k == 0;
    let high_open = hi_k + 1 == grid.len();
    let mut low = match (low_open, half) {
        (true, _) => grid[0],
        (false, Some(h)) if lo_k == best => {
            value_at(grid, &coords, (refined - h).max(coords[best - 1]))
        }
        _ => value_at(grid, &coords, cross(lo_k, lo_k - 1)),
    };
    let mut high = match (high_open, half) {
        (true, _) => grid[grid.len() - 1],
        (false, Some(h)) if hi_k == best => {
            value_at(grid, &coords, (refined + h).min(coords[best + 1]))
        }
        _ => value_at(grid, &coords, cross(hi_k, hi_k + 1)),
    };
    // A family whose members can be computed between the grid's values (the warm-up): the
    // profile is evaluated there instead of interpolated. On a grid coarser than the part's
    // resolution the parabola's vertex is biased and a convex profile interpolated linearly
    // narrows the interval. At a coordinate between two grid values the profiled parameter takes
    // the better of those the two chose. Between the last finite warm-up and the linear law
    // too (a finite `f`, linear in `1/f`: [`value_at`]), and at the law itself.
    // (the two members side by side on the threads, one when the two grid values chose the
    // same profiled value: the searches below are sequential, and at 200,000 points they had
    // been a fifth of a second of one thread beside the other idle, issue 31; the same numbers)
    let exact = |x: f64| -> Option<f64> {
        let v = value_at(grid, &coords, x);
        let k0 = coords.partition_point(|c| *c <= x).clamp(1, grid.len() - 1) - 1;
        let [p0, p1] = [chosen[k0], chosen[k0 + 1]].map(|k| family.values(k).1.unwrap_or(0.0));
        let at = |pause: f64| family.member_at(v, pause).map(|s| fwl(factor, r0, &s).0);
        let (a, b) = if p0.to_bits() == p1.to_bits() {
            let a = at(p0);
            (a, a)
        } else {
            join(threads, || at(p0), || at(p1))
        };
        [a, b].into_iter().flatten().min_by(f64::total_cmp)
    };
    if family.is_computed() {
        let a = coords[best.saturating_sub(1)];
        let b = coords[(best + 1).min(grid.len() - 1)];
        let (x_star, rss_star) =
            brent_min(&|x: f64| exact(x).unwrap_or(f64::INFINITY), a, b, EXACT_TOL);
        let rss_c = rss_star.min(rss_min);
        let zc = |x: f64| exact(x).map(|r| (r - rss_c) / s2);
        let zg: Vec<f64> = prof.iter().map(|(r, _)| (r - rss_c) / s2).collect();
        refined = x_star;
        // an end: the root of zc − bound between the last grid value within the bound (or the
        // estimate) and the first past it (the linear law included)
        let root = |inner: f64, outer: f64| -> Option<f64> {
            let (mut i, mut o) = (inner, outer);
            if zc(o)? <= bound {
                return None;
            }
            for _ in 0..ROOT_STEPS {
                let mid = 0.5 * (i + o);
                if zc(mid)? <= bound {
                    i = mid;
                } else {
                    o = mid;
                }
            }
            Some(0.5 * (i + o))
        };
        let (lo, hi) = hull(&zg, bound, best);
        if lo > 0 {
            let inner = if lo == best { x_star } else { coords[lo] };
            if let Some(x) = root(inner, coords[lo - 1]) {
                low = value_at(grid, &coords, x);
            }
        }
        if hi + 1 < grid.len() {
            let inner = if hi == best { x_star } else { coords[hi] };
            if let Some(x) = root(inner, coords[hi + 1]) {
                high = value_at(grid, &coords, x);
            }
        }
    }
    Some(ShapeFit {
        name: family.shape.name,
        unit: family.shape.unit.clone(),
        value: value_at(grid, &coords, refined),
        low,
        high,
        low_open,
        high_open,
        grid_value: grid[best],
        grid_index: chosen[best],
        profiled: family.profiled.as_ref().map(|p| Profiled {
            name: p.name,
            unit: p.unit.clone(),
            value: family.values(chosen[best]).1.unwrap_or(p.reference),
        }),
        reference: family.shape.reference,
        effective_shapes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::data::{Family, NamedColumns};
    use crate::numerics::random::Sampler;
    use crate::parameter::{Effect, Shape};

    /// Between the warm-up grid's last finite value (2.2) and the linear law, a coordinate is a
    /// finite `f`, linear in `1/f`: halfway 2·2.2, a quarter of the step past it 2.2/0.75 (to
    /// rounding), at the ends the grid's values.
    #[test]
    fn past_the_last_warm_up_the_value_is_linear_in_its_inverse() {
        let grid = crate::parameter::effect::WARM_UP_GRID;
        let coords = coordinates(&grid);
        let last = grid.len() - 1;
        assert!((value_at(&grid, &coords, last as f64 - 0.5) - 4.4).abs() < 1e-12);
        assert!((value_at(&grid, &coords, last as f64 - 0.75) - 2.2 / 0.75).abs() < 1e-12);
        assert_eq!(value_at(&grid, &coords, (last - 1) as f64), 2.2);
        assert!(value_at(&grid, &coords, last as f64).is_infinite());
    }

    /// A thermal-drift candidate whose family is `col` at each τ of `grid` (its signature at
    /// τ = 2), the constant baseline's factor, and its residual of data made at τ = 3.1
    /// (amplitude 0.5, noise 0.01 drawn from `seed`).
    fn drift_family(
        col: impl Fn(f64) -> DMatrix<f64>,
        grid: &[f64],
        seed: u64,
    ) -> (Factor, DVector<f64>, Candidate) {
        let n = col(2.0).nrows();
        let factor = Factor::new(&DMatrix::from_element(n, 1, 1.0), None);
        let mut rng = Sampler::new(seed);
        let y = DVector::from_iterator(n, col(3.1).iter().map(|v| 0.5 * v + 0.01 * rng.normal()));
        let r0 = factor.unabsorbed_vec(&y);
        let c = Candidate {
            effect: Effect::ThermalDrift,
            signature: NamedColumns::try_new(Effect::ThermalDrift.parameter_ids(), col(2.0))
                .unwrap()
                .into(),
            family: Some(Family::stored(
                Shape {
                    name: "tau",
                    unit: Unit::Mm,
                    reference: 2.0,
                    grid: grid.to_vec(),
                },
                grid.iter().map(|&t| col(t)).collect(),
            )),
        };
        (factor, r0, c)
    }

    /// A family of exponential steps `exp(−x/τ)` on 200 points with a constant baseline: data
    /// made at τ = 3.1 (between grid values 2.6 and 3.38) with noise 0.01 are fitted to within
    /// the interval, the interval holds the truth, and `m_eff` lies between 1 and the grid's size.
    #[test]
    fn the_shape_is_found_between_grid_values_and_its_interval_holds_it() {
        let n = 200;
        let x: Vec<f64> = (0..n).map(|i| i as f64 * 0.1).collect();
        let grid: Vec<f64> = (-9..=8).map(|k| 2.0 * 1.3f64.powi(k)).collect();
        let col = |tau: f64| DMatrix::from_iterator(n, 1, x.iter().map(|x| (-x / tau).exp()));
        let (factor, r0, c) = drift_family(col, &grid, 7);
        let m = scan_family(&factor, None, &c).effective_shapes;
        assert!(m > 1.0 && m < grid.len() as f64, "m_eff {m}");
        let fit = fit_shape(&factor, &r0, &c, 1, None, m, None, Threads::ONE).unwrap();
        assert!(fit.low < 3.1 && 3.1 < fit.high, "{fit:?}");
        // the estimate within 5 % of the truth (noise 0.01 on an amplitude of 0.5)
        assert!((fit.value / 3.1 - 1.0).abs() < 0.05, "{fit:?}");
        assert!(!fit.low_open && !fit.high_open);
        // the F quantile: F₀.₉₅(1, 100) = 3.936 (tables)
        assert!((f_quantile(0.95, 100.0) - 3.936).abs() < 1e-3);
    }

    /// A family's scan on 2 threads is the scan on 1, bit for bit: 20 members (blocks of 8, 8
    /// and 4), three of them inside the baseline's span (a constant: absorbed, no direction),
    /// so the kept directions are moved up past them in the members' order. And in a buffer
    /// whose values another family left, the same scan.
    #[test]
    fn a_family_is_scanned_the_same_on_two_threads() {
        let n = 300;
        let x: Vec<f64> = (0..n).map(|i| i as f64 * 0.1).collect();
        let col = |tau: f64| {
            DMatrix::from_iterator(
                n,
                1,
                x.iter()
                    .map(|x| if tau < 0.0 { 2.0 } else { (-x / tau).exp() }),
            )
        };
        // three members at "τ < 0": the constant column
        let grid: Vec<f64> = (0..20)
            .map(|k| {
                if [3, 9, 17].contains(&k) {
                    -1.0
                } else {
                    0.5 + 0.4 * k as f64
                }
            })
            .collect();
        let (factor, r0, c) = drift_family(col, &grid, 9);
        let one = scan_family_on(&factor, Some(&r0), &c, Threads::ONE, &mut Vec::new());
        let two = scan_family_on(&factor, Some(&r0), &c, Threads::new(2), &mut Vec::new());
        assert_eq!(
            one.effective_shapes.to_bits(),
            two.effective_shapes.to_bits()
        );
        let bits = |m: &Option<Vec<(f64, usize)>>| {
            m.as_ref()
                .unwrap()
                .iter()
                .map(|(r, k)| (r.to_bits(), *k))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&one.members), bits(&two.members));
        // in a buffer another family left (longer, every value NaN): the same scan
        let mut left = vec![f64::NAN; n * 25];
        let reused = scan_family_on(&factor, Some(&r0), &c, Threads::new(2), &mut left);
        assert_eq!(
            one.effective_shapes.to_bits(),
            reused.effective_shapes.to_bits()
        );
        assert_eq!(bits(&one.members), bits(&reused.members));
        assert_eq!(left.len(), n * 25);
        // the absorbed members add no rank
        let members = one.members.unwrap();
        assert_eq!(members.len(), 20);
        assert!([3, 9, 17].iter().all(|&k| members[k].1 == 0));
        assert!(one.effective_shapes > 1.0 && one.effective_shapes < 17.0);
    }

    /// Each member's fit from the scan is its own Frisch–Waugh–Lovell fit ([`fwl`]), bit for
    /// bit, whether the members have one column (projected in the directions' own columns) or
    /// two (projected in a copy): 300 points, 12 members, a constant baseline.
    #[test]
    fn a_members_scan_fit_is_its_own_fit() {
        let n = 300;
        let x: Vec<f64> = (0..n).map(|i| i as f64 * 0.1).collect();
        let grid: Vec<f64> = (0..12).map(|k| 0.5 + 0.4 * k as f64).collect();
        let one_column =
            |tau: f64| DMatrix::from_iterator(n, 1, x.iter().map(|x| (-x / tau).exp()));
        let (factor, r0, c) = drift_family(one_column, &grid, 4);
        let shape = c.family.as_ref().unwrap().shape.clone();
        for width in [1, 2] {
            let members = grid
                .iter()
                .map(|&t| DMatrix::from_fn(n, width, |i, j| (-x[i] / (t + j as f64)).exp()))
                .collect();
            let c = Candidate {
                family: Some(Family::stored(shape.clone(), members)),
                ..c.clone()
            };
            let scan = scan_family_on(&factor, Some(&r0), &c, Threads::ONE, &mut Vec::new());
            let family = c.family.as_ref().unwrap();
            for (k, (rss, rank)) in scan.members.unwrap().into_iter().enumerate() {
                let (want, want_rank) = fwl(&factor, &r0, &family.member(k));
                assert_eq!(
                    (rss.to_bits(), rank),
                    (want.to_bits(), want_rank),
                    "{width}, {k}"
                );
            }
            assert!(scan.effective_shapes >= 1.0 && scan.effective_shapes <= 12.0);
        }
    }

    /// A warm-up family with its pause profiled out: 240 points, the first half on A, data made
    /// at f = 0.3 and a pause of 0.2 (grid values) with noise 1 % of the amplitude over a constant
    /// baseline: the profile's interval holds f, the member chosen is at the pause 0.2, and the
    /// same data fitted without the pause (its first member of each f) put f outside its interval
    /// (the pause's step read as a slower warm-up). On 3 threads the fit is the one on 1, bit for
    /// bit (its Debug text).
    #[test]
    fn a_pause_between_the_passes_is_profiled_out() {
        use crate::effects::family::{Members, WarmUpBasis};
        use crate::parameter::effect::{PAUSE_GRID, WARM_UP_GRID};
        let n = 240;
        let basis = WarmUpBasis {
            x: (0..n).map(|i| (i as f64 + 0.5) / n as f64).collect(),
            second: (0..n).map(|i| i >= n / 2).collect(),
            z: (0..n)
                .map(|i| 0.5 + 0.5 * (i as f64 * 0.37).sin())
                .collect(),
        };
        let family = Family {
            shape: Effect::ThermalDrift.shape().unwrap(),
            profiled: Effect::ThermalDrift.profiled(),
            members: Members::WarmUp(basis.clone()),
        };
        assert_eq!(family.len(), WARM_UP_GRID.len() * PAUSE_GRID.len());
        let a = DMatrix::from_element(n, 1, 1.0);
        let factor = Factor::new(&a, None);
        let mut rng = Sampler::new(11);
        let truth = basis.column(0.3, 0.2);
        let y = DVector::from_iterator(n, truth.iter().map(|v| 0.02 * v + 2e-4 * rng.normal()));
        let r0 = factor.unabsorbed_vec(&y);
        let c = Candidate {
            effect: Effect::ThermalDrift,
            signature: NamedColumns::try_new(
                Effect::ThermalDrift.parameter_ids(),
                DMatrix::from_vec(n, 1, basis.column(f64::INFINITY, 0.0)),
            )
            .unwrap()
            .into(),
            family: Some(family.clone()),
        };
        let fit = fit_shape(&factor, &r0, &c, 1, None, 1.0, None, Threads::ONE).unwrap();
        assert!(fit.low <= 0.3 && 0.3 <= fit.high, "{fit:?}");
        // the searches' two members side by side: the same fit, bit for bit
        let on_three = fit_shape(&factor, &r0, &c, 1, None, 1.0, None, Threads::new(3)).unwrap();
        assert_eq!(format!("{on_three:?}"), format!("{fit:?}"));
        assert_eq!(fit.profiled.as_ref().map(|p| p.value), Some(0.2), "{fit:?}");
        assert_eq!(family.values(fit.grid_index).1, Some(0.2));
        // the family without its pause
        let unpaused = Family::stored(
            family.shape.clone(),
            (0..WARM_UP_GRID.len())
                .map(|i| family.member(i * PAUSE_GRID.len()).into_owned())
                .collect(),
        );
        let c0 = Candidate {
            family: Some(unpaused),
            ..c
        };
        let fit0 = fit_shape(&factor, &r0, &c0, 1, None, 1.0, None, Threads::ONE).unwrap();
        assert!(!(fit0.low <= 0.3 && 0.3 <= fit0.high), "{fit0:?}");
    }
}
