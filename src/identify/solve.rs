//! Least squares on small dense matrices by a column-scaled SVD with a numerical rank: the core
//! shared by the gap diagnosis (baseline and candidate fits, cross-validation folds, equivalence
//! spans) and by identification's residual statistics.
//!
//! `min ‖y − A·x‖²`: the columns of `A` are scaled to unit norm (by `scale`, when given, the
//! norms of the columns *before* any projection, so that a column the baseline absorbs almost
//! entirely counts as rank-deficient rather than as a tiny but "new" direction), then
//! `A·D⁻¹ = U Σ Vᵀ` and `x = D⁻¹ V Σ⁺ Uᵀ y`, with singular values below [`RANK_TOL`] (relative to
//! the unit column scale) dropped. `cov = D⁻¹ V Σ⁻² Vᵀ D⁻¹` is `(AᵀA)⁺`; multiply by `σ²` for the
//! covariance of `x`.
//!
//! Why a fixed `RANK_TOL` here and not the `max(n, p)·ε·s₁` of [`super::ScaledSvd`]: the gap
//! diagnosis projects candidate signatures off the baseline and must treat a direction the
//! baseline absorbs to 1e-7 of its norm as absorbed (not as a new parameter fitted to rounding
//! noise); identification's rank rule decides only exact dependencies and leaves near ones to the
//! condition-index rule.
//!
//! Residual figures: [`rms`] and [`max_abs`] (mm for deviations), the `rms`/`max_abs` of
//! [`super::ResidualStats`] as well.

use nalgebra::{DMatrix, DMatrixView, DMatrixViewMut, DVector};

use super::householder::{finish, HouseholderQr};
use crate::numerics::parallel::{map, map_mut, Threads};

/// Singular values (of the unit-column-scaled matrix) below this count as zero.
pub const RANK_TOL: f64 = 1e-7;

/// A factorised design: orthonormal basis of its column space and its pseudo-inverse.
#[derive(Debug, Clone)]
pub struct Factor {
    /// `n × r` orthonormal basis of the column space (`r` = numerical rank).
    pub basis: DMatrix<f64>,
    /// `V Σ⁻¹` unscaled (`p × r`): the pseudo-inverse is `vsi·basisᵀ` ([`Factor::solve`]; not
    /// formed: at 200,000 rows it would be `p × n`, 0.1 GB, issue 31).
    vsi: DMatrix<f64>,
    /// `p × p` unscaled covariance `(AᵀA)⁺`.
    pub cov: DMatrix<f64>,
    /// Numerical rank.
    pub rank: usize,
    /// Condition number of the retained part of the unit-scaled matrix.
    pub condition: f64,
}

impl Factor {
    /// Factorises `a`; `scale[j]` (if given) is the norm column `j` is measured against.
    pub fn new(a: &DMatrix<f64>, scale: Option<&[f64]>) -> Self {
        if a.ncols() == 1 {
            // by its norm, without a copy
            return Self::column(a, column_scales(a, scale)[0]);
        }
        Self::of(a.clone(), scale)
    }

    /// [`Factor::new`] of a design the caller gives up: scaled in place, no copy (a dense scan's
    /// `[A | smooth basis]` is 90 MB at 200,000 points, issue 31).
    pub fn of(a: DMatrix<f64>, scale: Option<&[f64]>) -> Self {
        Self::of_on(a, scale, Threads::ONE)
    }

    /// [`Factor::of`] with a tall design's row blocks ([`svd_tall`]) factorised side by side on
    /// `threads` threads: the same numbers.
    pub fn of_on(a: DMatrix<f64>, scale: Option<&[f64]>, threads: Threads) -> Self {
        let (n, p) = a.shape();
        if p == 0 || n == 0 {
            return Self {
                basis: DMatrix::zeros(n, 0),
                vsi: DMatrix::zeros(p, 0),
                cov: DMatrix::zeros(p, p),
                rank: 0,
                condition: 1.0,
            };
        }
        let d = column_scales(&a, scale);
        if p == 1 {
            return Self::column(&a, d[0]);
        }
        let mut scaled = a;
        for (j, dj) in d.iter().enumerate() {
            scaled.column_mut(j).scale_mut(1.0 / dj);
        }
        let (u, sv, vt) = svd_tall(scaled, threads);
        let Kept {
            keep,
            vsi,
            condition,
        } = kept(&sv, &vt, &d);
        let rank = keep.len();
        // every column kept (a design of full rank): U itself, not a copy of it (115 MB at
        // 200,000 points, a tenth of a second of one thread, issue 31)
        let basis = if keep.iter().copied().eq(0..u.ncols()) {
            u
        } else {
            u.select_columns(&keep)
        };
        let cov = &vsi * vsi.transpose();
        Self {
            basis,
            vsi,
            cov,
            rank,
            condition,
        }
    }

    /// [`Factor::new`] of one column `a` measured against the norm `d`: its SVD is its norm,
    /// `a/d = (a/‖a‖)·(‖a‖/d)·1` (one pass, where nalgebra's SVD of an `n × 1` matrix makes a
    /// Householder QR and its `Q`: a candidate of one parameter, fitted hundreds of times on a
    /// dense scan, issue 31).
    #[cfg_attr(target_arch = "wasm32", target_feature(enable = "simd128"))]
    fn column(a: &DMatrix<f64>, d: f64) -> Self {
        let norm = a.norm();
        let sv = norm / d;
        if sv > RANK_TOL {
            let vsi = DMatrix::from_element(1, 1, 1.0 / norm);
            Self {
                basis: a / norm,
                cov: &vsi * vsi.transpose(),
                vsi,
                rank: 1,
                condition: 1.0,
            }
        } else {
            Self {
                basis: DMatrix::zeros(a.nrows(), 0),
                vsi: DMatrix::zeros(1, 0),
                cov: DMatrix::zeros(1, 1),
                rank: 0,
                condition: 1.0,
            }
        }
    }

    /// The least-squares (minimum-norm) solution `x = A⁺y = V Σ⁻¹ (Qᵀ y)`.
    pub fn solve(&self, y: &DVector<f64>) -> DVector<f64> {
        self.solve_products(&self.basis.tr_mul(y))
    }

    /// [`Self::solve`] from the products `Qᵀy` (`r` of them): `V Σ⁻¹ (Qᵀy)`, without reading `Q`.
    pub fn solve_products(&self, qty: &DVector<f64>) -> DVector<f64> {
        &self.vsi * qty
    }

    /// `x - Q Qᵀ x`: the part of each column of `x` outside the column space (`Qᵀx` without
    /// forming `Qᵀ`: at 20,000 rows a copy of 9 MB a call).
    /// With few columns on either side, by [`unabsorbed_few`] (the same bits, `Q` read twice
    /// instead of twice a column of `x`).
    pub fn unabsorbed(&self, x: &DMatrix<f64>) -> DMatrix<f64> {
        self.unabsorbed_with_products(x).0
    }

    /// [`Self::unabsorbed`] of `x` and the products `Qᵀx` (`r × q`) it subtracted `Q` times:
    /// with them the least-squares solution for `y − x θ` is [`Self::solve_products`] of
    /// `Qᵀy − (Qᵀx) θ`, `Q` not read again (a fold's prediction, crate::gap::which).
    pub fn unabsorbed_with_products(&self, x: &DMatrix<f64>) -> (DMatrix<f64>, DMatrix<f64>) {
        if self.takes_few(x) {
            return unabsorbed_few(&self.basis, x);
        }
        let c = tr_mul(&self.basis, x);
        (x - &self.basis * &c, c)
    }

    /// Whether [`Self::unabsorbed`] of `x` is [`unabsorbed_few`]'s: few columns on either side.
    fn takes_few(&self, x: &DMatrix<f64>) -> bool {
        let (n, p) = self.basis.shape();
        n > SMALL_PRODUCT && (p <= SMALL_PRODUCT || x.ncols() <= SMALL_PRODUCT)
    }

    /// [`Self::unabsorbed`] of each of `xs`, the same bits as a call for each: the columns of
    /// those that a call would give to [`unabsorbed_few`] go through it together, in one group a
    /// thread, so `Q` is read twice a group instead of twice a matrix (a dense scan's candidates
    /// off the smooth fit's basis, 90 MB at 200,000 × 56, once a candidate, issue 31); the
    /// others as a call each.
    pub fn unabsorbed_each(&self, xs: &[&DMatrix<f64>], threads: Threads) -> Vec<DMatrix<f64>> {
        self.unabsorbed_each_with_products(xs, threads)
            .into_iter()
            .map(|(u, _)| u)
            .collect()
    }

    /// [`Self::unabsorbed_with_products`] of each of `xs`, the same bits as a call for each, the
    /// columns grouped as by [`Self::unabsorbed_each`].
    pub fn unabsorbed_each_with_products(
        &self,
        xs: &[&DMatrix<f64>],
        threads: Threads,
    ) -> Vec<(DMatrix<f64>, DMatrix<f64>)> {
        let (n, r) = self.basis.shape();
        let mut out: Vec<(DMatrix<f64>, DMatrix<f64>)> = map(threads, xs, |&x| {
            if self.takes_few(x) {
                assert_eq!(n, x.nrows(), "unabsorbed: {n} rows against {}", x.nrows());
                (x.clone(), DMatrix::zeros(r, x.ncols()))
            } else {
                self.unabsorbed_with_products(x)
            }
        });
        // each column to go through the kernel, and the matrix and column it is
        let mut cols: Vec<Tagged> = out
            .iter_mut()
            .zip(xs)
            .enumerate()
            .filter(|(_, (_, &x))| self.takes_few(x))
            .flat_map(|(m, ((u, _), _))| {
                u.as_mut_slice()
                    .chunks_mut(n.max(1))
                    .enumerate()
                    .map(move |(j, col)| (col, (m, j)))
            })
            .collect();
        if n == 0 || cols.is_empty() {
            return out;
        }
        let per = cols.len().div_ceil(threads.get().max(1));
        let mut groups: Vec<Vec<Tagged>> = Vec::new();
        while !cols.is_empty() {
            let rest = cols.split_off(per.min(cols.len()));
            groups.push(std::mem::replace(&mut cols, rest));
        }
        let products = map_mut(threads, &mut groups, |g| {
            let mut cols: Vec<&mut [f64]> = g.iter_mut().map(|(c, _)| &mut **c).collect();
            let c = unabsorb_columns(&self.basis, &mut cols);
            let at: Vec<(usize, usize)> = g.iter().map(|&(_, at)| at).collect();
            (c, at)
        });
        for (c, at) in products {
            for (k, (m, j)) in at.into_iter().enumerate() {
                out[m].1.set_column(j, &c.column(k));
            }
        }
        out
    }

    /// [`Self::unabsorbed`] in place: `x ← x − Q Qᵀ x` on a view (the columns of a larger
    /// matrix, without a copy of `x` and of the product: a dense scan's family members, issue 31),
    /// the same bits. Where `Q (Qᵀx)` is a blocked product (more than [`SMALL_PRODUCT`] rows,
    /// columns of `x` and of `Q`, and at most [`PRODUCT_DEPTH`] columns of `Q`), the product is
    /// subtracted in its own epilogue (`c ← −ab + c`: `ab` is summed as for the copy, then one
    /// rounding, that of `x − ab`); else the product is formed and subtracted, as by the copy.
    pub fn unabsorb_in_place(&self, mut x: DMatrixViewMut<'_, f64>) {
        let c = tr_mul_view(&self.basis, x.as_view());
        let (n, w) = x.shape();
        let r = self.basis.ncols();
        if cfg!(target_arch = "wasm32") && n > SMALL_PRODUCT && r > SMALL_PRODUCT {
            // the browser's: `x − Qc` a column at a time (crate::numerics::products)
            let q = crate::numerics::products::columns(&self.basis);
            for (mut col, cj) in x.column_iter_mut().zip(c.column_iter()) {
                crate::numerics::products::sub_mul(col.as_mut_slice(), &q, cj.as_slice());
            }
        } else if n > SMALL_PRODUCT && w > SMALL_PRODUCT && r > SMALL_PRODUCT && r <= PRODUCT_DEPTH
        {
            x.gemm(-1.0, &self.basis, &c, 1.0);
        } else {
            x -= &self.basis * c;
        }
    }

    /// Same for one vector.
    pub fn unabsorbed_vec(&self, x: &DVector<f64>) -> DVector<f64> {
        x - &self.basis * self.basis.tr_mul(x)
    }
}

/// A column and the matrix and column of it it is ([`Factor::unabsorbed_each_with_products`]).
type Tagged<'a> = (&'a mut [f64], (usize, usize));

/// What a scaled design's SVD keeps: the singular values above [`RANK_TOL`] (their indices),
/// `V Σ⁻¹` on them with its rows unscaled by `D⁻¹` (`p × r`), and the condition number of the
/// kept part (1 with none).
pub(crate) struct Kept {
    pub(crate) keep: Vec<usize>,
    pub(crate) vsi: DMatrix<f64>,
    pub(crate) condition: f64,
}

/// [`Kept`] from the singular values `sv` and `Vᵀ` of the design scaled by `d`.
pub(crate) fn kept(sv: &DVector<f64>, vt: &DMatrix<f64>, d: &[f64]) -> Kept {
    let p = d.len();
    let keep: Vec<usize> = (0..sv.len()).filter(|&k| sv[k] > RANK_TOL).collect();
    let smax = keep.iter().map(|&k| sv[k]).fold(0.0, f64::max);
    let smin = keep.iter().map(|&k| sv[k]).fold(f64::INFINITY, f64::min);
    // V Σ⁻¹ (p × r), then unscale rows by D⁻¹.
    let mut vsi = DMatrix::zeros(p, keep.len());
    for (c, &k) in keep.iter().enumerate() {
        for j in 0..p {
            vsi[(j, c)] = vt[(k, j)] / sv[k] / d[j];
        }
    }
    let condition = if keep.is_empty() { 1.0 } else { smax / smin };
    Kept {
        keep,
        vsi,
        condition,
    }
}

/// The norm each column of `a` is measured against: `scale[j]` when given, else the column's
/// norm; 1 where that is 0 or not finite ([`usable_scale`]).
#[cfg_attr(target_arch = "wasm32", target_feature(enable = "simd128"))]
pub(crate) fn column_scales(a: &DMatrix<f64>, scale: Option<&[f64]>) -> Vec<f64> {
    (0..a.ncols())
        .map(|j| usable_scale(scale.map_or_else(|| a.column(j).norm(), |s| s[j])))
        .collect()
}

/// A scale usable as a divisor: `s`, or 1 when `s` is 0, negative or not finite.
pub(crate) fn usable_scale(s: f64) -> f64 {
    if s > 0.0 && s.is_finite() {
        s
    } else {
        1.0
    }
}

/// Above this many rows, and at least [`QR_FIRST_RATIO`] times as many rows as columns, the SVD
/// of a design is that of its `R` after a Householder QR (`A = QR`, `R = U_R Σ Vᵀ`, `U = Q U_R`:
/// the same singular values and vectors to rounding). nalgebra's SVD of a tall matrix carries
/// its `n × p` `U` through every bidiagonal sweep: 97 ms against 70 ms at 20,000 × 56, 1.53 s
/// against 0.67 s at 200,000 × 56 (a dense scan's smooth fit, issue 31). The built-in 100 points
/// stay on the direct SVD.
pub const QR_FIRST_ROWS: usize = 2000;
/// See [`QR_FIRST_ROWS`].
pub const QR_FIRST_RATIO: usize = 4;
/// Rows of a block of the tall QR ([`svd_tall`]; at least twice the columns): a block of a
/// dense scan's `[A | smooth basis]` (4,096 × 72, 2.4 MB) stays in the cache while its
/// reflections sweep it, where the whole matrix (115 MB at 200,000 points) streams from memory
/// once a reflection: 1.05 s against 0.65 s on one thread at 200,000 × 72, 73 against 56 ms at
/// 20,000 × 72 (issue 31).
pub const TALL_QR_ROWS: usize = 4096;

/// Below this many entries (8 MB) a tall design's QR is one block: it is in the cache already,
/// and the blocks' own `Q`s and products only add work (a 20,000-point scan with a C backlash,
/// whose candidates' fits factorise 20,000 × 9-12 designs hundreds of times: 1.89 → 2.14 s with
/// every design in blocks).
pub const TALL_QR_MIN_ENTRIES: usize = 1 << 20;

/// `U` (`n × min(n, p)`), the singular values and `Vᵀ` of `a`. Above [`QR_FIRST_ROWS`], by the
/// QR of row blocks of [`TALL_QR_ROWS`] (TSQR, Demmel et al. 2012, "Communication-optimal
/// parallel and sequential QR and LU factorizations", SIAM J. Sci. Comput. 34(1) §3):
/// `A_i = Q_i R_i` for each block, side by side on `threads` threads, then the stacked `R_i`
/// `= Q_s R`; `R = U_R Σ Vᵀ`, `W = Q_s U_R`, and block `i` of `U` is `Q_i W_i` (`W_i` its `p`
/// rows of `W`). Householder reflections throughout, so as backward stable as the QR of the
/// whole; one block (fewer than 2·[`TALL_QR_ROWS`] rows, or [`TALL_QR_MIN_ENTRIES`]) is that QR.
fn svd_tall(a: DMatrix<f64>, threads: Threads) -> (DMatrix<f64>, DVector<f64>, DMatrix<f64>) {
    let (n, p) = a.shape();
    if n <= QR_FIRST_ROWS || n < QR_FIRST_RATIO * p {
        return svd_parts(a.svd(true, true));
    }
    let m = if n * p < TALL_QR_MIN_ENTRIES {
        1
    } else {
        (n / TALL_QR_ROWS.max(2 * p)).max(1)
    };
    if m == 1 {
        let qr = HouseholderQr::new(a);
        let (u, sv, vt) = jacobi_svd(qr.r());
        return (mul_tall(&qr.q(), u.as_view()), sv, vt);
    }
    let bounds: Vec<(usize, usize)> = (0..m).map(|i| (i * n / m, (i + 1) * n / m)).collect();
    let blocks = map(threads, &bounds, |&(start, end)| {
        HouseholderQr::new(a.rows(start, end - start).clone_owned())
    });
    drop(a);
    let mut stacked = DMatrix::zeros(m * p, p);
    for (i, qr) in blocks.iter().enumerate() {
        stacked.view_mut((i * p, 0), (p, p)).copy_from(&qr.r());
    }
    let top = HouseholderQr::new(stacked);
    let (u_r, sv, vt) = jacobi_svd(top.r());
    let w = top.q() * u_r;
    // U's rows a block at a time, each written by the thread that computes them (its piece of
    // every column: U is column-major), the block's QR dropped once used: the blocks and U are
    // not all held beside each other's copies (and the 90 MB of U at 200,000 points not copied
    // in by one thread, issue 31)
    let k = w.ncols();
    let mut u = zeros_lazily(n, k);
    let mut pieces: Vec<Vec<&mut [f64]>> = bounds.iter().map(|_| Vec::with_capacity(k)).collect();
    for column in u.as_mut_slice().chunks_mut(n) {
        let mut rest = column;
        for (piece, (start, end)) in pieces.iter_mut().zip(&bounds) {
            let (rows, tail) = rest.split_at_mut(end - start);
            piece.push(rows);
            rest = tail;
        }
    }
    let mut jobs: Vec<(usize, Option<_>, Vec<&mut [f64]>)> = blocks
        .into_iter()
        .zip(pieces)
        .enumerate()
        .map(|(i, (qr, piece))| (i, Some(qr), piece))
        .collect();
    map_mut(threads, &mut jobs, |(i, qr, piece)| {
        if let Some(qr) = qr.take() {
            let part = mul_tall(&qr.q(), w.rows(*i * p, p));
            let rows = part.nrows();
            for (c, column) in piece.iter_mut().enumerate() {
                column.copy_from_slice(&part.as_slice()[c * rows..(c + 1) * rows]);
            }
        }
    });
    drop(jobs);
    (u, sv, vt)
}

/// `a·b` for a tall `a` (`n × p`) and a small `b` (`p × q`): nalgebra's product natively; in the
/// browser a column at a time by [`crate::numerics::products::mul_into`] (wasm has only
/// `matrixmultiply`'s portable kernel, slow on such shapes, issue 31).
fn mul_tall(a: &DMatrix<f64>, b: DMatrixView<'_, f64>) -> DMatrix<f64> {
    let (n, p) = a.shape();
    assert_eq!(
        p,
        b.nrows(),
        "product: {p} columns against {} rows",
        b.nrows()
    );
    if cfg!(target_arch = "wasm32") && n > SMALL_PRODUCT && p > SMALL_PRODUCT {
        let cols = crate::numerics::products::columns(a);
        let mut out = DMatrix::zeros(n, b.ncols());
        for (mut col, bj) in out.column_iter_mut().zip(b.column_iter()) {
            crate::numerics::products::mul_into(col.as_mut_slice(), &cols, bj.as_slice());
        }
        return out;
    }
    a * b
}

/// The SVD `R = U Σ Vᵀ` of a small square `R` (a tall design's `R` after its QR) by one-sided
/// Jacobi rotations (Hestenes 1958; Demmel & Veselić 1992, who show it accurate to rounding in
/// every singular value relative to the column scaling): pairs of columns of `R V` rotated
/// until every pair is orthogonal to rounding, `σ_k` the columns' norms, `U`'s columns the
/// normalised ones (zero for `σ_k = 0`), sorted by decreasing `σ`. nalgebra's bidiagonal SVD
/// can return wrong singular values (its issue 1172): 1.4252 for 1.4143 on the `R` of a
/// 120,000 × 9 design in blocks (issue 31), which `Factor` would divide by.
pub(crate) fn jacobi_svd(r: DMatrix<f64>) -> (DMatrix<f64>, DVector<f64>, DMatrix<f64>) {
    let (m, p) = r.shape();
    let mut a = r;
    let mut v = DMatrix::<f64>::identity(p, p);
    for _ in 0..JACOBI_SWEEPS {
        let mut rotated = false;
        for i in 0..p.saturating_sub(1) {
            for j in i + 1..p {
                let alpha = a.column(i).norm_squared();
                let beta = a.column(j).norm_squared();
                let gamma = a.column(i).dot(&a.column(j));
                if gamma == 0.0 || gamma.abs() <= f64::EPSILON * (alpha * beta).sqrt() {
                    continue;
                }
                rotated = true;
                // the smaller root of t² + 2ζt − 1 = 0 makes columns i and j orthogonal
                let zeta = (beta - alpha) / (2.0 * gamma);
                let t = zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt());
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = c * t;
                for mat in [&mut a, &mut v] {
                    for k in 0..mat.nrows() {
                        let (x, y) = (mat[(k, i)], mat[(k, j)]);
                        mat[(k, i)] = c * x - s * y;
                        mat[(k, j)] = s * x + c * y;
                    }
                }
            }
        }
        if !rotated {
            break;
        }
    }
    let norms: Vec<f64> = (0..p).map(|k| a.column(k).norm()).collect();
    let mut order: Vec<usize> = (0..p).collect();
    order.sort_by(|&x, &y| norms[y].total_cmp(&norms[x]));
    let mut u = DMatrix::zeros(m, p);
    let mut vt = DMatrix::zeros(p, p);
    for (k, &o) in order.iter().enumerate() {
        if norms[o] > 0.0 {
            u.set_column(k, &(a.column(o) / norms[o]));
        }
        vt.set_row(k, &v.column(o).transpose());
    }
    let sv = DVector::from_iterator(p, order.iter().map(|&o| norms[o]));
    (u, sv, vt)
}

/// Sweeps of [`jacobi_svd`] at most: it converges quadratically, in 6-10 sweeps for the
/// designs here; 60 only bounds a pathological case.
const JACOBI_SWEEPS: usize = 60;

/// `U`, the singular values and `Vᵀ` of an SVD computed with both.
fn svd_parts(
    svd: nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>,
) -> (DMatrix<f64>, DVector<f64>, DMatrix<f64>) {
    // nalgebra always returns U and Vᵀ when asked for them.
    let (Some(u), Some(vt)) = (svd.u, svd.v_t) else {
        unreachable!("SVD computed with U and V")
    };
    (u, svd.singular_values, vt)
}

/// An `n × m` matrix of zeros whose memory the system zeroes page by page on first touch
/// (`vec![0.0; n·m]` allocates zeroed memory, where `DMatrix::zeros` writes every entry): a dense
/// scan's large outputs (115 MB at 200,000 points) are then not written twice, the first time
/// by one thread (issue 31). The same matrix.
pub fn zeros_lazily(n: usize, m: usize) -> DMatrix<f64> {
    DMatrix::from_vec(n, m, vec![0.0; n * m])
}

/// `[a | b]`: the columns of `a`, then those of `b` (same number of rows).
pub fn hstack(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let n = a.nrows();
    assert_eq!(n, b.nrows(), "hstack: {n} rows beside {}", b.nrows());
    // column-major: a's columns, then b's, each storage copied whole (an entry at a time through
    // a closure had been 40 ms of one thread for a dense scan's 115 MB, issue 31)
    let mut data = Vec::with_capacity(n * (a.ncols() + b.ncols()));
    data.extend_from_slice(a.as_slice());
    data.extend_from_slice(b.as_slice());
    DMatrix::from_vec(n, a.ncols() + b.ncols(), data)
}

/// `aᵀb`. With more than a few columns on each side, as one blocked product (`matrixmultiply`,
/// through [`DMatrix::gemm`] on `aᵀ` viewed in place by its strides: no copy of `a`), which reads
/// `a` once, where nalgebra's `tr_mul` takes a dot product per entry and reads `a` once a column
/// of `b` (at 20,000 rows and 56 columns, 9 MB each time); otherwise nalgebra's `tr_mul` (a
/// blocked product on a strided view of one column would touch a cache line per row). The sums
/// are in another order: equal to rounding.
pub fn tr_mul(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    tr_mul_view(a, b.as_view())
}

/// `aᵀa` by row blocks of [`TALL_QR_ROWS`], the blocks side by side on `threads` threads and
/// summed in their order (the same bits on any number of threads; to rounding [`tr_mul`]'s):
/// a dense scan's `n × m` Gram matrices, one thread's 0.1 s each at 200,000 × 54 (issue 31).
pub fn gram_on(a: &DMatrix<f64>, threads: Threads) -> DMatrix<f64> {
    let (n, p) = a.shape();
    gram_of_columns(a.as_slice(), n, p, threads)
}

/// [`gram_on`] of the `n × p` matrix whose columns are `a` one after the other (column-major,
/// `a.len() ≥ n·p`): the same bits.
pub fn gram_of_columns(a: &[f64], n: usize, p: usize, threads: Threads) -> DMatrix<f64> {
    assert!(a.len() >= n * p, "gram of {n} × {p} on {} values", a.len());
    sum_over_row_blocks(n, p, threads, |r0, rows| {
        let mut out = DMatrix::zeros(p, p);
        if cfg!(target_arch = "wasm32") {
            // the browser's: the block's columns' dot products (module doc of
            // crate::numerics::products)
            let cols: Vec<&[f64]> = (0..p).map(|j| &a[j * n + r0..j * n + r0 + rows]).collect();
            let o = out.as_mut_slice();
            crate::numerics::products::tr_mul_into(&cols, &cols, o, p, Some(0));
            crate::numerics::products::mirror_upper(o, p, p);
            return out;
        }
        // the block's rows of aᵀ (p × rows) and of a, viewed in place
        let at = DMatrixView::from_slice_with_strides(&a[r0..], p, rows, n, 1);
        let block = DMatrixView::from_slice_with_strides(&a[r0..], rows, p, 1, n);
        out.gemm(1.0, &at, &block, 0.0);
        out
    })
}

/// `Σ block(r0, rows)` (each `k × k`) over the row blocks `r0..r0 + rows` of [`TALL_QR_ROWS`]
/// that cover `n` rows, the blocks side by side on `threads` threads and summed in their order:
/// the same bits on any number of threads (the Gram matrices of a dense scan, [`gram_on`] and
/// [`crate::gap::span_gram::SpanGram`]).
pub fn sum_over_row_blocks(
    n: usize,
    k: usize,
    threads: Threads,
    block: impl Fn(usize, usize) -> DMatrix<f64> + Sync,
) -> DMatrix<f64> {
    let starts: Vec<usize> = (0..n).step_by(TALL_QR_ROWS).collect();
    let blocks = map(threads, &starts, |&r0| block(r0, TALL_QR_ROWS.min(n - r0)));
    let mut g = DMatrix::zeros(k, k);
    for b in blocks {
        g += b;
    }
    g
}

/// Up to this many rows or columns nalgebra multiplies by columns (its `gemm`'s `SMALL_DIM`),
/// above by blocks (`matrixmultiply`).
pub const SMALL_PRODUCT: usize = 5;

/// Depth (the shared dimension) up to which the blocked product sums in one pass
/// (`matrixmultiply`'s `kc` for `f64`), so that subtracting in its epilogue rounds as
/// subtracting the finished product.
pub const PRODUCT_DEPTH: usize = 256;

/// [`tr_mul`] with `b` a view (the columns of a larger matrix): the same bits.
pub fn tr_mul_view(a: &DMatrix<f64>, b: DMatrixView<'_, f64>) -> DMatrix<f64> {
    const FEW: usize = SMALL_PRODUCT;
    let (n, p) = a.shape();
    assert_eq!(n, b.nrows(), "tr_mul: {n} rows against {}", b.nrows());
    if p <= FEW || b.ncols() <= FEW || n <= FEW {
        return a.tr_mul(&b);
    }
    let mut out = DMatrix::zeros(p, b.ncols());
    if cfg!(target_arch = "wasm32") {
        // the browser's: dot products of the columns (crate::numerics::products)
        let a_cols = crate::numerics::products::columns(a);
        // (the views of b's columns kept, so their slices may be borrowed)
        let views: Vec<_> = b.column_iter().collect();
        let b_cols: Vec<&[f64]> = views.iter().map(|c| c.as_slice()).collect();
        crate::numerics::products::tr_mul_into(&a_cols, &b_cols, out.as_mut_slice(), p, None);
        return out;
    }
    // aᵀ (p × n) on a's column-major storage: entry (j, i) at i + j·n
    let at = nalgebra::DMatrixView::from_slice_with_strides(a.as_slice(), p, n, n, 1);
    out.gemm(1.0, &at, &b, 0.0);
    out
}

/// Rows of a block of [`unabsorbed_few`]'s passes: a multiple of 8 (nalgebra's dot products sum
/// eight rows at a time); the block's rows of `Q` (49 kB at 12 columns) stay in the cache while
/// every column of `x` is read against them.
const FEW_BLOCK_ROWS: usize = 512;

/// `x − Q(Qᵀx)` when `x` or `Q` has at most [`SMALL_PRODUCT`] columns, by the operations
/// nalgebra takes for such shapes, bit for bit: its `tr_mul`'s dot products (eight partial sums
/// over the rows ≡ m mod 8 of the first 8⌊n/8⌋ rows, added in pairs `(0, 4), (1, 5), (2, 6),
/// (3, 7)`, then the rows left one by one) and its product column by column (`y ← Q₀c₀`, then
/// `y ← Q_k c_k + y` in the order of `Q`'s columns; `+` commutes exactly), then `x − y`. In two
/// passes over blocks of rows: `Q` is read twice, where nalgebra's two calls read it once a
/// column of `x` each (a dense scan's baseline basis, 16 MB at 200,000 points, had been streamed
/// from memory 2·q times for a candidate's q columns, issue 31). Each column's numbers depend on
/// that column and `Q` alone: [`unabsorb_columns`] takes any set of columns together.
/// Also the products `Qᵀx` (`p × q`) it subtracted `Q` times.
fn unabsorbed_few(q: &DMatrix<f64>, x: &DMatrix<f64>) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = q.nrows();
    assert_eq!(n, x.nrows(), "unabsorbed: {n} rows against {}", x.nrows());
    let mut out = x.clone();
    if n == 0 {
        return (out, DMatrix::zeros(q.ncols(), x.ncols()));
    }
    let mut cols: Vec<&mut [f64]> = out.as_mut_slice().chunks_mut(n).collect();
    let c = unabsorb_columns(q, &mut cols);
    (out, c)
}

/// `x ← x − Q(Qᵀx)` on each of the columns `cols` (each `Q`'s rows long), [`unabsorbed_few`]'s
/// operations: each column the same bits whatever the others beside it. Returns `Qᵀx` (`p × w`,
/// column `j` that of `cols[j]`).
///
/// On a processor with AVX2 the same code is compiled for it (chosen at run time): four rows
/// an instruction instead of two, each lane the same multiplications and additions in the same
/// order (no fused multiply-add), so the same bits.
fn unabsorb_columns(q: &DMatrix<f64>, cols: &mut [&mut [f64]]) -> DMatrix<f64> {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2, checked just above
            return unsafe { unabsorb_columns_avx2(q, cols) };
        }
    }
    #[cfg(target_arch = "wasm32")]
    return unabsorb_columns_simd128(q, cols);
    #[cfg(not(target_arch = "wasm32"))]
    unabsorb_columns_in(q, cols)
}

/// [`unabsorb_columns_in`] compiled for wasm's 128-bit SIMD (two rows an instruction, no fused
/// multiply-add: the same bits).
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn unabsorb_columns_simd128(q: &DMatrix<f64>, cols: &mut [&mut [f64]]) -> DMatrix<f64> {
    unabsorb_columns_in(q, cols)
}

/// [`unabsorb_columns_in`] compiled for AVX2 (without FMA: the same roundings).
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn unabsorb_columns_avx2(q: &DMatrix<f64>, cols: &mut [&mut [f64]]) -> DMatrix<f64> {
    unabsorb_columns_in(q, cols)
}

/// [`unabsorb_columns`]'s two passes.
#[inline(always)]
fn unabsorb_columns_in(q: &DMatrix<f64>, cols: &mut [&mut [f64]]) -> DMatrix<f64> {
    let (n, p) = q.shape();
    let w = cols.len();
    if let Some(c) = cols.iter().find(|c| c.len() != n) {
        panic!("unabsorbed: {n} rows against {}", c.len());
    }
    if p == 0 || w == 0 {
        return DMatrix::zeros(p, w);
    }
    let qs = q.as_slice();
    // pass 1: Qᵀx, each entry's eight partial sums carried from block to block
    let body = n - n % 8;
    let mut partial = vec![[0.0f64; 8]; p * w];
    for start in (0..body).step_by(FEW_BLOCK_ROWS) {
        let end = (start + FEW_BLOCK_ROWS).min(body);
        for k in 0..p {
            let qk = &qs[k * n + start..k * n + end];
            // two columns of `x` a pass over `Q`'s column (each of its values loaded once for
            // two products: 2.5 ms against 3.4 for two columns of 20,000 rows off 60 under Node,
            // issue 31), each entry's partial sums its own: the same bits
            let pairs = cols.chunks_exact(2);
            let single = pairs.remainder();
            for (jp, pair) in pairs.enumerate() {
                let j = 2 * jp;
                let (x0, x1) = (&pair[0][start..end], &pair[1][start..end]);
                // the partial sums in registers through the block
                let (mut a0, mut a1) = (partial[k * w + j], partial[k * w + j + 1]);
                for ((a, b0), b1) in qk
                    .chunks_exact(8)
                    .zip(x0.chunks_exact(8))
                    .zip(x1.chunks_exact(8))
                {
                    for m in 0..8 {
                        a0[m] += a[m] * b0[m];
                        a1[m] += a[m] * b1[m];
                    }
                }
                partial[k * w + j] = a0;
                partial[k * w + j + 1] = a1;
            }
            for (col, j) in single.iter().zip(w - single.len()..) {
                let xj = &col[start..end];
                let mut acc = partial[k * w + j];
                for (a, b) in qk.chunks_exact(8).zip(xj.chunks_exact(8)) {
                    for m in 0..8 {
                        acc[m] += a[m] * b[m];
                    }
                }
                partial[k * w + j] = acc;
            }
        }
    }
    let mut c = DMatrix::zeros(p, w);
    for k in 0..p {
        for (j, col) in cols.iter().enumerate() {
            let mut res = finish(&partial[k * w + j]);
            for i in body..n {
                res += qs[k * n + i] * col[i];
            }
            c[(k, j)] = res;
        }
    }
    // pass 2: x − Q c, a block of rows at a time
    let mut y = vec![0.0; FEW_BLOCK_ROWS.min(n)];
    for start in (0..n).step_by(FEW_BLOCK_ROWS) {
        let end = (start + FEW_BLOCK_ROWS).min(n);
        let y = &mut y[..end - start];
        for (j, col) in cols.iter_mut().enumerate() {
            let c0 = c[(0, j)];
            for (yi, a) in y.iter_mut().zip(&qs[start..end]) {
                *yi = a * c0;
            }
            crate::numerics::products::add_products(
                y,
                1..p,
                |k| &qs[k * n + start..k * n + end],
                |k| c[(k, j)],
            );
            for (o, yi) in col[start..end].iter_mut().zip(y.iter()) {
                *o -= *yi;
            }
        }
    }
    c
}

/// Root mean square of a slice (0 for an empty one).
pub fn rms(x: &[f64]) -> f64 {
    if x.is_empty() {
        0.0
    } else {
        (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
    }
}

/// Largest absolute value (0 for an empty slice).
pub fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`unabsorbed_few`] is nalgebra's `x − Q(Qᵀx)` bit for bit, on shapes with few columns on
    /// either side, row counts on and off the multiples of 8 and of the block, and a column of
    /// signed zeros (tolerance: none).
    #[test]
    fn the_fused_few_column_unabsorbed_is_nalgebras_bit_for_bit() {
        let f = |i: usize, j: usize| ((i * 7 + j * 13) % 17) as f64 - 8.0 + 0.1 * (i as f64).sin();
        for (n, p, w) in [
            (6, 3, 2),
            (13, 5, 1),
            (1031, 12, 4),
            (1024, 9, 5),
            (2051, 4, 9),
            (777, 1, 3),
            (600, 7, 0),
        ] {
            let q = DMatrix::from_fn(n, p, f);
            let mut x = DMatrix::from_fn(n, w, |i, j| f(i + 3, j + 1) * 1e-3);
            if w > 1 {
                x.column_mut(1).fill(-0.0);
            }
            let want_c = q.tr_mul(&x);
            let want = &x - &q * &want_c;
            // the dispatched kernel (AVX2 where the processor has it) and the portable one
            let portable = {
                let mut out = x.clone();
                let mut cols: Vec<&mut [f64]> = out.as_mut_slice().chunks_mut(n).collect();
                let c = unabsorb_columns_in(&q, &mut cols);
                (out, c)
            };
            for (got, got_c) in [unabsorbed_few(&q, &x), portable] {
                assert_eq!(got.shape(), want.shape());
                for (g, w) in got.iter().zip(want.iter()) {
                    assert_eq!(g.to_bits(), w.to_bits(), "{n} × {p}, {} columns", x.ncols());
                }
                // and the products it subtracted are nalgebra's `Qᵀx`
                assert_eq!(got_c.shape(), want_c.shape());
                for (g, w) in got_c.iter().zip(want_c.iter()) {
                    assert_eq!(g.to_bits(), w.to_bits(), "Qᵀx: {n} × {p}");
                }
            }
        }
    }

    /// [`Factor::unabsorbed_each`] is [`Factor::unabsorbed`] of each matrix bit for bit, and
    /// [`Factor::unabsorbed_each_with_products`] [`Factor::unabsorbed_with_products`] (with the
    /// products `Qᵀx`), on 1, 2 and 3 threads, with matrices of 0, 1, 3 and 9 columns (the last by the blocked product
    /// against a basis of 12 columns) and a basis of 4 columns (every matrix by the few-column
    /// kernel). Tolerance: none.
    #[test]
    fn unabsorbed_each_is_unabsorbed_of_each_bit_for_bit() {
        let f = |i: usize, j: usize| ((i * 7 + j * 13) % 17) as f64 - 8.0 + 0.1 * (i as f64).sin();
        let n = 2051;
        let xs: Vec<DMatrix<f64>> = [1, 3, 0, 9, 1, 2]
            .iter()
            .enumerate()
            .map(|(m, &w)| DMatrix::from_fn(n, w, |i, j| f(i + 3 * m, j + m) * 1e-3))
            .collect();
        let refs: Vec<&DMatrix<f64>> = xs.iter().collect();
        for p in [12, 4] {
            let a = DMatrix::from_fn(n, p, |i, j| f(i, j) + (i % (j + 2)) as f64);
            let factor = Factor::of(a, None);
            let want: Vec<(DMatrix<f64>, DMatrix<f64>)> = xs
                .iter()
                .map(|x| factor.unabsorbed_with_products(x))
                .collect();
            for (x, (u, _)) in xs.iter().zip(&want) {
                assert_eq!(&factor.unabsorbed(x), u);
            }
            for t in [1, 2, 3] {
                let plain = factor.unabsorbed_each(&refs, Threads::new(t));
                let got = factor.unabsorbed_each_with_products(&refs, Threads::new(t));
                assert_eq!(got.len(), want.len());
                for (((g, gc), (w, wc)), u) in got.iter().zip(&want).zip(&plain) {
                    assert_eq!(g.shape(), w.shape());
                    assert_eq!(gc.shape(), wc.shape());
                    for (a, b) in g.iter().zip(w.iter()).chain(gc.iter().zip(wc.iter())) {
                        assert_eq!(a.to_bits(), b.to_bits(), "{p} columns, {t} threads");
                    }
                    assert_eq!(u, g);
                }
            }
        }
    }

    /// The blocked `aᵀb` is nalgebra's `tr_mul` to rounding (1e-13 relative to the product of the
    /// norms) on shapes above and below the blocked product's threshold, and exactly it below.
    #[test]
    fn the_blocked_transposed_product_is_the_plain_one() {
        let f = |i: usize, j: usize| ((i * 7 + j * 13) % 17) as f64 - 8.0 + 0.1 * (i as f64).sin();
        for (n, p, k) in [(300, 12, 9), (50, 6, 6), (40, 3, 8), (7, 7, 2)] {
            let a = DMatrix::from_fn(n, p, f);
            let b = DMatrix::from_fn(n, k, |i, j| f(i + 3, j + 1));
            let got = tr_mul(&a, &b);
            let want = a.tr_mul(&b);
            let scale = a.norm() * b.norm();
            assert!((&got - &want).amax() <= 1e-13 * scale, "{n}x{p}, {k}");
            if p <= 5 || k <= 5 {
                assert_eq!(got, want);
            }
        }
    }

    /// The Gram matrix by row blocks is `aᵀa` to rounding (1e-13 of ‖a‖²) on 9,000 × 12 (three
    /// blocks, the last short) and 100 × 7 (one), and the same bits on 1 and 3 threads, from a
    /// view of `a`'s rows block by block, and from the first columns of a longer buffer.
    #[test]
    fn the_blocked_gram_is_the_product() {
        let f = |i: usize, j: usize| ((i * 7 + j * 13) % 17) as f64 - 8.0 + 0.1 * (i as f64).sin();
        for (n, p) in [(9000, 12), (100, 7)] {
            let a = DMatrix::from_fn(n, p, f);
            let g = gram_on(&a, Threads::ONE);
            let want = a.transpose() * &a;
            assert!((&g - &want).amax() <= 1e-13 * a.norm_squared(), "{n} x {p}");
            assert_eq!(gram_on(&a, Threads::new(3)), g);
            // the blocks as rows of `a` (the product of a view of its rows), summed in order:
            // the same bits
            let mut by_rows = DMatrix::zeros(p, p);
            for r0 in (0..n).step_by(TALL_QR_ROWS) {
                let rows = TALL_QR_ROWS.min(n - r0);
                let at = DMatrixView::from_slice_with_strides(&a.as_slice()[r0..], p, rows, n, 1);
                let mut block = DMatrix::zeros(p, p);
                block.gemm(1.0, &at, &a.rows(r0, rows), 0.0);
                by_rows += block;
            }
            assert_eq!(g, by_rows, "{n} x {p}");
            // the first columns of a longer buffer (what follows them is not read)
            let mut longer = a.as_slice().to_vec();
            longer.extend(std::iter::repeat_n(f64::NAN, 3 * n));
            assert_eq!(gram_of_columns(&longer, n, p, Threads::new(2)), g);
        }
    }

    /// Projecting off the basis in place is the copy's projection bit for bit, whether the
    /// product is blocked (6 to 40 columns) or by columns (1 to 5 columns, or a basis of 4
    /// columns), on the columns of a larger matrix.
    #[test]
    fn unabsorbing_in_place_is_the_copy_bit_for_bit() {
        let f = |i: usize, j: usize| ((i * 7 + j * 13) % 17) as f64 - 8.0 + 0.1 * (i as f64).sin();
        for (n, p) in [(300, 12), (300, 4), (5000, 40)] {
            let factor = Factor::new(&DMatrix::from_fn(n, p, f), None);
            for w in [1, 3, 5, 6, 9, 40] {
                let x = DMatrix::from_fn(n, w + 2, |i, j| f(i + 5, j + 3) * 0.7);
                let want = factor.unabsorbed(&x.columns(1, w).into_owned());
                let mut got = x.clone();
                factor.unabsorb_in_place(got.columns_mut(1, w));
                assert_eq!(got.columns(1, w), want, "{n} x {p}, {w} columns");
                assert_eq!(got.column(0), x.column(0));
                assert_eq!(got.column(w + 1), x.column(w + 1));
            }
        }
    }

    #[test]
    fn exact_fit_and_rank_deficiency() {
        // y = 2·c0 − 3·c1 exactly; c2 = c0 + c1 makes the matrix rank 2.
        let a = DMatrix::from_row_slice(
            5,
            3,
            &[
                1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 2.0, 3.0, 1.0, 3.0, 4.0, 1.0, 4.0, 5.0,
            ],
        );
        let y = DVector::from_fn(5, |i, _| 2.0 - 3.0 * i as f64);
        let f = Factor::new(&a, None);
        assert_eq!(f.rank, 2);
        let x = f.solve(&y);
        let r = &y - &a * &x;
        assert!(r.norm() < 1e-10, "residual {}", r.norm());
        assert!(f.unabsorbed_vec(&y).norm() < 1e-10);
    }

    #[test]
    fn residual_stats_use_the_same_rms_and_max() {
        // ResidualStats (paper 001 eq. 17) and the diagnosis read the same figures, bit for bit.
        let measured = [0.003, -0.0125, 0.007, 0.0, -0.001];
        let fitted = [0.001, -0.01, 0.009, 0.0005, 0.0];
        let r: Vec<f64> = measured.iter().zip(&fitted).map(|(m, f)| m - f).collect();
        let st = crate::identify::ResidualStats::of(&measured, &fitted, 0.003);
        assert_eq!(st.rms, rms(&r));
        assert_eq!(st.max_abs, max_abs(&r));
        // Closed form: r = (2, −2.5, −2, −0.5, −1) µm, Σr² = 15.5e-6 mm².
        crate::assert_near!(st.rms, (15.5e-6f64 / 5.0).sqrt(), 1e-15);
        crate::assert_near!(st.max_abs, 0.0025, 1e-15);
    }

    /// `got` holds the values of `want` to 1e-12 relative, in any order, but its smallest, which
    /// is below 1e-12 (a rank one short).
    fn same_singular_values_but_one_zero(mut want: Vec<f64>, got: &DVector<f64>) {
        let mut got: Vec<f64> = got.iter().copied().collect();
        want.sort_by(f64::total_cmp);
        got.sort_by(f64::total_cmp);
        for (x, z) in want.iter().zip(&got).skip(1) {
            assert!((x / z - 1.0).abs() < 1e-12, "{x} vs {z}");
        }
        assert!(got[0] < 1e-12, "{}", got[0]);
    }

    /// The QR-first SVD of a tall design ([`QR_FIRST_ROWS`]) gives what the direct SVD gives: a
    /// 3,000 × 6 design whose last column is the sum of two others (rank 5) with an uneven
    /// scale: the same rank, singular values to 1e-12 relative, the same projection and
    /// least-squares solution to 1e-10 of their norms.
    #[test]
    fn qr_first_svd_equals_the_direct_one() {
        let mut rng = crate::numerics::random::Sampler::new(3);
        let n = 3000;
        let mut a = DMatrix::from_fn(n, 6, |_, _| rng.normal());
        for i in 0..n {
            a[(i, 5)] = a[(i, 0)] + 1e3 * a[(i, 2)];
            a[(i, 1)] *= 1e-4;
        }
        let y = DVector::from_fn(n, |i, _| a[(i, 1)] * 2e4 - a[(i, 3)] + rng.normal());
        let f = Factor::new(&a, None);
        let scaled = {
            let mut m = a.clone();
            for j in 0..6 {
                let nj = a.column(j).norm();
                m.column_mut(j).scale_mut(1.0 / nj);
            }
            m
        };
        let direct = scaled.clone().svd(true, true);
        let (_, sv, _) = svd_tall(scaled, Threads::ONE);
        assert_eq!(f.rank, 5);
        let d: Vec<f64> = direct.singular_values.iter().copied().collect();
        same_singular_values_but_one_zero(d, &sv);
        // the direct SVD's projection and solution, from its own basis
        let u = direct.u.unwrap();
        let keep: Vec<usize> = (0..6)
            .filter(|&k| direct.singular_values[k] > RANK_TOL)
            .collect();
        let basis = u.select_columns(&keep);
        let r_direct = &y - &basis * basis.tr_mul(&y);
        let r = f.unabsorbed_vec(&y);
        assert!(
            (&r - &r_direct).norm() < 1e-10 * y.norm(),
            "{}",
            (&r - &r_direct).norm()
        );
        let x = f.solve(&y);
        assert!((&y - &a * &x - &r).norm() < 1e-10 * y.norm());
    }

    /// The QR by row blocks ([`TALL_QR_ROWS`]) of a 120,000 × 9 design (29 blocks; rank 8, one
    /// column the sum of two others, one scaled by 1e-5): the rank 8, singular values those of
    /// the Gram matrix's eigenvalues to 1e-12 relative (and their squares summing to the 9 unit
    /// columns' to 1e-13, which nalgebra's direct SVD does not guarantee: 9.019 on a 20,000 × 9
    /// matrix of this kind, its largest value 0.5 % off, nalgebra issue 1172), an orthonormal
    /// `U` to 1e-13, the projection that of the 8 independent columns to 1e-10 of `‖y‖`; and
    /// the same bits on 1 and 3 threads (the blocks do not depend on them).
    #[test]
    fn the_blocked_tall_svd_is_exact_to_rounding() {
        let mut rng = crate::numerics::random::Sampler::new(5);
        // 1.08 million entries: above TALL_QR_MIN_ENTRIES, so in blocks
        let n = 120_000;
        assert!(n * 9 >= TALL_QR_MIN_ENTRIES && n / TALL_QR_ROWS == 29);
        let mut a = DMatrix::from_fn(n, 9, |_, _| rng.normal());
        for i in 0..n {
            a[(i, 8)] = a[(i, 0)] - 30.0 * a[(i, 4)];
            a[(i, 2)] *= 1e-5;
        }
        let y = DVector::from_fn(n, |i, _| a[(i, 2)] * 1e5 + a[(i, 7)] + rng.normal());
        let one = Factor::of_on(a.clone(), None, Threads::ONE);
        let three = Factor::of_on(a.clone(), None, Threads::new(3));
        assert_eq!(one.basis, three.basis);
        assert_eq!(one.cov, three.cov);
        assert_eq!(one.rank, 8);
        let mut unit = a.clone();
        for mut c in unit.column_iter_mut() {
            let norm = c.norm();
            c.scale_mut(1.0 / norm);
        }
        let (u, sv, _) = svd_tall(unit.clone(), Threads::new(2));
        let want: Vec<f64> = unit
            .tr_mul(&unit)
            .symmetric_eigenvalues()
            .iter()
            .map(|l| l.max(0.0).sqrt())
            .collect();
        same_singular_values_but_one_zero(want, &sv);
        let squares: f64 = sv.iter().map(|s| s * s).sum();
        assert!((squares - 9.0).abs() < 1e-13, "{squares}");
        let gram = u.tr_mul(&u) - DMatrix::identity(9, 9);
        assert!(gram.amax() < 1e-13, "{}", gram.amax());
        let q = a.columns(0, 8).into_owned().qr().q();
        let want_r = &y - &q * q.tr_mul(&y);
        let r = one.unabsorbed_vec(&y);
        assert!(
            (&r - &want_r).norm() < 1e-10 * y.norm(),
            "{}",
            (&r - &want_r).norm()
        );
    }
}
