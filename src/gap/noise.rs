//! Noise versus structure in a residual, along each curve (points taken in increasing `u`).
//!
//! - Noise σ independent of smooth structure: the pooled von Neumann estimator
//!   `σ²_vN = Σ(r_{i+1} − r_i)² / (2 Σ(m − 1))` (a slowly varying trend barely changes
//!   successive differences), and a robust second-difference estimator
//!   `σ_d2 = 1.4826 · median|r_{i+1} − 2r_i + r_{i−1}| / √6` (var of a second difference of iid
//!   noise is 6σ²; the median ignores the few differences that straddle a step such as a backlash
//!   reversal, and second differences remove linear trends). Both are reported; the diagnosis
//!   uses the smooth-basis estimate of [`super::smooth_noise`] (which also removes whatever the
//!   baseline's own signatures explain) unless a CMM repeatability is given.
//! - Noise σ as the **nugget of the robust variogram** along each curve (geostatistics: the
//!   variogram of `r = structure + ε` is `γ(h) = σ² + γ_s(h)`, and a structure that is smooth at
//!   the sample spacing has `γ_s(h) ≈ b h²` near 0). With the robust semivariogram at index lags
//!   1 and 2 pooled over the curves (a trimmed mean of the squared differences, see
//!   [`robust_semivariogram`]: it ignores the few differences a local bump or a reversal step
//!   touches), the extrapolation to lag 0 through `a + b h²` is `σ²_nugget = (4 γ̂(1) − γ̂(2)) / 3`.
//!   Since `Δ_{2}r_i = Δ_1 r_i + Δ_1 r_{i+1}`, any structure has `γ_s(2) ≤ 4 γ_s(1)`, so in
//!   expectation the nugget is never below σ²: structure can only inflate it. A waviness
//!   `A sin(ωs)` sampled at spacing Δ (`γ_s(h) = (A²/2)(1 − cos ωhΔ)`) adds ≈ `A²(ωΔ)⁴/12` to it
//!   instead of the `A²(ωΔ)²/4` it adds to the von Neumann estimate: for λ = 6Δ exactly 1/6 of
//!   the wave's variance instead of 1/2. A non-positive extrapolation (sampling noise with few
//!   points) gives no estimate.
//! - Randomness: the Wald–Wolfowitz runs test of the signs along each curve (too few runs =
//!   structure), pooled over curves as a z-score; the lag-1 autocorrelation `ρ₁` per curve with
//!   `z = ρ₁ √m` (pooled: sums over curves).
//! - Whiteness: the Ljung–Box statistic `Q = m(m+2) Σ_{k=1}^{K} ρ_k²/(m − k)` per curve, summed
//!   over the curves (independent under the null) against χ² with `K × curves` degrees of freedom
//!   (K = [`LJUNG_BOX_LAGS`]); it does not depend on σ, so it tells structure from noise even when
//!   a stated CMM repeatability is wrong.
//! - Size: `χ² = RSS / σ²` against `n − rank` degrees of freedom.

use serde::Serialize;

use super::stats;

/// Largest σ (mm) an estimate may have before the report questions it: a CMM measuring a
/// flank-milled wall repeats within 1-2 µm (paper 000 §6: R0 = 3 µm over 3 repeats, σ ≈ 1.8 µm);
/// an estimate above 3 µm more likely holds a structure the estimators took for noise.
pub const PLAUSIBLE_CMM_SIGMA_MM: f64 = 0.003;

/// Lags of the Ljung–Box test (≈ 100 mm of tool path at the built-in 25 mm spacing).
pub const LJUNG_BOX_LAGS: usize = 4;

/// Fraction of the squared differences kept by the trimmed semivariogram.
pub const KEEP_FRACTION: f64 = 0.9;
/// `E[X | X ≤ q₀.₉]` for `X ~ χ²₁`: `P(χ²₃ ≤ 2.705543)/0.9 = 0.560714/0.9`.
pub const TRIMMED_CHI2_1: f64 = 0.623_015_5;

/// Noise estimates from a residual.
#[derive(Debug, Clone, Serialize)]
pub struct NoiseEstimate {
    /// Given CMM repeatability (mm), if any.
    pub given: Option<f64>,
    /// Pooled von Neumann successive-difference estimate (mm).
    pub von_neumann: f64,
    /// Robust second-difference estimate (mm).
    pub second_difference: f64,
    /// Residual σ of the baseline plus a smooth basis per curve ([`super::smooth_noise`]) (mm).
    pub smooth: Option<f64>,
    /// Its robust (median) version (mm).
    pub smooth_robust: Option<f64>,
    /// Robust second-difference estimate of that smooth-basis residual (mm): what is left of a
    /// waviness the smooth basis could not follow is damped by the differencing, a step or a bump
    /// is ignored by the median.
    pub smooth_second_difference: Option<f64>,
    /// Nugget of the robust variogram along the curves (mm); `None` with too few points or a
    /// negative extrapolation.
    pub variogram_nugget: Option<f64>,
    /// The σ the decisions use (mm): the given value, else the smallest of the smooth-basis
    /// estimates and the variogram nugget (each is consistent for white noise and inflated by a
    /// different kind of structure: waves shorter than the smooth basis follows, a few large
    /// points, short waves), else the second-difference estimate of the residual itself.
    pub used: f64,
}

/// Randomness tests of a residual along one curve (or pooled).
#[derive(Debug, Clone, Serialize)]
pub struct Randomness {
    /// Number of points.
    pub n: usize,
    /// Observed runs of equal sign.
    pub runs: usize,
    /// Expected runs for random signs.
    pub runs_expected: f64,
    /// z-score of the runs (negative: fewer runs than random, i.e. structure).
    pub runs_z: f64,
    /// Two-sided p-value of the runs test.
    pub runs_p: f64,
    /// Lag-1 autocorrelation.
    pub lag1: f64,
    /// Two-sided p-value of the lag-1 autocorrelation (`z = ρ₁ √m`).
    pub lag1_p: f64,
}

/// Sums needed for the runs test and lag-1 autocorrelation of one sequence.
#[derive(Debug, Clone, Copy, Default)]
struct RunSums {
    n: usize,
    runs: usize,
    expected: f64,
    var: f64,
    lag_num: f64,
    lag_den: f64,
}

fn run_sums(r: &[f64]) -> RunSums {
    let signs: Vec<bool> = r.iter().filter(|v| **v != 0.0).map(|v| *v > 0.0).collect();
    let m = signs.len();
    let np = signs.iter().filter(|s| **s).count() as f64;
    let nm = m as f64 - np;
    let runs = if m == 0 {
        0
    } else {
        1 + signs.windows(2).filter(|w| w[0] != w[1]).count()
    };
    let mf = m as f64;
    let (expected, var) = if m >= 2 {
        let e = 2.0 * np * nm / mf + 1.0;
        let v = 2.0 * np * nm * (2.0 * np * nm - mf) / (mf * mf * (mf - 1.0));
        (e, v.max(0.0))
    } else {
        (runs as f64, 0.0)
    };
    let lag_num: f64 = r.windows(2).map(|w| w[0] * w[1]).sum();
    let lag_den: f64 = r.iter().map(|v| v * v).sum();
    RunSums {
        n: r.len(),
        runs,
        expected,
        var,
        lag_num,
        lag_den,
    }
}

fn randomness_from(s: RunSums) -> Randomness {
    let runs_z = if s.var > 0.0 {
        (s.runs as f64 - s.expected) / s.var.sqrt()
    } else {
        0.0
    };
    let lag1 = if s.lag_den > 0.0 {
        s.lag_num / s.lag_den
    } else {
        0.0
    };
    Randomness {
        n: s.n,
        runs: s.runs,
        runs_expected: s.expected,
        runs_z,
        runs_p: stats::normal_two_sided(runs_z),
        lag1,
        lag1_p: stats::normal_two_sided(lag1 * (s.n as f64).sqrt()),
    }
}

/// Runs test and lag-1 autocorrelation of one sequence.
pub fn randomness(r: &[f64]) -> Randomness {
    randomness_from(run_sums(r))
}

/// The same tests pooled over several sequences (sums of runs, expectations and variances).
pub fn randomness_pooled(seqs: &[Vec<f64>]) -> Randomness {
    let mut t = RunSums::default();
    for s in seqs {
        let r = run_sums(s);
        t.n += r.n;
        t.runs += r.runs;
        t.expected += r.expected;
        t.var += r.var;
        t.lag_num += r.lag_num;
        t.lag_den += r.lag_den;
    }
    randomness_from(t)
}

/// Ljung–Box whiteness test pooled over sequences.
#[derive(Debug, Clone, Serialize)]
pub struct LjungBox {
    /// Lags per curve.
    pub lags: usize,
    /// `Σ_curves m(m+2) Σ_k ρ_k²/(m − k)`.
    pub q: f64,
    /// Degrees of freedom (lags × curves long enough).
    pub dof: usize,
    /// `P(χ²_dof > Q)`: small = the residual is not white noise.
    pub p_value: f64,
}

/// Ljung–Box test of the sequences (each centred on its mean), `lags` lags per sequence; sequences
/// shorter than `lags + 3` are skipped.
pub fn ljung_box(seqs: &[Vec<f64>], lags: usize) -> LjungBox {
    let (mut q, mut dof) = (0.0, 0usize);
    for s in seqs {
        let m = s.len();
        if lags == 0 || m < lags + 3 {
            continue;
        }
        let mean = s.iter().sum::<f64>() / m as f64;
        let c: Vec<f64> = s.iter().map(|v| v - mean).collect();
        let c0: f64 = c.iter().map(|v| v * v).sum();
        if c0 <= 0.0 {
            continue;
        }
        let mf = m as f64;
        for k in 1..=lags {
            let rho: f64 = c.windows(k + 1).map(|w| w[0] * w[k]).sum::<f64>() / c0;
            q += mf * (mf + 2.0) * rho * rho / (mf - k as f64);
        }
        dof += lags;
    }
    LjungBox {
        lags,
        q,
        dof,
        p_value: if dof > 0 {
            stats::chi2_sf(q, dof as f64)
        } else {
            1.0
        },
    }
}

/// Robust semivariogram at index lag `h` pooled over sequences: the mean of the smallest
/// [`KEEP_FRACTION`] of the squared differences `(r_{i+h} − r_i)²`, divided by `2 c` with
/// `c = E[X | X ≤ q₀.₉]` for `X ~ χ²₁` (= P(χ²₃ ≤ q₀.₉)/0.9 = [`TRIMMED_CHI2_1`]), so that it
/// is `σ²` for white noise. Trimming the largest tenth ignores the few differences a local bump
/// or a reversal step touches, at a much smaller loss of efficiency than a median. `None`
/// without any pair.
pub fn robust_semivariogram(seqs: &[Vec<f64>], h: usize) -> Option<f64> {
    let mut d: Vec<f64> = seqs
        .iter()
        .filter(|s| s.len() > h)
        .flat_map(|s| s.windows(h + 1).map(|w| (w[h] - w[0]).powi(2)))
        .collect();
    if d.is_empty() {
        return None;
    }
    d.sort_by(f64::total_cmp);
    let keep = ((KEEP_FRACTION * d.len() as f64).round() as usize).clamp(1, d.len());
    let mean = d[..keep].iter().sum::<f64>() / keep as f64;
    Some(mean / (2.0 * TRIMMED_CHI2_1))
}

/// Noise σ as the nugget of the robust variogram: `√((4 γ̂(1) − γ̂(2)) / 3)` (mm), `None` when
/// the extrapolation is not positive or there are too few points.
pub fn variogram_nugget_sigma(seqs: &[Vec<f64>]) -> Option<f64> {
    let g1 = robust_semivariogram(seqs, 1)?;
    let g2 = robust_semivariogram(seqs, 2)?;
    let nugget = (4.0 * g1 - g2) / 3.0;
    (nugget > 0.0).then(|| nugget.sqrt())
}

/// Robust second-difference σ of sequences: `1.4826 · median|Δ²r| / √6` (0 if none).
pub fn second_difference_sigma(seqs: &[Vec<f64>]) -> f64 {
    let mut d2: Vec<f64> = seqs
        .iter()
        .flat_map(|s| s.windows(3).map(|w| (w[2] - 2.0 * w[1] + w[0]).abs()))
        .collect();
    if d2.is_empty() {
        0.0
    } else {
        1.482_6 * stats::median(&mut d2) / 6f64.sqrt()
    }
}

/// Noise σ from sequences along the curves; `given` overrides the one used for decisions;
/// `smooth` = (σ, robust σ, second-difference σ) of the smooth-basis residual.
pub fn estimate_noise(
    seqs: &[Vec<f64>],
    given: Option<f64>,
    smooth: Option<(f64, f64, f64)>,
) -> NoiseEstimate {
    let (mut num, mut den) = (0.0, 0usize);
    let mut d2 = Vec::new();
    for s in seqs {
        for w in s.windows(2) {
            num += (w[1] - w[0]).powi(2);
            den += 1;
        }
        for w in s.windows(3) {
            d2.push((w[2] - 2.0 * w[1] + w[0]).abs());
        }
    }
    let von_neumann = if den > 0 {
        (num / (2.0 * den as f64)).sqrt()
    } else {
        0.0
    };
    let second_difference = if d2.is_empty() {
        0.0
    } else {
        1.482_6 * stats::median(&mut d2) / 6f64.sqrt()
    };
    let variogram_nugget = variogram_nugget_sigma(seqs);
    let estimated = smooth.map_or(second_difference, |s| s.0.min(s.1).min(s.2));
    let estimated = variogram_nugget.map_or(estimated, |v| estimated.min(v));
    NoiseEstimate {
        given,
        von_neumann,
        second_difference,
        smooth: smooth.map(|s| s.0),
        smooth_robust: smooth.map(|s| s.1),
        smooth_second_difference: smooth.map(|s| s.2),
        variogram_nugget,
        used: given.unwrap_or(estimated),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_of_a_step_and_of_alternation() {
        // 10 positive then 10 negative: 2 runs, expected 11 → strongly negative z.
        let step: Vec<f64> = (0..20).map(|i| if i < 10 { 1.0 } else { -1.0 }).collect();
        let r = randomness(&step);
        assert_eq!(r.runs, 2);
        assert!((r.runs_expected - 11.0).abs() < 1e-12);
        assert!(r.runs_z < -3.0 && r.lag1 > 0.8);
        // Alternating signs: 20 runs (too many), lag-1 ≈ −1.
        let alt: Vec<f64> = (0..20)
            .map(|i| if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let r = randomness(&alt);
        assert_eq!(r.runs, 20);
        assert!(r.lag1 < -0.9);
    }

    #[test]
    fn second_difference_ignores_a_linear_trend() {
        let s: Vec<f64> = (0..25).map(|i| 0.01 * i as f64).collect();
        let e = estimate_noise(&[s], None, None);
        assert!(e.second_difference < 1e-12, "{}", e.second_difference);
        // von Neumann sees the trend's slope: σ² = 0.01²/2.
        assert!((e.von_neumann - 0.01 / 2f64.sqrt()).abs() < 1e-12);
    }

    /// `curves` sequences of `m` standard normal values from one seeded stream.
    fn white(seed: u64, curves: usize, m: usize) -> Vec<Vec<f64>> {
        let mut rng = crate::random::Sampler::new(seed);
        (0..curves)
            .map(|_| (0..m).map(|_| rng.normal()).collect())
            .collect()
    }

    #[test]
    fn variogram_nugget_is_sigma_for_white_noise_and_ignores_a_wave() {
        // 4 curves × 250 points of σ = 1: the trimmed semivariogram is unbiased (constant
        // TRIMMED_CHI2_1), so the nugget is 1 within sampling error (~3 % here).
        let seqs = white(10, 4, 250);
        let nug = variogram_nugget_sigma(&seqs).unwrap();
        assert!((nug - 1.0).abs() < 0.1, "{nug}");
        // Add a wave of amplitude 5 and 6 samples per period: the von Neumann estimate grows to
        // √(1 + 25/4) ≈ 2.7, the nugget by (4γ₁ − γ₂)/3 of the wave = (25/2)(4·0.5 − 1.5)/3 = 25/12
        // → √(1 + 25/12) ≈ 1.76; the trimming constant assumes Gaussian differences, and the
        // lighter-tailed differences of a sine are over-corrected by ≈ 1.4 → ≈ √(1 + 2.9) ≈ 2.0.
        let wavy: Vec<Vec<f64>> = seqs
            .iter()
            .map(|s| {
                s.iter()
                    .enumerate()
                    .map(|(i, v)| v + 5.0 * (std::f64::consts::PI * i as f64 / 3.0).sin())
                    .collect()
            })
            .collect();
        let e = estimate_noise(&wavy, None, None);
        let nug = e.variogram_nugget.unwrap();
        assert!(e.von_neumann > 2.5, "{}", e.von_neumann);
        assert!(nug < 2.1 && nug > 0.9, "{nug}");
        assert!((e.used - nug.min(e.second_difference)).abs() < 1e-15);
    }

    #[test]
    fn ljung_box_accepts_white_noise_and_rejects_a_trend() {
        // (Calibration checked over 400 seeds: 5.3 % of p-values below 0.05.)
        let seqs = white(20, 4, 25);
        let lb = ljung_box(&seqs, LJUNG_BOX_LAGS);
        assert_eq!(lb.dof, 16);
        assert!(lb.p_value > 0.01, "{lb:?}");
        // A slow wave on top: strongly autocorrelated.
        let slow: Vec<Vec<f64>> = seqs
            .iter()
            .map(|s| {
                s.iter()
                    .enumerate()
                    .map(|(i, v)| v + 3.0 * (i as f64 / 4.0).sin())
                    .collect()
            })
            .collect();
        assert!(ljung_box(&slow, LJUNG_BOX_LAGS).p_value < 1e-6);
    }
}
