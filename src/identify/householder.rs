//! The Householder QR of a tall matrix (Golub & Van Loan, *Matrix Computations*, 4th ed., §5.1.2
//! and Algorithm 5.2.1): `A = H₀H₁⋯H_{p−1}·[R; 0]`, each `H_k = I − 2v_kv_kᵀ` with a unit axis
//! `v_k` zero above row `k`, stored below the diagonal as nalgebra 0.34's `QR` stores it, and by
//! its operations bit for bit: the axis from the column and its norm (`reflection_axis_mut`), a
//! column reflected as `y ← f·v + s·y` with `f = −2s·(v·y)` and `s` the sign of the diagonal
//! (`Reflection::reflect_with_sign`), every dot product nalgebra's (eight partial sums over
//! the rows ≡ m mod 8 of the first 8⌊n/8⌋ rows, added in pairs `(0, 4), (1, 5), (2, 6), (3, 7)`
//! to 0, then the rows left one by one). So the same `R`, `Q` and `Qᵀy` to the last bit
//! (tests), in loops the compiler vectorises: nalgebra's reflection reads its columns through
//! run-time strides and updates them one entry at a time, and each of its dot products waits on
//! its own eight sums; here two columns are reflected together (their sums interleaved) and
//! the updates run four entries an instruction where the processor has AVX2 (chosen at run
//! time, without fused multiply-adds: the same roundings). Issue 31: the QRs and `Q`s of a
//! 20,000-point scan's tall designs had been 8 % of its CPU.

use nalgebra::DMatrix;

/// A Householder QR: the axes below the diagonal and `R` above it (`qr`), the diagonal of `R`
/// with its sign (`diag`: nalgebra's `QR` fields).
#[derive(Debug, Clone)]
pub struct HouseholderQr {
    qr: DMatrix<f64>,
    diag: Vec<f64>,
    /// Whether column `k` was reflected (a zero column is not; its columns to the right are
    /// left as they are at that step).
    reflected: Vec<bool>,
}

/// Columns `S` added to a factorised `A` ([`HouseholderQr::added`]): the columns `p..` of the QR
/// of `[A | S]` (`p` the columns of `A`), each reflected by `A`'s reflections, then by their own.
#[derive(Debug, Clone)]
pub struct AddedQr {
    qr: DMatrix<f64>,
    diag: Vec<f64>,
}

impl HouseholderQr {
    /// The QR of `a` (nalgebra's `a.qr()`, the same bits).
    pub fn new(a: DMatrix<f64>) -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the processor has AVX2, checked just above
                return unsafe { new_avx2(a) };
            }
        }
        #[cfg(target_arch = "wasm32")]
        return new_simd128(a);
        #[cfg(not(target_arch = "wasm32"))]
        new_in(a)
    }

    /// `R` (`min(n, p) × p`, its diagonal `|diag|`: nalgebra's `QR::r`).
    pub fn r(&self) -> DMatrix<f64> {
        let (n, p) = self.qr.shape();
        let dim = n.min(p);
        let mut r = DMatrix::zeros(dim, p);
        for c in 0..p {
            for row in 0..dim.min(c + 1) {
                r[(row, c)] = self.qr[(row, c)];
            }
        }
        for (k, d) in self.diag.iter().enumerate() {
            r[(k, k)] = d.abs();
        }
        r
    }

    /// The thin `Q` (`n × min(n, p)`: nalgebra's `QR::q`, each reflection applied to the
    /// identity's columns it changes, the last first).
    pub fn q(&self) -> DMatrix<f64> {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the processor has AVX2, checked just above
                return unsafe { q_avx2(self) };
            }
        }
        #[cfg(target_arch = "wasm32")]
        return q_simd128(self);
        #[cfg(not(target_arch = "wasm32"))]
        q_in(self)
    }

    /// The QR of `[A | s]` from that of `A` (`self`), the same bits as [`HouseholderQr::new`]
    /// of the whole: a column's reflections depend on its own entries and the axes before it
    /// only, and `A`'s axes on `A` only. `s`'s columns take `A`'s reflections, then the QR of
    /// their rows below `A`'s goes on as the whole one's would: the columns of `A` are not
    /// factorised again for each `s` (a model's alternatives, issue 31).
    pub fn added(&self, s: DMatrix<f64>) -> AddedQr {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the processor has AVX2, checked just above
                return unsafe { added_avx2(self, s) };
            }
        }
        #[cfg(target_arch = "wasm32")]
        return added_simd128(self, s);
        #[cfg(not(target_arch = "wasm32"))]
        added_qr(self, s)
    }

    /// `R` of `[A | S]` (that of [`HouseholderQr::new`] of the whole).
    pub fn r_with(&self, added: &AddedQr) -> DMatrix<f64> {
        let (n, p) = self.qr.shape();
        let q = added.qr.ncols();
        let dim = n.min(p + q);
        let mut r = DMatrix::zeros(dim, p + q);
        r.view_mut((0, 0), (n.min(p), p)).copy_from(&self.r());
        for c in 0..q {
            for row in 0..dim.min(p + c + 1) {
                r[(row, p + c)] = added.qr[(row, c)];
            }
        }
        for (k, d) in added.diag.iter().enumerate() {
            r[(p + k, p + k)] = d.abs();
        }
        r
    }

    /// `y ← Qᵀy` of `[A | S]` for a `y` to which `A`'s `Qᵀ` is applied already
    /// ([`HouseholderQr::q_tr_mul`]): `S`'s own reflections.
    pub fn added_q_tr_mul(&self, added: &AddedQr, y: &mut [f64]) {
        let n = self.qr.nrows();
        let p = self.qr.ncols();
        assert_eq!(y.len(), n, "Qᵀy: {} entries for {n} rows", y.len());
        let qs = added.qr.as_slice();
        for (k, d) in added.diag.iter().enumerate() {
            let i = p + k;
            reflect_one(&qs[k * n + i..(k + 1) * n], &mut y[i..], d.signum());
        }
    }

    /// `y ← Qᵀy` for an `n`-vector `y`, `Q` the whole `n × n` product of the reflections (the
    /// first `min(n, p)` entries are the thin `Q`'s `Qᵀy`; the others, the coordinates of `y`
    /// outside `A`'s column space: nalgebra's `QR::q_tr_mul`).
    pub fn q_tr_mul(&self, y: &mut [f64]) {
        let n = self.qr.nrows();
        assert_eq!(y.len(), n, "Qᵀy: {} entries for {n} rows", y.len());
        let qs = self.qr.as_slice();
        for (i, d) in self.diag.iter().enumerate() {
            let axis = &qs[i * n + i..(i + 1) * n];
            reflect_one(axis, &mut y[i..], d.signum());
        }
    }
}

/// [`new_in`] compiled for AVX2 (without FMA: the same roundings).
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn new_avx2(a: DMatrix<f64>) -> HouseholderQr {
    new_in(a)
}

/// [`q_in`] compiled for AVX2.
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn q_avx2(f: &HouseholderQr) -> DMatrix<f64> {
    q_in(f)
}

/// [`HouseholderQr::added`] compiled for AVX2.
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn added_avx2(base: &HouseholderQr, s: DMatrix<f64>) -> AddedQr {
    added_qr(base, s)
}

/// [`new_in`] compiled for wasm's 128-bit SIMD (two rows an instruction; wasm has no fused
/// multiply-add in it: the same roundings, the same bits as the scalar code).
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn new_simd128(a: DMatrix<f64>) -> HouseholderQr {
    new_in(a)
}

/// [`q_in`] compiled for wasm's 128-bit SIMD.
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn q_simd128(f: &HouseholderQr) -> DMatrix<f64> {
    q_in(f)
}

/// [`HouseholderQr::added`] compiled for wasm's 128-bit SIMD.
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn added_simd128(base: &HouseholderQr, s: DMatrix<f64>) -> AddedQr {
    added_qr(base, s)
}

/// [`HouseholderQr::added`]: `s` reflected by `base`'s reflections, then by its own.
#[inline(always)]
fn added_qr(base: &HouseholderQr, mut s: DMatrix<f64>) -> AddedQr {
    added_in(base, &mut s);
    let (diag, _) = own_reflections(base.qr.ncols(), &mut s);
    AddedQr { qr: s, diag }
}

/// The columns of `s` reflected by `base`'s reflections, in their order (those it made).
#[inline(always)]
fn added_in(base: &HouseholderQr, s: &mut DMatrix<f64>) {
    let n = base.qr.nrows();
    assert_eq!(s.nrows(), n, "columns of {} rows added to {n}", s.nrows());
    let qs = base.qr.as_slice();
    let out = s.as_mut_slice();
    for (i, (&done, d)) in base.reflected.iter().zip(&base.diag).enumerate() {
        if done {
            reflect_columns(&qs[i * n + i..(i + 1) * n], out, n, i, d.signum());
        }
    }
}

/// The QR of `s`'s rows from `offset` on, as the whole matrix's goes on from its column
/// `offset`: column `k`'s axis on rows `offset + k..`, the columns right of it reflected; the
/// diagonal entries and whether each column was reflected.
#[inline(always)]
fn own_reflections(offset: usize, s: &mut DMatrix<f64>) -> (Vec<f64>, Vec<bool>) {
    let (n, q) = s.shape();
    let mut diag = Vec::with_capacity(q);
    let mut done = Vec::with_capacity(q);
    let out = s.as_mut_slice();
    for k in 0..q {
        let i = offset + k;
        if i >= n {
            break;
        }
        let (left, right) = out.split_at_mut((k + 1) * n);
        let axis = &mut left[k * n + i..];
        let (norm, reflected) = reflection_axis(axis);
        if reflected {
            reflect_columns(axis, right, n, i, norm.signum());
        }
        diag.push(norm);
        done.push(reflected);
    }
    (diag, done)
}

/// nalgebra's `QR::new`: column `i`'s axis (`clear_column_unchecked`), then the columns right of
/// it reflected on rows `i..`.
#[inline(always)]
fn new_in(mut a: DMatrix<f64>) -> HouseholderQr {
    let (diag, reflected) = own_reflections(0, &mut a);
    HouseholderQr {
        qr: a,
        diag,
        reflected,
    }
}

/// nalgebra's `QR::q`: the identity's columns `i..` reflected on rows `i..` by reflection `i`,
/// from the last reflection to the first (including one whose axis nalgebra left unnormalised:
/// a zero column).
#[inline(always)]
fn q_in(f: &HouseholderQr) -> DMatrix<f64> {
    let n = f.qr.nrows();
    let dim = f.diag.len();
    let mut q = DMatrix::identity(n, dim);
    let qs = f.qr.as_slice();
    let out = q.as_mut_slice();
    for i in (0..dim).rev() {
        let axis = &qs[i * n + i..(i + 1) * n];
        reflect_columns(axis, &mut out[i * n..], n, i, f.diag[i].signum());
    }
    q
}

/// nalgebra's `reflection_axis_mut` on `column` (rows `i..` of column `i`): the unit axis of the
/// reflection taking it to `(∓|column|, 0, …)`, in place; the diagonal entry it leaves and
/// whether there was a reflection (a zero column has none).
#[inline(always)]
fn reflection_axis(column: &mut [f64]) -> (f64, bool) {
    let sq = 0.0 + dot(column, column);
    let norm = sq.sqrt();
    // simba's `to_exp` of a real: (|x|, ±1), +1 for x ≥ 0 (and for −0)
    let x0 = column[0];
    let (modulus, sign) = if x0 >= 0.0 { (x0, 1.0) } else { (-x0, -1.0) };
    let signed_norm = sign * norm;
    let factor = (sq + modulus * norm) * 2.0;
    column[0] += signed_norm;
    if factor != 0.0 {
        let root = factor.sqrt();
        for e in column.iter_mut() {
            *e /= root;
        }
        // normalised again (nalgebra's `normalize_mut`)
        let again = (0.0 + dot(column, column)).sqrt();
        for e in column.iter_mut() {
            *e /= again;
        }
        (-signed_norm, true)
    } else {
        (signed_norm, false)
    }
}

/// The columns held in `cols` (each `n` long, column-major) reflected on their rows `row..` by
/// the unit `axis` (`n − row` long) with sign `sign`, two columns at a time.
#[inline(always)]
fn reflect_columns(axis: &[f64], cols: &mut [f64], n: usize, row: usize, sign: f64) {
    let mut pairs = cols.chunks_exact_mut(2 * n);
    for pair in &mut pairs {
        let (c0, c1) = pair.split_at_mut(n);
        reflect_two(axis, &mut c0[row..], &mut c1[row..], sign);
    }
    let rest = pairs.into_remainder();
    if rest.len() == n {
        reflect_one(axis, &mut rest[row..], sign);
    }
}

/// nalgebra's `reflect_with_sign` of one column: `y ← f·v + s·y`, `f = (v·y − 0)·(−2s)`.
#[inline(always)]
fn reflect_one(axis: &[f64], y: &mut [f64], sign: f64) {
    let m_two = sign * -2.0;
    let factor = (dot(axis, y) - 0.0) * m_two;
    update(axis, y, factor, sign);
}

/// [`reflect_one`] of two columns, their dot products' sums interleaved (the same sums each).
#[inline(always)]
fn reflect_two(axis: &[f64], y0: &mut [f64], y1: &mut [f64], sign: f64) {
    let m_two = sign * -2.0;
    let (d0, d1) = dot_two(axis, y0, y1);
    update(axis, y0, (d0 - 0.0) * m_two, sign);
    update(axis, y1, (d1 - 0.0) * m_two, sign);
}

/// `y ← f·v + s·y` (nalgebra's `axpy` with `c = 1`: `f·v·1 + s·y`, the `·1` exact).
#[inline(always)]
fn update(axis: &[f64], y: &mut [f64], factor: f64, sign: f64) {
    for (e, v) in y.iter_mut().zip(axis) {
        *e = factor * v + sign * *e;
    }
}

/// nalgebra's dot product of two vectors (module doc).
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let body = n - n % 8;
    let mut acc = [0.0f64; 8];
    for (x, y) in a[..body].chunks_exact(8).zip(b[..body].chunks_exact(8)) {
        for m in 0..8 {
            acc[m] += x[m] * y[m];
        }
    }
    let mut res = finish(&acc);
    for i in body..n {
        res += a[i] * b[i];
    }
    res
}

/// [`dot`] of `a` with `b0` and with `b1` (all the same length), side by side: each product's
/// eight sums held as two runs of four (lanes 0-3 and 4-7), one vector register each.
#[inline(always)]
fn dot_two(a: &[f64], b0: &[f64], b1: &[f64]) -> (f64, f64) {
    let n = a.len().min(b0.len()).min(b1.len());
    let body = n - n % 8;
    let (mut lo0, mut hi0, mut lo1, mut hi1) = ([0.0f64; 4], [0.0f64; 4], [0.0f64; 4], [0.0f64; 4]);
    for ((x, y0), y1) in a[..body]
        .chunks_exact(8)
        .zip(b0[..body].chunks_exact(8))
        .zip(b1[..body].chunks_exact(8))
    {
        for m in 0..4 {
            lo0[m] += x[m] * y0[m];
            hi0[m] += x[m + 4] * y0[m + 4];
            lo1[m] += x[m] * y1[m];
            hi1[m] += x[m + 4] * y1[m + 4];
        }
    }
    let join =
        |lo: [f64; 4], hi: [f64; 4]| [lo[0], lo[1], lo[2], lo[3], hi[0], hi[1], hi[2], hi[3]];
    let (mut r0, mut r1) = (finish(&join(lo0, hi0)), finish(&join(lo1, hi1)));
    for i in body..n {
        r0 += a[i] * b0[i];
        r1 += a[i] * b1[i];
    }
    (r0, r1)
}

/// nalgebra's sum of a dot product's eight partial sums (also [`super::solve`]'s fused
/// few-column product's).
#[inline(always)]
pub(super) fn finish(acc: &[f64; 8]) -> f64 {
    let mut res = 0.0;
    res += acc[0] + acc[4];
    res += acc[1] + acc[5];
    res += acc[2] + acc[6];
    res += acc[3] + acc[7];
    res
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;
    use crate::numerics::random::Sampler;

    fn bits(m: &DMatrix<f64>) -> Vec<u64> {
        m.iter().map(|x| x.to_bits()).collect()
    }

    /// Shapes with rows ≡ 0 and ≢ 0 mod 8, odd and even column counts (the pairs and the column
    /// left alone), square, one column, wide, a zero column and a repeated one (a reflection
    /// nalgebra skips), and rows below the diagonal already zero.
    fn cases() -> Vec<DMatrix<f64>> {
        let mut rng = Sampler::new(31);
        let mut out = Vec::new();
        for &(n, p) in &[
            (2003, 9),
            (4096, 8),
            (517, 12),
            (64, 1),
            (13, 13),
            (5, 9),
            (1000, 2),
            (7, 3),
        ] {
            out.push(DMatrix::from_fn(n, p, |_, _| rng.normal()));
        }
        let mut zero_col = DMatrix::from_fn(301, 5, |_, _| rng.normal());
        zero_col.column_mut(2).fill(0.0);
        out.push(zero_col);
        let mut repeated = DMatrix::from_fn(250, 4, |_, _| rng.normal());
        let c = repeated.column(0).clone_owned();
        repeated.set_column(3, &c);
        out.push(repeated);
        let mut upper = DMatrix::from_fn(40, 6, |_, _| rng.normal());
        for c in 0..6 {
            for r in c + 1..40 {
                upper[(r, c)] = if c % 2 == 0 { 0.0 } else { -0.0 };
            }
        }
        out.push(upper);
        out
    }

    /// `R`, `Q` and `Qᵀy` against nalgebra's `QR`, bit for bit, on every case; the kernel this
    /// processor dispatches to (AVX2 on one that has it) and the portable one both.
    #[test]
    fn the_qr_is_nalgebras_bit_for_bit() {
        let mut rng = Sampler::new(7);
        for a in cases() {
            let theirs = a.clone().qr();
            let y: Vec<f64> = (0..a.nrows()).map(|_| rng.normal()).collect();
            let mut their_y = nalgebra::DVector::from_column_slice(&y);
            theirs.q_tr_mul(&mut their_y);
            for ours in [HouseholderQr::new(a.clone()), new_in(a.clone())] {
                let shape = a.shape();
                assert_eq!(bits(&ours.r()), bits(&theirs.r()), "R of {shape:?}");
                assert_eq!(bits(&ours.q()), bits(&theirs.q()), "Q of {shape:?}");
                assert_eq!(bits(&q_in(&ours)), bits(&theirs.q()), "Q of {shape:?}");
                let mut our_y = y.clone();
                ours.q_tr_mul(&mut our_y);
                let want: Vec<u64> = their_y.iter().map(|x| x.to_bits()).collect();
                let got: Vec<u64> = our_y.iter().map(|x| x.to_bits()).collect();
                assert_eq!(got, want, "Qᵀy of {shape:?}");
            }
        }
    }

    /// `[A | S]` from `A`'s QR: `R` and `Qᵀy` of the whole, bit for bit, for `S` of one and of
    /// several columns, with a zero column in `A` (a step without reflection).
    #[test]
    fn added_columns_are_the_whole_qr_bit_for_bit() {
        let mut rng = Sampler::new(11);
        for (n, p, q, zero) in [
            (2003, 8, 1, None),
            (517, 5, 4, Some(2)),
            (64, 3, 2, Some(0)),
        ] {
            let mut a = DMatrix::from_fn(n, p, |_, _| rng.normal());
            if let Some(z) = zero {
                a.column_mut(z).fill(0.0);
            }
            let s = DMatrix::from_fn(n, q, |_, _| rng.normal());
            let whole = HouseholderQr::new(crate::identify::solve::hstack(&a, &s));
            let base = HouseholderQr::new(a);
            let added = base.added(s.clone());
            assert_eq!(
                bits(&base.r_with(&added)),
                bits(&whole.r()),
                "R of {n}×{p}+{q}"
            );
            let y: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
            let mut want = y.clone();
            whole.q_tr_mul(&mut want);
            let mut got = y;
            base.q_tr_mul(&mut got);
            base.added_q_tr_mul(&added, &mut got);
            let bits_of = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits_of(&got), bits_of(&want), "Qᵀy of {n}×{p}+{q}");
            // the portable kernels too
            let mut s2 = s;
            added_in(&base, &mut s2);
            let (diag, _) = own_reflections(p, &mut s2);
            let portable = AddedQr { qr: s2, diag };
            assert_eq!(bits(&base.r_with(&portable)), bits(&whole.r()));
        }
    }

    /// A zero matrix: no reflection, `R = 0` and nalgebra's `Q` (its unnormalised axes applied).
    #[test]
    fn a_zero_matrix_is_nalgebras_too() {
        let a = DMatrix::<f64>::zeros(20, 3);
        let theirs = a.clone().qr();
        let ours = HouseholderQr::new(a);
        assert_eq!(bits(&ours.r()), bits(&theirs.r()));
        assert_eq!(bits(&ours.q()), bits(&theirs.q()));
    }
}
