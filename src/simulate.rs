//! Synthetic measured parts: the deviations a machine with given errors would leave, plus
//! seeded CMM noise (the twin used by `testpiece simulate`, validation and tests).
//!
//! `deviation = A·x + e` (mm; + = material left, - = overcut): `A` is the linearised design of
//! paper 000 eq. 13-14 (the sensitivity stage's matrix at the measured points, optionally with
//! the tool-radius column -1), `x` the errors (rad; mm for `EX0B` and `dR`), `e_i` Gaussian with
//! σ (mm) from a ChaCha8 stream seeded by `seed`, so the same seed gives the same part natively
//! and in wasm.

use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use thiserror::Error;

use crate::identify::{Design, IdentifyError};

/// What can go wrong when simulating a part.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimulateError {
    /// An item of an error list is not `NAME=value`.
    #[error("error list item {index} `{text}`: expected NAME=value, e.g. EX0B=0.03")]
    BadItem { index: usize, text: String },
    /// A value does not parse as a finite number.
    #[error("error list item {index}: value `{text}` of {name} is not a finite number")]
    BadValue {
        index: usize,
        name: String,
        text: String,
    },
    /// The same name is given twice.
    #[error("error list: {name} is given twice")]
    Duplicate { name: String },
    /// The noise σ is negative or not finite.
    #[error("noise sigma {0} mm: expected a finite number >= 0")]
    BadNoise(f64),
    /// A name unknown to the design.
    #[error(transparent)]
    Design(#[from] IdentifyError),
}

/// Parses `EX0B=0.03,EA0B=3e-4` (commas or semicolons; spaces ignored; empty gives none).
pub fn parse_errors(text: &str) -> Result<Vec<(String, f64)>, SimulateError> {
    let mut out: Vec<(String, f64)> = Vec::new();
    for (k, item) in text
        .split([',', ';'])
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .enumerate()
    {
        let index = k + 1;
        let (name, value) = item.split_once('=').ok_or_else(|| SimulateError::BadItem {
            index,
            text: item.to_string(),
        })?;
        let name = name.trim().to_string();
        if name.is_empty() {
            return Err(SimulateError::BadItem {
                index,
                text: item.to_string(),
            });
        }
        let v: f64 = value
            .trim()
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| SimulateError::BadValue {
                index,
                name: name.clone(),
                text: value.trim().to_string(),
            })?;
        if out.iter().any(|(n, _)| *n == name) {
            return Err(SimulateError::Duplicate { name });
        }
        out.push((name, v));
    }
    Ok(out)
}

/// `A·x + e` at the design rows, `x` from `(name, value)` pairs (others 0), `e ~ N(0, σ²)`.
pub fn simulate_deviation(
    design: &Design,
    errors: &[(String, f64)],
    noise_sigma: f64,
    seed: u64,
) -> Result<Vec<f64>, SimulateError> {
    if !(noise_sigma.is_finite() && noise_sigma >= 0.0) {
        return Err(SimulateError::BadNoise(noise_sigma));
    }
    let x = design.vector_from(errors)?;
    let mut y = design.predict(&x);
    if noise_sigma > 0.0 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        for v in y.iter_mut() {
            let z: f64 = StandardNormal.sample(&mut rng);
            *v += noise_sigma * z;
        }
    }
    Ok(y)
}
