//! Pivot-length signature (effects.md): a real pivot-to-tip length `L0 + dL0` moves the tool by
//! `−dL0·w` along its own axis `w`, which has no normal component on a flank-milled wall
//! (`N·w = 0`); the part origin was set with B = 0, which removed `−dL0·ẑ`, so what shows is
//! `+dL0·ẑ·N = dL0·N_z`.

use super::EffectPoint;

/// `pivot_length.dL0` column (mm/mm): `N_z`.
pub fn pivot_length(points: &[EffectPoint]) -> Vec<Vec<f64>> {
    vec![points.iter().map(|p| p.n.z).collect()]
}
