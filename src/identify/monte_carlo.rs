//! Monte Carlo check of the identification uncertainty with seeded CMM noise.
//!
//! **From an MPE to a standard deviation.** Paper 000 §6 quotes the CMM's maximum permissible
//! error of length measurement `MPE_E = ±(3 + L/75) µm` (L in mm) and the repeatability range
//! `R0 = 3 µm` (ISO 10360-2:2009). An MPE is a bound, not a standard deviation: following the
//! GUM (JCGM 100, 4.3.7) a value known only to lie within `±a` is given a rectangular
//! distribution, standard uncertainty `a/√3`. `R0` is the range of 3 repeated measurements; for
//! normal errors the expected range of 3 samples is `d2·σ` with `d2 = 1.693`, so `σ_rep = R0/1.693`.
//! The noise of point `i` is Gaussian with `σ_i = max(MPE_E(L_i)/√3, R0/1.693)`, `L_i` being the
//! distance of the point from the part origin (the datum the CMM measures from). For the paper's
//! CMM and the S-shape (L ≤ 160 mm) this gives σ between 1.77 and 2.96 µm.
//!
//! Each run draws `y = A·x_true + e` with a ChaCha8 stream seeded by `seed` (identical natively
//! and in wasm) and applies the same linear estimator as [`super::identify`]; the spread of the
//! estimates is compared with the predicted std `√diag(M Σ Mᵀ)`.

use nalgebra::{DMatrix, DVector};
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};

use super::{identify, Design, Factored, IdentifyError, IdentifyOptions, Observations};

/// `d2` for samples of 3: expected range of 3 standard normal values.
pub const D2_RANGE_OF_3: f64 = 1.693;

/// A CMM's maximum permissible errors (ISO 10360-2): `MPE_E = ±(a + L/k) µm`, `R0` in µm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CmmMpe {
    /// Constant term `a` (µm).
    pub a_um: f64,
    /// Length divisor `k` (mm per µm): MPE grows by 1 µm every `k` mm.
    pub k_mm: f64,
    /// Repeatability range `R0` (µm; 0 when not given: the MPE term alone).
    #[serde(default)]
    pub r0_um: f64,
}

impl CmmMpe {
    /// The Trimesure CMM of paper 000 §6: `±(3 + L/75) µm`, `R0 = 3 µm`.
    pub fn paper000() -> Self {
        CmmMpe {
            a_um: 3.0,
            k_mm: 75.0,
            r0_um: 3.0,
        }
    }

    /// Validated constructor (all values > 0, finite; `r0_um` >= 0).
    pub fn try_new(a_um: f64, k_mm: f64, r0_um: f64) -> Result<Self, IdentifyError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !ok(a_um) {
            return Err(IdentifyError::BadOption {
                name: "mpe a_um",
                value: a_um,
                expected: "> 0 (µm)",
            });
        }
        if !ok(k_mm) {
            return Err(IdentifyError::BadOption {
                name: "mpe k_mm",
                value: k_mm,
                expected: "> 0 (mm)",
            });
        }
        if !(r0_um.is_finite() && r0_um >= 0.0) {
            return Err(IdentifyError::BadOption {
                name: "mpe r0_um",
                value: r0_um,
                expected: ">= 0 (µm)",
            });
        }
        Ok(CmmMpe { a_um, k_mm, r0_um })
    }

    /// `MPE_E(L)` in mm for a length `L` in mm.
    pub fn mpe_mm(&self, length_mm: f64) -> f64 {
        (self.a_um + length_mm.abs() / self.k_mm) * 1e-3
    }

    /// Standard deviation (mm) of one point at distance `L` (mm): `max(MPE_E/√3, R0/d2)`.
    pub fn sigma_mm(&self, length_mm: f64) -> f64 {
        (self.mpe_mm(length_mm) / 3f64.sqrt()).max(self.r0_um * 1e-3 / D2_RANGE_OF_3)
    }
}

/// The noise added in each run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Noise {
    /// The same σ (mm) at every point.
    Gaussian { sigma: f64 },
    /// One σ (mm) per design row.
    PerPoint { sigma: Vec<f64> },
}

impl Noise {
    /// Per-point σ from a CMM's MPE and the distance of each point from the part origin (mm).
    pub fn from_mpe(mpe: &CmmMpe, lengths_mm: &[f64]) -> Self {
        Noise::PerPoint {
            sigma: lengths_mm.iter().map(|&l| mpe.sigma_mm(l)).collect(),
        }
    }

    fn sigma(&self, n: usize) -> Result<Vec<f64>, IdentifyError> {
        let s = match self {
            Noise::Gaussian { sigma } => vec![*sigma; n],
            Noise::PerPoint { sigma } => {
                if sigma.len() != n {
                    return Err(IdentifyError::LengthMismatch {
                        what: "noise sigmas",
                        found: sigma.len(),
                        expected: n,
                    });
                }
                sigma.clone()
            }
        };
        if let Some(&bad) = s.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(IdentifyError::BadOption {
                name: "noise sigma",
                value: bad,
                expected: ">= 0 and finite (mm)",
            });
        }
        Ok(s)
    }
}

/// Options of [`monte_carlo`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MonteCarloOptions {
    /// Number of simulated parts (default 500).
    pub runs: usize,
    /// Seed of the ChaCha8 stream (default 7).
    pub seed: u64,
}

impl Default for MonteCarloOptions {
    fn default() -> Self {
        MonteCarloOptions { runs: 500, seed: 7 }
    }
}

impl MonteCarloOptions {
    /// Sets the number of runs.
    pub fn with_runs(mut self, runs: usize) -> Self {
        self.runs = runs;
        self
    }
    /// Sets the seed.
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }
}

/// Monte Carlo result for one parameter or combination.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct McEstimate {
    /// Parameter name or combination text.
    pub name: String,
    /// True value.
    pub truth: f64,
    /// Mean of the estimates.
    pub mean: f64,
    /// Std of the estimates over the runs.
    pub std_mc: f64,
    /// Std predicted by the linear propagation `√(c M Σ Mᵀ cᵀ)`.
    pub std_predicted: f64,
}

/// What the Monte Carlo check found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MonteCarloReport {
    pub runs: usize,
    pub seed: u64,
    /// Smallest and largest per-point σ used (mm).
    pub sigma_min: f64,
    pub sigma_max: f64,
    /// Per parameter, in design order.
    pub parameters: Vec<McEstimate>,
    /// Per estimable combination of the not-separable groups.
    pub combinations: Vec<McEstimate>,
    /// Mean residual RMS over the runs (mm).
    pub residual_rms_mean: f64,
}

/// Simulates `runs` parts `A·truth + noise` and identifies each with the estimator of
/// [`identify`] (same weights, same kept directions).
pub fn monte_carlo(
    design: &Design,
    obs: &Observations,
    truth: &[f64],
    noise: &Noise,
    mc: &MonteCarloOptions,
    opts: &IdentifyOptions,
) -> Result<MonteCarloReport, IdentifyError> {
    let p = design.cols();
    if truth.len() != p {
        return Err(IdentifyError::LengthMismatch {
            what: "true parameters",
            found: truth.len(),
            expected: p,
        });
    }
    if mc.runs < 2 {
        return Err(IdentifyError::BadOption {
            name: "runs",
            value: mc.runs as f64,
            expected: ">= 2",
        });
    }
    let sigma = noise.sigma(design.rows())?;
    let f = Factored::new(design, obs, opts)?;
    let m = f.estimator();
    let clean = design.predict(truth);
    // Structure (groups) from the noise-free part.
    let structure = identify(
        design,
        &Observations {
            deviation: clean.clone(),
            ..obs.clone()
        },
        opts,
    )?;
    let names = design.names();
    let combos: Vec<(String, Vec<f64>)> = structure
        .groups
        .iter()
        .flat_map(|g| g.estimable.iter())
        .map(|e| (e.combination.text.clone(), e.combination.vector(&names)))
        .collect();

    // Predicted covariance M Σ Mᵀ.
    let n = f.used.len();
    let sig_used: Vec<f64> = f.used.iter().map(|&i| sigma[i]).collect();
    let ms = DMatrix::from_fn(p, n, |j, r| m[(j, r)] * sig_used[r]);
    let cov = &ms * ms.transpose();
    let pred = |c: &[f64]| {
        let cv = DVector::from_column_slice(c);
        (cv.transpose() * &cov * &cv)[(0, 0)].max(0.0).sqrt()
    };

    let mut rng = ChaCha8Rng::seed_from_u64(mc.seed);
    let mut sum = vec![0.0; p + combos.len()];
    let mut sum2 = vec![0.0; p + combos.len()];
    let mut rms_sum = 0.0;
    let a = design.matrix();
    for _ in 0..mc.runs {
        let mut y = DVector::zeros(n);
        for (r, &i) in f.used.iter().enumerate() {
            let z: f64 = StandardNormal.sample(&mut rng);
            y[r] = clean[i] + sigma[i] * z;
        }
        let x = &m * &y;
        let mut vals: Vec<f64> = x.iter().copied().collect();
        for (_, c) in &combos {
            vals.push(c.iter().zip(x.iter()).map(|(a, b)| a * b).sum());
        }
        for (k, v) in vals.iter().enumerate() {
            sum[k] += v;
            sum2[k] += v * v;
        }
        let mut ss = 0.0;
        for (r, &i) in f.used.iter().enumerate() {
            let fit: f64 = (0..p).map(|j| a[(i, j)] * x[j]).sum();
            ss += (y[r] - fit).powi(2);
        }
        rms_sum += (ss / n as f64).sqrt();
    }
    let runs = mc.runs as f64;
    let stat = |k: usize| {
        let mean = sum[k] / runs;
        let var = ((sum2[k] - runs * mean * mean) / (runs - 1.0)).max(0.0);
        (mean, var.sqrt())
    };
    let parameters = (0..p)
        .map(|j| {
            let (mean, std_mc) = stat(j);
            let mut e = vec![0.0; p];
            e[j] = 1.0;
            McEstimate {
                name: names[j].clone(),
                truth: truth[j],
                mean,
                std_mc,
                std_predicted: pred(&e),
            }
        })
        .collect();
    let combinations = combos
        .iter()
        .enumerate()
        .map(|(k, (text, c))| {
            let (mean, std_mc) = stat(p + k);
            McEstimate {
                name: text.clone(),
                truth: c.iter().zip(truth).map(|(a, b)| a * b).sum(),
                mean,
                std_mc,
                std_predicted: pred(c),
            }
        })
        .collect();
    Ok(MonteCarloReport {
        runs: mc.runs,
        seed: mc.seed,
        sigma_min: sigma.iter().copied().fold(f64::INFINITY, f64::min),
        sigma_max: sigma.iter().copied().fold(0.0, f64::max),
        parameters,
        combinations,
        residual_rms_mean: rms_sum / runs,
    })
}
