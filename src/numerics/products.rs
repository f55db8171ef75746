//! The two matrix products of a dense scan's diagnosis, written for the browser's wasm:
//! `C = AᵀB` ([`tr_mul_into`]: the Gram matrices of the families' members, `Qᵀx` of a
//! projection, the whiteness test's `Bᵀ A_k B`) and `x − Qc` or `Qc` a column at a time
//! ([`sub_mul`], [`mul_into`]: a projection's second half, the tall SVD's `QW`). Matrices are
//! given as their columns, slices of one length `n` ([`columns`]).
//!
//! Natively these are `matrixmultiply`'s blocked products (nalgebra's `gemm`), whose kernels
//! for AVX2/AVX-512 are fast. In wasm that crate has only its portable kernel, and a tall
//! product with a few columns (a 20,000 × 54 Gram in blocks of 4,096 rows, `Qᵀx` of 8 columns)
//! spends most of its time in the masked edge tiles: 0.57 s of the page's 2.2 s on a
//! 20,000-point scan under Node (issue 31). Here each entry of `AᵀB` is a dot product of two
//! columns, the rows two at a time (a 128-bit lane pair), tiles of 4 × 2 entries so each column
//! read serves two or four entries; in wasm each function is compiled for `simd128`. Plain Rust beside
//! the lanes: the same code runs natively in the tests, against nalgebra's products to 1e-14
//! relative (a different order of the sums, so not the same bits).
//!
//! Units: whatever the matrices carry.

use nalgebra::DMatrix;

/// The columns of `m` as slices of its column-major storage (any number of rows, 0 too).
pub fn columns(m: &DMatrix<f64>) -> Vec<&[f64]> {
    let n = m.nrows();
    (0..m.ncols())
        .map(|j| &m.as_slice()[j * n..(j + 1) * n])
        .collect()
}

/// Rows of the blocks in which [`sub_mul`] and [`mul_into`] form `Qc` (the block's sums stay
/// in the first-level cache while each column of `Q` is added in).
const SUB_BLOCK_ROWS: usize = 512;

/// `out ← AᵀB` (`out` column-major `p × q` with column stride `ld`) for `A`'s columns `a` and
/// `B`'s columns `b` (all of one length `n`): entry `(i, j)` the dot product of `a[i]` and
/// `b[j]`. With `upper = Some(o)` (a symmetric product whose columns `b` are its columns
/// `o..o + q`) only the entries on and above its diagonal, `i ≤ o + j`, are computed, the others
/// left as they are ([`mirror_upper`] fills them in once every column is done).
pub fn tr_mul_into(a: &[&[f64]], b: &[&[f64]], out: &mut [f64], ld: usize, upper: Option<usize>) {
    #[cfg(target_arch = "wasm32")]
    return tr_mul_simd128(a, b, out, ld, upper);
    #[cfg(not(target_arch = "wasm32"))]
    tr_mul_in(a, b, out, ld, upper)
}

/// [`tr_mul_in`] compiled for wasm's 128-bit SIMD.
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn tr_mul_simd128(a: &[&[f64]], b: &[&[f64]], out: &mut [f64], ld: usize, upper: Option<usize>) {
    tr_mul_in(a, b, out, ld, upper)
}

#[inline(always)]
fn tr_mul_in(a: &[&[f64]], b: &[&[f64]], out: &mut [f64], ld: usize, upper: Option<usize>) {
    let n = a.first().or(b.first()).map_or(0, |c| c.len());
    if let Some(c) = a.iter().chain(b).find(|c| c.len() != n) {
        panic!("AᵀB: a column of {} rows among columns of {n}", c.len());
    }
    let (p, q) = (a.len(), b.len());
    assert!(
        q == 0 || (ld >= p && (q - 1) * ld + p <= out.len()),
        "AᵀB: a {p} × {q} result with stride {ld} in {} values",
        out.len()
    );
    let wanted = |i: usize, j: usize| upper.is_none_or(|o| i <= o + j);
    for j in (0..q).step_by(TILE_COLS) {
        let j2 = (j + TILE_COLS).min(q);
        for i in (0..p).step_by(TILE_ROWS) {
            // (the tile's last column the furthest down: none below the diagonal further on)
            if !wanted(i, j2 - 1) {
                break;
            }
            let i2 = (i + TILE_ROWS).min(p);
            let t = tile(a, b, i, i2, j, j2);
            for (jj, col) in (j..j2).enumerate() {
                for (ii, row) in (i..i2).enumerate() {
                    if wanted(row, col) {
                        out[row + col * ld] = t[jj][ii];
                    }
                }
            }
        }
    }
}

/// The entries below the diagonal of the square `p × p` matrix `out` (column stride `ld`) from
/// those above it: a symmetric product after [`tr_mul_into`] with `upper`.
pub fn mirror_upper(out: &mut [f64], p: usize, ld: usize) {
    for j in 0..p {
        for i in j + 1..p {
            out[i + j * ld] = out[j + i * ld];
        }
    }
}

/// Rows (columns of `A`) and columns (of `B`) of a tile of [`tr_mul_into`]: each of `B`'s
/// columns read serves four entries and each of `A`'s two, eight pairs of lanes of sums (with
/// the six loaded they fit the sixteen 128-bit registers of an x86-64, where V8 runs the page:
/// 4.5 ms against 2 × 2's 5.2 for a 20,000 × 60 by 12 product under Node, issue 31). Each
/// entry's sums are its own, whatever the tile (test `each_entry_is_its_own_dot_product`): the same bits.
const TILE_ROWS: usize = 4;
const TILE_COLS: usize = 2;

/// The entries `(i, j)`, `i ∈ i0..i1`, `j ∈ j0..j1` (at most [`TILE_ROWS`] × [`TILE_COLS`]) of
/// `AᵀB`: per entry two partial sums (even and odd rows), added at the end, then the last row
/// when `n` is odd.
#[inline(always)]
fn tile(
    a: &[&[f64]],
    b: &[&[f64]],
    i0: usize,
    i1: usize,
    j0: usize,
    j1: usize,
) -> [[f64; TILE_ROWS]; TILE_COLS] {
    // (a missing column of a tile reads its first one again; its sums are not written)
    let x: [&[f64]; TILE_ROWS] = std::array::from_fn(|t| a[if i0 + t < i1 { i0 + t } else { i0 }]);
    let y: [&[f64]; TILE_COLS] = std::array::from_fn(|t| b[if j0 + t < j1 { j0 + t } else { j0 }]);
    let n = x[0].len();
    let body = n - n % 2;
    let s = tile_sums(x.map(|c| &c[..body]), y.map(|c| &c[..body]));
    let mut t = s.map(|col| col.map(|e| e[0] + e[1]));
    for r in body..n {
        for (tj, yj) in t.iter_mut().zip(&y) {
            for (e, xi) in tj.iter_mut().zip(&x) {
                *e += xi[r] * yj[r];
            }
        }
    }
    t
}

/// The even- and odd-row partial sums of `x[i]·y[j]` for every pair of a tile (slices of one
/// even length), `[j][i]`.
#[cfg(not(target_arch = "wasm32"))]
#[inline(always)]
fn tile_sums(x: [&[f64]; TILE_ROWS], y: [&[f64]; TILE_COLS]) -> [[[f64; 2]; TILE_ROWS]; TILE_COLS] {
    let mut s = [[[0.0f64; 2]; TILE_ROWS]; TILE_COLS];
    for r in (0..x[0].len()).step_by(2) {
        for (sj, yj) in s.iter_mut().zip(&y) {
            for (e, xi) in sj.iter_mut().zip(&x) {
                for m in 0..2 {
                    e[m] += xi[r + m] * yj[r + m];
                }
            }
        }
    }
    s
}

/// [`tile_sums`] in wasm's 128-bit lanes (the compiler leaves the portable loop scalar): a
/// lane each for the even and odd rows, the same products and sums in the same order.
#[cfg(target_arch = "wasm32")]
#[inline(always)]
fn tile_sums(x: [&[f64]; TILE_ROWS], y: [&[f64]; TILE_COLS]) -> [[[f64; 2]; TILE_ROWS]; TILE_COLS] {
    use core::arch::wasm32::{
        f64x2_add, f64x2_extract_lane, f64x2_mul, f64x2_splat, v128, v128_load,
    };
    let n = x[0].len();
    assert!(
        n % 2 == 0 && x.iter().chain(&y).all(|c| c.len() == n),
        "tile sums of columns of {:?} rows",
        x.iter().chain(&y).map(|c| c.len()).collect::<Vec<_>>()
    );
    let load = |c: &[f64], r: usize| -> v128 {
        // SAFETY: r + 1 < n = c.len() (r even, n even); wasm's v128 loads need no alignment
        unsafe { v128_load(c.as_ptr().add(r) as *const v128) }
    };
    let mut s = [[f64x2_splat(0.0); TILE_ROWS]; TILE_COLS];
    for r in (0..n).step_by(2) {
        let c = y.map(|c| load(c, r));
        let a = x.map(|c| load(c, r));
        for (sj, cj) in s.iter_mut().zip(c) {
            for (e, ai) in sj.iter_mut().zip(a) {
                *e = f64x2_add(*e, f64x2_mul(ai, cj));
            }
        }
    }
    s.map(|col| col.map(|v| [f64x2_extract_lane::<0>(v), f64x2_extract_lane::<1>(v)]))
}

/// `x ← x − Qc` for one column `x` (`n` rows), `Q`'s columns `q` (each `n` rows) and `c` (as
/// many entries as `q`): `Qc` formed a block of rows at a time and subtracted once.
pub fn sub_mul(x: &mut [f64], q: &[&[f64]], c: &[f64]) {
    #[cfg(target_arch = "wasm32")]
    return combine_simd128(x, q, c, true);
    #[cfg(not(target_arch = "wasm32"))]
    combine(x, q, c, true)
}

/// `x ← Qc` (as [`sub_mul`], the product written instead of subtracted).
pub fn mul_into(x: &mut [f64], q: &[&[f64]], c: &[f64]) {
    #[cfg(target_arch = "wasm32")]
    return combine_simd128(x, q, c, false);
    #[cfg(not(target_arch = "wasm32"))]
    combine(x, q, c, false)
}

/// [`combine`] compiled for wasm's 128-bit SIMD.
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn combine_simd128(x: &mut [f64], q: &[&[f64]], c: &[f64], subtract: bool) {
    combine(x, q, c, subtract)
}

/// `x ← x − Qc` when `subtract`, else `x ← Qc`.
#[inline(always)]
fn combine(x: &mut [f64], q: &[&[f64]], c: &[f64], subtract: bool) {
    let n = x.len();
    assert_eq!(
        q.len(),
        c.len(),
        "Qc: {} columns against {} entries",
        q.len(),
        c.len()
    );
    if let Some(col) = q.iter().find(|col| col.len() != n) {
        panic!("Qc: a column of {} rows against {n}", col.len());
    }
    let mut y = [0.0; SUB_BLOCK_ROWS];
    for start in (0..n).step_by(SUB_BLOCK_ROWS) {
        let end = (start + SUB_BLOCK_ROWS).min(n);
        let y = &mut y[..end - start];
        y.fill(0.0);
        add_products(y, 0..q.len(), |k| &q[k][start..end], |k| c[k]);
        let x = &mut x[start..end];
        if subtract {
            for (o, yi) in x.iter_mut().zip(y.iter()) {
                *o -= *yi;
            }
        } else {
            x.copy_from_slice(y);
        }
    }
}

/// `y ← y + Σ col(k)·coef(k)` over the columns `ks` (each `col(k)` as long as `y`), each row's
/// sum `((y + q_k c_k) + q_{k+1} c_{k+1}) + …` in the order of `ks`, four columns a pass over `y`
/// (its values loaded and stored once for four products, not for each: 0.75 ms against 1.2 for
/// 20,000 rows and 60 columns under Node, issue 31): the same bits as one column a pass.
/// [`combine`]'s `Qc` and the few-column projection's (`crate::identify::solve`).
#[inline(always)]
pub(crate) fn add_products<'q>(
    y: &mut [f64],
    ks: std::ops::Range<usize>,
    col: impl Fn(usize) -> &'q [f64],
    coef: impl Fn(usize) -> f64,
) {
    let mut k = ks.start;
    while k + 4 <= ks.end {
        let cs = [coef(k), coef(k + 1), coef(k + 2), coef(k + 3)];
        let (q0, q1, q2, q3) = (col(k), col(k + 1), col(k + 2), col(k + 3));
        for ((((yi, a0), a1), a2), a3) in y.iter_mut().zip(q0).zip(q1).zip(q2).zip(q3) {
            *yi = (((*yi + a0 * cs[0]) + a1 * cs[1]) + a2 * cs[2]) + a3 * cs[3];
        }
        k += 4;
    }
    for k in k..ks.end {
        let ck = coef(k);
        for (yi, a) in y.iter_mut().zip(col(k)) {
            *yi += a * ck;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn filled(n: usize, m: usize, seed: u64) -> DMatrix<f64> {
        let mut s = seed;
        DMatrix::from_fn(n, m, |_, _| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
    }

    /// `AᵀB` against nalgebra's `tr_mul` for odd and even shapes (rows, both column counts),
    /// with a result stride larger than its rows: equal to 1e-14 of the sums of |products|
    /// (the sums taken in another order).
    #[test]
    fn tr_mul_is_nalgebras() {
        for (n, p, q) in [
            (0, 3, 2),
            (1, 1, 1),
            (7, 3, 5),
            (8, 4, 4),
            (513, 9, 6),
            (1000, 2, 7),
        ] {
            let a = filled(n, p, 1);
            let b = filled(n, q, 2);
            let want = a.tr_mul(&b);
            let scale = a.abs().tr_mul(&b.abs());
            let ld = p + 3;
            let mut out = vec![f64::NAN; ld * q.max(1)];
            tr_mul_into(&columns(&a), &columns(&b), &mut out, ld, None);
            for j in 0..q {
                for i in 0..p {
                    let d = (out[i + j * ld] - want[(i, j)]).abs();
                    assert!(
                        d <= 1e-14 * scale[(i, j)].max(1.0),
                        "{n}×{p}×{q} ({i}, {j}): {d:e}"
                    );
                }
            }
        }
    }

    /// A symmetric product (the Gram matrix `AᵀA`) from its upper triangle, its columns in two
    /// blocks, mirrored: symmetric, and the general product's numbers (each entry's sums in the
    /// same order) above the diagonal.
    #[test]
    fn the_gram_is_symmetric_and_the_general_product() {
        for (n, p) in [(5, 1), (9, 5), (64, 6), (301, 11)] {
            let a = filled(n, p, 3);
            let mut full = vec![0.0; p * p];
            let mut sym = vec![f64::NAN; p * p];
            tr_mul_into(&columns(&a), &columns(&a), &mut full, p, None);
            // the columns in two blocks, as the whiteness test's products come
            let all = columns(&a);
            let (left, right) = all.split_at(p / 2);
            tr_mul_into(&all, left, &mut sym, p, Some(0));
            tr_mul_into(&all, right, &mut sym[p / 2 * p..], p, Some(p / 2));
            mirror_upper(&mut sym, p, p);
            for j in 0..p {
                for i in 0..p {
                    assert_eq!(sym[i + j * p], sym[j + i * p], "{n}×{p} ({i}, {j})");
                    if i <= j {
                        assert_eq!(sym[i + j * p], full[i + j * p], "{n}×{p} ({i}, {j})");
                    }
                }
            }
        }
    }

    /// Every entry of `AᵀB` is its own two-lane dot product (even rows, odd rows, their sum, then
    /// the last row when `n` is odd), whatever its place in a tile (edges, a symmetric product's
    /// diagonal tiles): bit for bit, so the tile's shape cannot change a number.
    #[test]
    fn each_entry_is_its_own_dot_product() {
        let dot = |x: &[f64], y: &[f64]| {
            let body = x.len() - x.len() % 2;
            let mut s = [0.0f64; 2];
            for r in (0..body).step_by(2) {
                for m in 0..2 {
                    s[m] += x[r + m] * y[r + m];
                }
            }
            let mut t = s[0] + s[1];
            for r in body..x.len() {
                t += x[r] * y[r];
            }
            t
        };
        for (n, p, q) in [(1, 1, 1), (7, 3, 5), (8, 4, 4), (513, 9, 6), (64, 13, 13)] {
            let a = filled(n, p, 7);
            let b = filled(n, q, 8);
            let (ac, bc) = (columns(&a), columns(&b));
            let mut out = vec![f64::NAN; p * q];
            tr_mul_into(&ac, &bc, &mut out, p, None);
            for j in 0..q {
                for i in 0..p {
                    let want = dot(ac[i], bc[j]);
                    assert_eq!(
                        out[i + j * p].to_bits(),
                        want.to_bits(),
                        "{n}×{p}×{q} ({i}, {j})"
                    );
                }
            }
            let mut sym = vec![f64::NAN; p * p];
            tr_mul_into(&ac, &ac, &mut sym, p, Some(0));
            for j in 0..p {
                for i in 0..=j {
                    let want = dot(ac[i], ac[j]);
                    assert_eq!(
                        sym[i + j * p].to_bits(),
                        want.to_bits(),
                        "{n}×{p} sym ({i}, {j})"
                    );
                }
            }
        }
    }

    /// `Qc` a row at a time is `((0 + q₀c₀) + q₁c₁) + …` in the columns' order, whatever the
    /// columns taken together in a pass: bit for bit against that sum, for column counts on
    /// both sides of a multiple of four.
    #[test]
    fn each_row_of_qc_is_its_own_sum() {
        for (n, r) in [(3, 1), (600, 4), (515, 7), (9, 9)] {
            let q = filled(n, r, 9);
            let c = filled(r, 1, 10);
            let mut got = vec![f64::NAN; n];
            mul_into(&mut got, &columns(&q), c.as_slice());
            for i in 0..n {
                let mut want = 0.0;
                for k in 0..r {
                    want += q[(i, k)] * c[k];
                }
                assert_eq!(got[i].to_bits(), want.to_bits(), "{n}×{r} ({i})");
            }
        }
    }

    /// `x − Qc` and `Qc` against nalgebra's, across a block boundary of [`SUB_BLOCK_ROWS`]: to 1e-14 of
    /// the sums of |terms|.
    #[test]
    fn sub_mul_is_nalgebras() {
        for (n, r) in [(1, 1), (10, 3), (1100, 8), (513, 1), (7, 0)] {
            let q = filled(n, r, 4);
            let c = filled(r, 1, 5);
            let x = filled(n, 1, 6);
            let want = &x - &q * &c;
            let scale = x.abs() + q.abs() * c.abs();
            let mut got = x.as_slice().to_vec();
            sub_mul(&mut got, &columns(&q), c.as_slice());
            let mut product = vec![f64::NAN; n];
            mul_into(&mut product, &columns(&q), c.as_slice());
            let qc = &q * &c;
            for i in 0..n {
                let d = (got[i] - want[(i, 0)]).abs();
                assert!(d <= 1e-14 * scale[(i, 0)].max(1.0), "{n}×{r} ({i}): {d:e}");
                let d = (product[i] - qc[(i, 0)]).abs();
                assert!(
                    d <= 1e-14 * scale[(i, 0)].max(1.0),
                    "Qc {n}×{r} ({i}): {d:e}"
                );
            }
        }
    }
}
