//! Naming the leading terms of a direction: its largest components in decreasing magnitude, with
//! ties broken by the lower index, and coefficients written as a combination writes them. Used by
//! the identifiability groups ([`crate::identify::groups`]) and by the derivation of a machine's
//! location errors from what the part sees ([`crate::sensitivity::error_set`]).

use serde::{Deserialize, Serialize};

/// One term of a combination: `coefficient · name`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Term {
    pub name: String,
    pub coefficient: f64,
}

/// Relative width within which two magnitudes count as tied (a few hundred ulps): ties are broken
/// by the lower parameter index, so a tie that rounding breaks one way natively and the other way
/// in wasm (different `libm`) names the same leading parameter on both.
const TIE: f64 = 1e-9;

/// The indices of `(index, magnitude)` pairs in decreasing magnitude, where magnitudes within
/// [`TIE`] (relative to the larger) count as equal and the lower index comes first. Greedy
/// selection rather than `sort_by`, since "within a tolerance" is not a total order.
pub fn by_decreasing_magnitude(mut items: Vec<(usize, f64)>) -> Vec<usize> {
    let mut out = Vec::with_capacity(items.len());
    while !items.is_empty() {
        let top = items
            .iter()
            .map(|&(_, m)| m)
            .fold(f64::NEG_INFINITY, f64::max);
        let pick = items
            .iter()
            .enumerate()
            .filter(|(_, &(_, m))| m >= top - TIE * top.abs() || m == top)
            .min_by_key(|(_, &(j, _))| j)
            .map_or(0, |(k, _)| k);
        out.push(items.swap_remove(pick).0);
    }
    out
}

/// Indices of the largest `|v_j|` until they carry `share` of `‖v‖²`, in decreasing order.
pub fn dominant(v: &[f64], share: f64) -> Vec<usize> {
    let total: f64 = v.iter().map(|x| x * x).sum();
    let idx = by_decreasing_magnitude((0..v.len()).map(|j| (j, v[j].abs())).collect());
    let mut acc = 0.0;
    let mut out = Vec::new();
    for j in idx {
        if total > 0.0 && acc >= share * total {
            break;
        }
        if v[j] == 0.0 && !out.is_empty() {
            break;
        }
        acc += v[j] * v[j];
        out.push(j);
    }
    out
}

/// A coefficient's magnitude as a combination writes it: nothing for 1 (within 0.005), two
/// decimals from 0.01 to 100, else two significant digits in exponent form; a space after.
pub fn magnitude_text(mag: f64) -> String {
    if (mag - 1.0).abs() < 0.005 {
        String::new()
    } else if (0.01..100.0).contains(&mag) {
        format!("{mag:.2} ")
    } else {
        format!("{mag:.2e} ")
    }
}
