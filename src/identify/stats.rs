//! Residual statistics: RMS, max |r|, and the metrics of paper 001 eq. 15-17.
//!
//! With measured `y_i`, fitted `y'_i`, residual `r_i = y_i - y'_i` (mm) over `n` points:
//! - `mad` = (1/n) Σ |r_i| (eq. 15, E_MAD);
//! - `mape` = (100/m) Σ |r_i| / |y_i| in % (eq. 16, E_MAP). Eq. 16 divides by `y_i`; our
//!   deviations change sign, so we divide by `|y_i|`, and only over the `m` points with
//!   `|y_i| >= floor` (default 0.003 mm = the CMM repeatability range R0 of paper 000 §6: a measured
//!   deviation smaller than the CMM's repeatability is no meaningful denominator). `None` when `m = 0`;
//! - `rmse` = √((1/n) Σ r_i²) (eq. 17, R_MES), which is also `rms`;
//! - `max_abs` = max |r_i|.

use serde::{Deserialize, Serialize};

use super::solve;

/// Statistics of a set of residuals (mm, except `mape` in %).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResidualStats {
    /// Number of points.
    pub n: usize,
    /// √(mean r²) (mm); the same number as `rmse`.
    pub rms: f64,
    /// max |r| (mm).
    pub max_abs: f64,
    /// Mean |r| (mm), paper 001 eq. 15.
    pub mad: f64,
    /// Mean |r|/|y| over the points with |y| >= `mape_floor`, in %, paper 001 eq. 16.
    pub mape: Option<f64>,
    /// Number of points that entered `mape`.
    pub mape_points: usize,
    /// √(mean r²) (mm), paper 001 eq. 17.
    pub rmse: f64,
}

impl ResidualStats {
    /// Statistics of `measured - fitted`. Empty input gives zeros.
    pub fn of(measured: &[f64], fitted: &[f64], mape_floor: f64) -> Self {
        let n = measured.len().min(fitted.len());
        if n == 0 {
            return ResidualStats {
                n: 0,
                rms: 0.0,
                max_abs: 0.0,
                mad: 0.0,
                mape: None,
                mape_points: 0,
                rmse: 0.0,
            };
        }
        let r: Vec<f64> = (0..n).map(|i| measured[i] - fitted[i]).collect();
        let mut sa = 0.0;
        let mut sp = 0.0;
        let mut m = 0;
        for (i, ri) in r.iter().enumerate() {
            sa += ri.abs();
            if measured[i].abs() >= mape_floor && measured[i] != 0.0 {
                sp += ri.abs() / measured[i].abs();
                m += 1;
            }
        }
        let rms = solve::rms(&r);
        let max_abs = solve::max_abs(&r);
        ResidualStats {
            n,
            rms,
            max_abs,
            mad: sa / n as f64,
            mape: (m > 0).then(|| 100.0 * sp / m as f64),
            mape_points: m,
            rmse: rms,
        }
    }
}
