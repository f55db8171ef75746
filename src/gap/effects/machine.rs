//! Signatures that need the machine's axis path (kinematics stage, [`crate::sensitivity`]):
//! `scale_x/y/z` and `backlash_x/y/z/b/c`, and the axis reversals along the path.
//!
//! Scale error (effects.md): `E_XX = k·X`, `E_YY = k·Y`, `E_ZZ = k·(Z − L0)`, i.e. the linear
//! coefficient (power 1) of the axis's own positioning error motion, evaluated by
//! [`crate::sensitivity::jacobian_rows`] like the location errors (defect per unit at the point,
//! minus the tip displacement at the reference pose `(0, 0, L0, 0, 0)` where the part origin is
//! set, which removes the constant `k·L0` of Z). Backlash: the first-order-lag reversal model of
//! [`crate::sensitivity::reversal`] (lag of 2 mm of tool-tip path, settled at each pass start).

use crate::gap::data::Reversal;
pub use crate::gap::effect::{BACKLASH_AXES, SCALE_AXES};
use crate::gap::GapError;
use crate::machine::{AxisName, ErrorParam};
use crate::part::{MeasurementPoint, SShape};
use crate::sensitivity::defect::jacobian_rows;
use crate::sensitivity::reversal::{backlash_signatures_lagged, directions, Lag, Pass};
use crate::sensitivity::SensitivityOptions;

fn model_err(e: impl std::fmt::Display) -> GapError {
    GapError::Model(e.to_string())
}

/// `scale_<axis>.k` columns (mm/mm), axes of [`SCALE_AXES`].
pub fn scale_signatures(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &SensitivityOptions,
) -> Result<Vec<(AxisName, Vec<f64>)>, GapError> {
    let params: Vec<ErrorParam> = SCALE_AXES
        .iter()
        .map(|&a| ErrorParam::Motion {
            component: a,
            axis: a,
            power: 1,
        })
        .collect();
    let m = jacobian_rows(part, points, opts, &params).map_err(model_err)?;
    Ok(SCALE_AXES
        .iter()
        .enumerate()
        .map(|(j, &a)| (a, m.column(j).iter().copied().collect()))
        .collect())
}

/// `backlash_<axis>.b` columns (mm/mm or mm/rad), axes of the lags, on the lags of the passes
/// of [`crate::sensitivity::reversal::passes`] ([`super::path_model::PathModel::lags`]: the
/// axes of [`BACKLASH_AXES`]).
pub fn backlash_columns(
    lags: &[Lag; 2],
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &SensitivityOptions,
) -> Result<Vec<(AxisName, Vec<f64>)>, GapError> {
    let cols = backlash_signatures_lagged(lags, part, points, opts).map_err(model_err)?;
    Ok(lags[0].axes.iter().copied().zip(cols).collect())
}

/// Where each axis reverses along the passes (A then B): tool-tip path length from the start of
/// A (mm).
pub fn reversals(passes: &[Pass; 2]) -> Vec<Reversal> {
    let mut out = Vec::new();
    let mut offset = 0.0;
    for p in passes {
        for axis in BACKLASH_AXES {
            let d = directions(p, axis);
            for k in 1..d.len() {
                if d[k] != d[k - 1] {
                    out.push(Reversal {
                        axis,
                        s: offset + p.s[k],
                    });
                }
            }
        }
        offset += p.s.last().copied().unwrap_or(0.0);
    }
    out.sort_by(|a, b| a.s.total_cmp(&b.s));
    out
}
