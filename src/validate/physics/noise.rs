//! The noise of a measured part: the CMM's own (Gaussian, heavy-tailed, or with occasional large
//! errors) and the part's surface scatter (roughness, local form), which re-probing the same
//! points does not resample.
//!
//! A measurement `j` of point `i` records `y_ij = μ_i + s_i + ε_ij`: `μ_i` the noise-free
//! deviation, `s_i ~ N(0, σ_s²)` drawn once per part, `ε_ij` the CMM's noise of standard deviation
//! `σ_c`, fresh at every probing:
//! - **Gaussian** `ε = σ_c z`;
//! - **Student-t** of `ν` degrees of freedom scaled to standard deviation `σ_c`:
//!   `ε = σ_c √((ν − 2)/ν) · z / √(χ²_ν/ν)` (heavy tails: a few points 3-5 σ out);
//! - **contaminated**: Gaussian, and with probability `rate` a point is off by a further
//!   `±U(factor_lo, factor_hi)·σ_c` (a speck of dirt, a probe hiccup): outliers, not noise.
//!
//! The σ of one analysed deviation (what the detection limit is computed with) is the standard
//! deviation of the noise excluding the contamination: `√(σ_s² + σ_c²)` for one measurement,
//! `√(σ_s² + σ_c²/k)` for the mean of `k` (the scatter does not average out).

use crate::numerics::random::Sampler;

/// The CMM's noise distribution.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "model", rename_all = "snake_case")]
pub enum CmmModel {
    Gaussian,
    StudentT {
        nu: u32,
    },
    Contaminated {
        rate: f64,
        factor_lo: f64,
        factor_hi: f64,
    },
}

impl CmmModel {
    /// A short name for tables.
    pub fn name(&self) -> &'static str {
        match self {
            CmmModel::Gaussian => "gaussian",
            CmmModel::StudentT { .. } => "student_t",
            CmmModel::Contaminated { .. } => "contaminated",
        }
    }
}

/// The noise of one part.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct NoiseSpec {
    /// The CMM's σ (mm).
    pub cmm_sigma: f64,
    pub model: CmmModel,
    /// The part's surface scatter σ (mm; 0: none).
    pub scatter_sigma: f64,
    /// Number of measurements of the same points (1: one file).
    pub repeats: usize,
}

impl NoiseSpec {
    /// The σ of one analysed deviation (one file, or the mean of the repeats; mm).
    pub fn sigma(&self) -> f64 {
        (self.scatter_sigma.powi(2) + self.cmm_sigma.powi(2) / self.repeats.max(1) as f64).sqrt()
    }

    /// The measurements of a part whose noise-free deviations are `mu`: `repeats` files sharing
    /// one draw of the surface scatter.
    pub fn measure(&self, mu: &[f64], rng: &mut Sampler) -> Vec<Vec<f64>> {
        let scatter: Vec<f64> = mu
            .iter()
            .map(|_| {
                if self.scatter_sigma > 0.0 {
                    self.scatter_sigma * rng.normal()
                } else {
                    0.0
                }
            })
            .collect();
        (0..self.repeats.max(1))
            .map(|_| {
                mu.iter()
                    .zip(&scatter)
                    .map(|(m, s)| m + s + self.cmm_draw(rng))
                    .collect()
            })
            .collect()
    }

    /// One draw of the CMM's noise (mm).
    fn cmm_draw(&self, rng: &mut Sampler) -> f64 {
        let s = self.cmm_sigma;
        match self.model {
            CmmModel::Gaussian => s * rng.normal(),
            CmmModel::StudentT { nu } => {
                let chi2: f64 = (0..nu).map(|_| rng.normal().powi(2)).sum();
                let nu = nu as f64;
                s * ((nu - 2.0) / nu).sqrt() * rng.normal() / (chi2 / nu).sqrt()
            }
            CmmModel::Contaminated {
                rate,
                factor_lo,
                factor_hi,
            } => {
                let z = s * rng.normal();
                if rng.unit() < rate {
                    z + rng.sign() * rng.uniform(factor_lo, factor_hi) * s
                } else {
                    z
                }
            }
        }
    }
}
