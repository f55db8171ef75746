//! The CMM-noise setting: how the σ of one measured deviation is known, resolved once, shared by
//! the analysis of a part and by the measurement plan before a part exists.
//!
//! The lab gives σ, or its CMM's maximum permissible error `MPE_E = A + L/K` µm (ISO 10360-2,
//! with the repeatability range `R0`), or nothing (σ is then estimated from the residual by the
//! measurement model, [`crate::measurement::noise`]); repeat measurements of the part give it too
//! ([`NoiseKind::Repeat`], resolved by the analysis from the repeats).

use serde::Serialize;

use crate::identify::monte_carlo::CmmMpe;
use crate::identify::IdentifyError;

/// Where the σ of an analysis or a plan comes from (JSON: `given`, `mpe`, `repeat`,
/// `estimated`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum NoiseKind {
    /// σ as the lab gave it.
    Given,
    /// σ from the CMM's MPE at the points ([`noise_from_mpe`]).
    Mpe,
    /// σ of the mean of repeat measurements, from their differences.
    Repeat,
    /// σ estimated from the residual (no CMM figure given).
    Estimated,
}

impl NoiseKind {
    /// Whether σ was derived (from the MPE at the points, or from the repeats' differences):
    /// the reports then say how.
    pub fn is_derived(self) -> bool {
        matches!(self, NoiseKind::Mpe | NoiseKind::Repeat)
    }
}

/// The CMM-noise setting, checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CmmNoise {
    /// Nothing given: σ from the residual.
    Estimated,
    /// σ of one deviation (mm, 1σ), positive and finite.
    Sigma(f64),
    /// The CMM's MPE, validated.
    Mpe(CmmMpe),
}

/// A CMM-noise setting that cannot be used, with the values given.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NoiseError {
    #[error("CMM uncertainty σ = {0} mm is not a positive finite number")]
    BadSigma(f64),
    #[error(
        "the CMM noise is given twice: σ = {sigma} mm and MPE = {a} + L/{k} µm; give one of them"
    )]
    SigmaAndMpe { sigma: f64, a: f64, k: f64 },
    #[error("CMM MPE: {0}")]
    BadMpe(IdentifyError),
}

impl CmmNoise {
    /// The setting of a σ (mm) and an MPE, at most one of them given.
    pub fn try_new(sigma: Option<f64>, mpe: Option<&CmmMpe>) -> Result<Self, NoiseError> {
        if let Some(s) = sigma {
            if !(s.is_finite() && s > 0.0) {
                return Err(NoiseError::BadSigma(s));
            }
        }
        match (sigma, mpe) {
            (Some(sigma), Some(m)) => Err(NoiseError::SigmaAndMpe {
                sigma,
                a: m.a_um,
                k: m.k_mm,
            }),
            (Some(sigma), None) => Ok(CmmNoise::Sigma(sigma)),
            (None, Some(m)) => CmmMpe::try_new(m.a_um, m.k_mm, m.r0_um)
                .map(CmmNoise::Mpe)
                .map_err(NoiseError::BadMpe),
            (None, None) => Ok(CmmNoise::Estimated),
        }
    }

    /// The σ this setting gives at points at distances `lengths` (mm) from the part origin.
    pub fn resolve(&self, lengths: &[f64]) -> ResolvedNoise {
        match *self {
            CmmNoise::Estimated => ResolvedNoise {
                kind: NoiseKind::Estimated,
                sigma: None,
                mpe: None,
            },
            CmmNoise::Sigma(s) => ResolvedNoise {
                kind: NoiseKind::Given,
                sigma: Some(s),
                mpe: None,
            },
            CmmNoise::Mpe(m) => {
                let (median, lo, hi) = noise_from_mpe(&m, lengths);
                ResolvedNoise {
                    kind: NoiseKind::Mpe,
                    sigma: Some(median),
                    mpe: Some(MpeRange { mpe: m, lo, hi }),
                }
            }
        }
    }
}

/// The σ of a setting at a set of points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResolvedNoise {
    pub kind: NoiseKind,
    /// σ (mm); `None` when it is to be estimated from the residual.
    pub sigma: Option<f64>,
    /// The MPE and the smallest and largest per-point σ it gives (mm).
    pub mpe: Option<MpeRange>,
}

/// An MPE and the range of the per-point σ it gives over the points (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MpeRange {
    pub mpe: CmmMpe,
    pub lo: f64,
    pub hi: f64,
}

/// σ (mm) from a CMM's MPE at points at distances `lengths` (mm) from the part origin: each
/// point's `σ_i = max(MPE_E(L_i)/√3, R0/1.693)` (the Monte Carlo's rule,
/// [`crate::identify::monte_carlo::CmmMpe::sigma_mm`]); the analysis uses their **median** as
/// one σ for every point, in the identification and in the diagnosis. Why one σ and not
/// per-point weights: the diagnosis's tests (χ², F, the k σ rule) and the correlated fit of an
/// unexplained structure take one white σ, and the final answer must be fitted as the diagnosis
/// was; on the S-shape (L ≤ 160 mm) the σ_i differ by less than a factor 1.3 for usual MPEs
/// (`3 + L/75`: 1.77..2.96 µm), so weights would change the estimates little. Returns (median,
/// min, max).
pub fn noise_from_mpe(mpe: &CmmMpe, lengths: &[f64]) -> (f64, f64, f64) {
    let mut s: Vec<f64> = lengths.iter().map(|&l| mpe.sigma_mm(l)).collect();
    s.sort_by(f64::total_cmp);
    if s.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let m = s.len();
    let med = if m % 2 == 1 {
        s[m / 2]
    } else {
        0.5 * (s[m / 2 - 1] + s[m / 2])
    };
    (med, s[0], s[m - 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The setting's checks, each failure with the values given (exact).
    #[test]
    fn settings_are_checked() {
        assert_eq!(CmmNoise::try_new(None, None), Ok(CmmNoise::Estimated));
        assert_eq!(
            CmmNoise::try_new(Some(0.002), None),
            Ok(CmmNoise::Sigma(0.002))
        );
        assert_eq!(
            CmmNoise::try_new(Some(-1.0), None),
            Err(NoiseError::BadSigma(-1.0))
        );
        let m = CmmMpe::paper000();
        assert_eq!(
            CmmNoise::try_new(Some(0.002), Some(&m)),
            Err(NoiseError::SigmaAndMpe {
                sigma: 0.002,
                a: 3.0,
                k: 75.0
            })
        );
        let r = CmmNoise::try_new(None, Some(&m))
            .unwrap()
            .resolve(&[0.0, 75.0, 150.0]);
        assert_eq!(r.kind, NoiseKind::Mpe);
        // σ_i = max((3 + L/75)/√3, 3/1.693) µm: 1.772, 2.309, 2.887 µm; median the middle one.
        let s = r.sigma.unwrap();
        assert!((s - 4.0e-3 / 3f64.sqrt()).abs() < 1e-12, "{s}");
    }
}
