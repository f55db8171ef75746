//! The detection limit of every effect of `shared/spec/effects.md` on the plan's points: the
//! smallest size of each effect parameter that the diagnosis's decision rule can name.
//!
//! effects.md names an effect only if the part of it that the baseline (the location errors,
//! `physical` mode) cannot absorb has an RMS over the points above `k σ` (`k` =
//! [`crate::gap::DiagnoseOptions::detect_factor`], 2.5). For parameter `j` of an effect with
//! signature column `s_j` (mm per unit of the parameter) and the baseline design `A`, the
//! unabsorbed part per unit is `u_j = (I − P_A) s_j` ([`crate::identify::solve::Factor`], the
//! projector the diagnosis uses), and the limit is
//!
//! `limit_j = k σ / RMS(u_j) = k σ √n / ‖u_j‖`   (in the parameter's unit),
//!
//! the formula of the diagnosis's own `detection_limit` per parameter (`gap::which`), here on
//! the plan's points before any part exists. A column the baseline absorbs entirely has no
//! limit (JSON null: never visible on this part). Signatures come from the part model of the
//! diagnosis ([`crate::effects::prepared::Prepared::part_model`]), not re-derived.

use std::collections::BTreeMap;

use nalgebra::DMatrix;
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};

use crate::effects::builtin::PartModel;
use crate::identify::solve::Factor;
use crate::machine::Unit;
use crate::parameter::Effect;

/// One parameter's limit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParameterLimit {
    pub name: String,
    pub unit: Unit,
    /// Smallest visible size (unit of the parameter); `None` (null) when never visible.
    pub size: Option<f64>,
    /// Share of the signature's norm the baseline absorbs, `√(1 − ‖u‖²/‖s‖²)` (0..1).
    pub absorbed_fraction: f64,
}

/// The limits of one effect.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DetectionLimit {
    pub effect: Effect,
    /// Plain name for reports (effects.md meaning).
    pub plain_name: &'static str,
    pub parameters: Vec<ParameterLimit>,
}

/// Every effect's limits, serialised as `{effect id: {parameter: size}}`.
#[derive(Debug, Clone, PartialEq)]
pub struct DetectionLimits(pub Vec<DetectionLimit>);

impl Serialize for DetectionLimits {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for d in &self.0 {
            // Inserted one by one: `collect` into a map sorts with a copy of the sort code of
            // its own (numerics::order).
            let mut sizes: BTreeMap<&str, Option<f64>> = BTreeMap::new();
            for p in &d.parameters {
                sizes.insert(p.name.as_str(), p.size);
            }
            m.serialize_entry(d.effect.id(), &sizes)?;
        }
        m.end()
    }
}

/// The limits (`k σ` rule, `sigma` in mm) of every candidate of `model` against its baseline.
pub fn detection_limits(model: &PartModel, sigma: f64, k: f64) -> DetectionLimits {
    let base = Factor::new(&model.baseline.matrix, None);
    let n = model.baseline.matrix.nrows().max(1) as f64;
    DetectionLimits(
        model
            .candidates
            .iter()
            .map(|c| DetectionLimit {
                effect: c.effect,
                plain_name: c.effect.plain_name(),
                parameters: parameter_limits(&base, &c.signature.matrix, n, sigma * k)
                    .into_iter()
                    .zip(c.effect.parameters())
                    .map(|((size, absorbed_fraction), (name, unit))| ParameterLimit {
                        name: name.to_string(),
                        unit: unit.clone(),
                        size,
                        absorbed_fraction,
                    })
                    .collect(),
            })
            .collect(),
    )
}

/// Below this unabsorbed norm relative to the signature's (and below
/// [`crate::effects::builtin::INVISIBLE_SIGNATURE`] absolute) a column is absorbed entirely:
/// the rank rule of [`crate::identify::solve::RANK_TOL`].
const ABSORBED: f64 = crate::identify::solve::RANK_TOL;

/// `(k σ √n / ‖u_j‖, absorbed fraction)` per column of `sig`, `threshold = k σ` (mm).
fn parameter_limits(
    base: &Factor,
    sig: &DMatrix<f64>,
    n: f64,
    threshold: f64,
) -> Vec<(Option<f64>, f64)> {
    let u = base.unabsorbed(sig);
    (0..sig.ncols())
        .map(|j| {
            let sn = sig.column(j).norm();
            let un = u.column(j).norm();
            let absorbed = if sn > 0.0 {
                (1.0 - (un / sn).powi(2)).max(0.0).sqrt()
            } else {
                1.0
            };
            let visible = un > ABSORBED * sn && sn > crate::effects::builtin::INVISIBLE_SIGNATURE;
            (visible.then(|| threshold * n.sqrt() / un), absorbed)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// Baseline `A = (1, 1, 1, 1)ᵀ`, signature `s = (1, −1, 1, −1)ᵀ` (orthogonal to it): nothing
    /// absorbed, `RMS(u) = 1`, so the limit is `k σ` (closed form, 1e-15); `s = (2, 2, 2, 2)`
    /// is absorbed entirely: no limit.
    #[test]
    fn limit_is_k_sigma_over_the_unabsorbed_rms() {
        let base = Factor::new(&DMatrix::from_element(4, 1, 1.0), None);
        let sig = DMatrix::from_column_slice(4, 2, &[1.0, -1.0, 1.0, -1.0, 2.0, 2.0, 2.0, 2.0]);
        let l = parameter_limits(&base, &sig, 4.0, 2.5 * 0.002);
        assert_near!(l[0].0.unwrap(), 0.005, 1e-15);
        // √(1 − ‖u‖²/‖s‖²) of a rounding-level difference: √ε ≈ 1.5e-8.
        assert_near!(l[0].1, 0.0, 2e-8);
        assert_eq!(l[1].0, None);
        assert_near!(l[1].1, 1.0, 1e-12);
    }
}
