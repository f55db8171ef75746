//! Overcut signature (effects.md, paper 000 §3): `k ×` the exact envelope deviation of the flank
//! path at the points (computed by [`crate::toolpath::envelope`]); `k = 1` is the exact envelope.

/// `overcut.k` column (mm per unit k): the envelope deviations themselves.
pub fn overcut(envelope: &[f64]) -> Vec<Vec<f64>> {
    vec![envelope.to_vec()]
}
