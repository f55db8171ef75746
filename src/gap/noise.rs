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
//! - Randomness: the Wald–Wolfowitz runs test of the signs along each curve (too few runs =
//!   structure), pooled over curves as a z-score; the lag-1 autocorrelation `ρ₁` per curve with
//!   `z = ρ₁ √m` (pooled: sums over curves).
//! - Size: `χ² = RSS / σ²` against `n − rank` degrees of freedom.

use serde::Serialize;

use super::stats;

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
    /// The σ the decisions use (mm): the given value, else the smallest of the three smooth-basis
    /// estimates (each is inflated by a different kind of structure: long waves, a few large
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

/// Robust second-difference σ of sequences: `1.4826 · median|Δ²r| / √6` (0 if none).
pub fn second_difference_sigma(seqs: &[Vec<f64>]) -> f64 {
    let mut d2: Vec<f64> = seqs
        .iter()
        .flat_map(|s| s.windows(3).map(|w| (w[2] - 2.0 * w[1] + w[0]).abs()))
        .collect();
    if d2.is_empty() {
        0.0
    } else {
        1.482_6 * median(&mut d2) / 6f64.sqrt()
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
        1.482_6 * median(&mut d2) / 6f64.sqrt()
    };
    NoiseEstimate {
        given,
        von_neumann,
        second_difference,
        smooth: smooth.map(|s| s.0),
        smooth_robust: smooth.map(|s| s.1),
        smooth_second_difference: smooth.map(|s| s.2),
        used: given.unwrap_or(smooth.map_or(second_difference, |s| s.0.min(s.1).min(s.2))),
    }
}

fn median(x: &mut [f64]) -> f64 {
    x.sort_by(f64::total_cmp);
    let m = x.len();
    if m % 2 == 1 {
        x[m / 2]
    } else {
        0.5 * (x[m / 2 - 1] + x[m / 2])
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
}
