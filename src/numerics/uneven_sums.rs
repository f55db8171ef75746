//! Sums of exponentials at uneven positions, `F(k) = Σ_j c_j e^{ikθ_j}` for `k = 0, 1, …, K`,
//! in `O(m log m)` instead of the `O(m K)` of the sums themselves: the nonuniform fast Fourier
//! transform (type 1) by fast Gaussian gridding, Greengard & Lee, "Accelerating the nonuniform
//! fast Fourier transform", SIAM Review 46(3), 2004:
//!
//! - each strength is spread onto a regular grid of `M_r = R·M` points over `[0, 2π)` by the
//!   periodic heat kernel `g_τ(x) = Σ_l e^{−(x − 2πl)²/4τ}`, over the `2·M_sp` grid points nearest
//!   its position (the kernel as three factors `E₁·E₂^l·E₃(l)`: one exponential a point);
//! - the grid's discrete Fourier transform is the Fourier coefficients of the spread sum to the
//!   kernel's tails;
//! - dividing by the kernel's coefficients `√(τ/π)·e^{−k²τ}` gives the sums, with
//!   `τ = π M_sp / (M² R (R − ½))`.
//!
//! Greengard and Lee give about 12 digits relative to `Σ|c_j|` at `R = 2` and `M_sp = 12`; here
//! `M_sp` = [`SPREAD`] and `M` at least twice the highest frequency asked (the frequencies asked
//! are oversampled further), 1e-12 of `Σ|c_j|` by this file's test. Two real strengths are summed
//! at once as the real and imaginary parts of one complex strength.

use std::f64::consts::PI;

/// The grid points a position's strength is spread over, each side (`M_sp`).
pub const SPREAD: usize = 14;

/// A complex number as `(re, im)`.
pub type Complex = (f64, f64);

/// `Σ_j a_j e^{ikθ_j}` for `k = 0..=ka` and `Σ_j b_j e^{ikθ_j}` for `k = 0..=kb` (`a`, `b`
/// real strengths at the positions `theta`, each in `[0, 2π)`), to ~1e-12 of `Σ|a_j|` and
/// `Σ|b_j|` (their test).
pub fn exp_sums(
    theta: &[f64],
    a: &[f64],
    b: &[f64],
    ka: usize,
    kb: usize,
) -> (Vec<Complex>, Vec<Complex>) {
    assert!(
        theta.len() == a.len() && theta.len() == b.len(),
        "exp_sums: {} positions, {} and {} strengths",
        theta.len(),
        a.len(),
        b.len()
    );
    let k_top = ka.max(kb);
    // modes −M/2..M/2 cover ±k_top; the grid R = 2 times finer, a power of two
    let grid = (4 * (k_top + 1)).max(4 * SPREAD).next_power_of_two();
    let modes = (grid / 2) as f64;
    let tau = PI * SPREAD as f64 / (modes * modes * 2.0 * 1.5);
    let h = 2.0 * PI / grid as f64;
    let mut f = vec![(0.0, 0.0); grid];
    // E₃(l) = e^{−(lh)²/4τ} for l = 0..=SPREAD
    let e3: Vec<f64> = (0..=SPREAD)
        .map(|l| (-(l as f64 * h).powi(2) / (4.0 * tau)).exp())
        .collect();
    for ((&x, &ca), &cb) in theta.iter().zip(a).zip(b) {
        let m0 = (x / h).floor();
        let d = x - m0 * h;
        let m0 = m0 as i64;
        // the kernel at grid point m0 + l: e^{−(lh − d)²/4τ} = E₁ · E₂^l · E₃(|l|)
        let e1 = (-d * d / (4.0 * tau)).exp();
        let e2 = (d * h / (2.0 * tau)).exp();
        let add = |f: &mut [Complex], l: i64, g: f64| {
            let i = (m0 + l).rem_euclid(grid as i64) as usize;
            f[i].0 += ca * g;
            f[i].1 += cb * g;
        };
        // l = 0, 1, …, SPREAD and l = −1, …, −(SPREAD − 1)
        let mut up = e1;
        for (l, &e) in e3.iter().enumerate() {
            add(&mut f, l as i64, up * e);
            up *= e2;
        }
        let mut down = e1 / e2;
        for (l, &e) in e3.iter().enumerate().take(SPREAD).skip(1) {
            add(&mut f, -(l as i64), down * e);
            down /= e2;
        }
    }
    fft(&mut f);
    // D(k) = Σ c e^{−ikθ} = √(π/τ) e^{k²τ} · FFT[k] / M_r for the complex c = a + ib; a and b
    // real: D_a(k) = (D(k) + conj D(−k))/2, D_b(k) = (D(k) − conj D(−k))/2i, and the sums
    // asked, with e^{+ikθ}, their conjugates
    let scale = (PI / tau).sqrt() / grid as f64;
    let at = |k: usize| -> (Complex, Complex) {
        let g = scale * (k as f64 * k as f64 * tau).exp();
        let p = f[k % grid];
        let q = f[(grid - k % grid) % grid];
        let (d, e) = ((p.0 * g, p.1 * g), (q.0 * g, q.1 * g));
        // D(k) = d, conj D(−k) = (e.0, −e.1)
        let da = (0.5 * (d.0 + e.0), 0.5 * (d.1 - e.1));
        let db = (0.5 * (d.1 + e.1), -0.5 * (d.0 - e.0));
        ((da.0, -da.1), (db.0, -db.1))
    };
    let both: Vec<(Complex, Complex)> = (0..=k_top).map(at).collect();
    let sa = both[..=ka].iter().map(|s| s.0).collect();
    let sb = both[..=kb].iter().map(|s| s.1).collect();
    (sa, sb)
}

/// The discrete Fourier transform `X_k = Σ_m x_m e^{−2πikm/N}` in place (`N` a power of two):
/// radix 2, decimation in time, the twiddles evaluated directly (not by recurrence).
fn fft(x: &mut [Complex]) {
    let n = x.len();
    assert!(n.is_power_of_two(), "fft: {n} points, not a power of two");
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            x.swap(i, j);
        }
    }
    let twiddles: Vec<Complex> = (0..n / 2)
        .map(|k| {
            let (s, c) = (-2.0 * PI * k as f64 / n as f64).sin_cos();
            (c, s)
        })
        .collect();
    let mut len = 2;
    while len <= n {
        let stride = n / len;
        for start in (0..n).step_by(len) {
            for k in 0..len / 2 {
                let w = twiddles[k * stride];
                let (u, v) = (x[start + k], x[start + k + len / 2]);
                let t = (v.0 * w.0 - v.1 * w.1, v.0 * w.1 + v.1 * w.0);
                x[start + k] = (u.0 + t.0, u.1 + t.1);
                x[start + k + len / 2] = (u.0 - t.0, u.1 - t.1);
            }
        }
        len <<= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The direct sums `Σ c e^{ikθ}`.
    fn direct(theta: &[f64], c: &[f64], k_max: usize) -> Vec<Complex> {
        (0..=k_max)
            .map(|k| {
                theta.iter().zip(c).fold((0.0, 0.0), |(re, im), (&t, &cj)| {
                    let (s, co) = (k as f64 * t).sin_cos();
                    (re + cj * co, im + cj * s)
                })
            })
            .collect()
    }

    /// The gridded sums equal the direct ones to 1e-12 of `Σ|c_j|` (Greengard and Lee's 12
    /// digits at `M_sp` = 12, here 14), on uneven positions (a jittered grid with a gap, and
    /// positions near 0 and 2π, where the kernel wraps), for 7, 300 and 1,000 points and the
    /// frequencies up to half and all of the points, strengths of both signs.
    #[test]
    fn gridded_sums_are_the_direct_sums() {
        let mut rng = crate::numerics::random::Sampler::new(5);
        for m in [7usize, 300, 1000] {
            let mut theta: Vec<f64> = (0..m)
                .map(|j| {
                    let u = (j as f64 + 0.4 * rng.uniform(-1.0, 1.0)) / m as f64;
                    // a gap in the middle third's first half
                    let u = if (0.33..0.5).contains(&u) { u * 0.9 } else { u };
                    (2.0 * PI * u).rem_euclid(2.0 * PI)
                })
                .collect();
            theta[0] = 1e-9;
            theta[m - 1] = 2.0 * PI - 1e-9;
            let a: Vec<f64> = (0..m).map(|_| rng.normal()).collect();
            let b: Vec<f64> = (0..m).map(|j| (j as f64 * 0.01).sin() + 0.5).collect();
            let (ka, kb) = (m / 2, m);
            let (sa, sb) = exp_sums(&theta, &a, &b, ka, kb);
            for (c, got, k) in [(&a, &sa, ka), (&b, &sb, kb)] {
                let want = direct(&theta, c, k);
                let l1: f64 = c.iter().map(|v| v.abs()).sum();
                assert_eq!(got.len(), k + 1);
                for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                    let err = (g.0 - w.0).hypot(g.1 - w.1);
                    assert!(
                        err <= 1e-12 * l1,
                        "m {m}, k {i}: {g:?} vs {w:?} ({err:e} of {l1})"
                    );
                }
            }
        }
    }

    /// The radix-2 transform is the direct DFT to 1e-13 of the input's 1-norm on 1, 2 and 64
    /// points.
    #[test]
    fn the_fft_is_the_dft() {
        for n in [1usize, 2, 64] {
            let x: Vec<Complex> = (0..n)
                .map(|j| ((j as f64 * 0.7).sin(), (j as f64 * 1.3).cos()))
                .collect();
            let mut got = x.clone();
            fft(&mut got);
            let l1: f64 = x.iter().map(|v| v.0.hypot(v.1)).sum();
            for (k, g) in got.iter().enumerate() {
                let w = x.iter().enumerate().fold((0.0, 0.0), |(re, im), (m, v)| {
                    let (s, c) = (-2.0 * PI * (k * m) as f64 / n as f64).sin_cos();
                    (re + v.0 * c - v.1 * s, im + v.0 * s + v.1 * c)
                });
                assert!(
                    (g.0 - w.0).hypot(g.1 - w.1) <= 1e-13 * l1,
                    "{n} points, k {k}"
                );
            }
        }
    }
}
