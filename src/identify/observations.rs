//! Measured deviations at the rows of a design: ids, curve labels, optional weights.

use serde::{Deserialize, Serialize};

use super::IdentifyError;

/// The measured side of the fit: one entry per design row.
///
/// `deviation` is `(measured - nominal)·N` in mm (+ = material left, - = overcut).
/// `weights` are relative weights `w_i = 1/σ_i²` up to a common factor (1 if absent); a
/// weight 0 excludes the point (it is then listed in `points_excluded`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Observations {
    /// Point ids as in the file.
    pub ids: Vec<String>,
    /// Curve label of each point (`A_Z11`, ...); used for per-curve residual statistics.
    pub curves: Vec<String>,
    /// Measured deviation (mm).
    pub deviation: Vec<f64>,
    /// Relative weights (>= 0), or `None` for all 1.
    pub weights: Option<Vec<f64>>,
}

impl Observations {
    /// Ids `1..=n`, one curve label `all`, unit weights.
    pub fn plain(deviation: Vec<f64>) -> Self {
        let n = deviation.len();
        Observations {
            ids: (1..=n).map(|i| i.to_string()).collect(),
            curves: vec!["all".to_string(); n],
            deviation,
            weights: None,
        }
    }

    /// Ids and curve labels given.
    pub fn new(ids: Vec<String>, curves: Vec<String>, deviation: Vec<f64>) -> Self {
        Observations {
            ids,
            curves,
            deviation,
            weights: None,
        }
    }

    /// Sets relative weights.
    pub fn with_weights(mut self, weights: Vec<f64>) -> Self {
        self.weights = Some(weights);
        self
    }

    /// The rows `rows` get weight 0 (left out of the fit and listed in `points_excluded`), the
    /// others keep theirs; no change when `rows` is empty.
    pub fn excluding(self, rows: &[usize]) -> Self {
        if rows.is_empty() {
            return self;
        }
        let w = (0..self.len())
            .map(|i| {
                if rows.contains(&i) {
                    0.0
                } else {
                    self.weight(i)
                }
            })
            .collect();
        self.with_weights(w)
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.deviation.len()
    }

    /// True when there is no point.
    pub fn is_empty(&self) -> bool {
        self.deviation.is_empty()
    }

    /// The weight of point `i` (1 when no weights are given).
    pub fn weight(&self, i: usize) -> f64 {
        self.weights.as_ref().map_or(1.0, |w| w[i])
    }

    /// Checks lengths against `rows` and that values and weights are finite (weights >= 0).
    pub fn validate(&self, rows: usize) -> Result<(), IdentifyError> {
        let lens = [
            ("deviations", self.deviation.len()),
            ("point ids", self.ids.len()),
            ("curve labels", self.curves.len()),
        ];
        for (what, found) in lens {
            if found != rows {
                return Err(IdentifyError::LengthMismatch {
                    what,
                    found,
                    expected: rows,
                });
            }
        }
        if let Some(w) = &self.weights {
            if w.len() != rows {
                return Err(IdentifyError::LengthMismatch {
                    what: "weights",
                    found: w.len(),
                    expected: rows,
                });
            }
            for (i, &v) in w.iter().enumerate() {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(IdentifyError::BadWeight {
                        id: self.ids[i].clone(),
                        value: v,
                    });
                }
            }
        }
        for (i, &v) in self.deviation.iter().enumerate() {
            if !v.is_finite() {
                return Err(IdentifyError::NonFiniteDeviation {
                    id: self.ids[i].clone(),
                    value: v,
                });
            }
        }
        Ok(())
    }
}
