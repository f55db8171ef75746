//! Thermal-drift signature (effects.md): the head grows along machine Z in proportion to
//! machining time, i.e. to the tool-tip path length `s` from the start of A (through B). A drift
//! `g` over the whole path moves the tool by `−g·(s/s_total)·ẑ` (towards the table), so the
//! deviation is `−g·(s/s_total)·N_z`.

use super::EffectPoint;

/// `thermal_drift.g` column (mm/mm): `−(s/s_total)·N_z`.
pub fn thermal_drift(points: &[EffectPoint], s_total: f64) -> Vec<Vec<f64>> {
    vec![points.iter().map(|p| -(p.s / s_total) * p.n.z).collect()]
}
