//! Repeat measurements of one part: the CMM noise from their differences (pure error) and the
//! lack-of-fit test that then separates structure from noise without any estimator.
//!
//! The same `n` points measured `k ≥ 2` times, `y_ij = μ_i + ε_ij` with `ε ~ N(0, σ²)`
//! independent between measurements (the part does not change between them; only the CMM
//! probes again). Then (Draper & Smith, *Applied Regression Analysis*, §2.1, "pure error"):
//! - `SS_pe = Σ_i Σ_j (y_ij − ȳ_i)²` with `n(k − 1)` degrees of freedom, and
//!   `σ̂² = SS_pe / (n(k − 1))` estimates σ² whatever the part's shape (the mean `ȳ_i`
//!   absorbs every structure, a machine error, an effect or a waviness alike);
//! - the analysis fits the means `ȳ_i`, whose noise has `σ_mean = σ̂ / √k`;
//! - lack of fit: with `RSS` the residual sum of squares of a fit of `p` (rank) columns to the
//!   means, `F = (RSS / (n − p)) / σ̂²_mean` against `F(n − p, n(k − 1))`; a small p-value says
//!   the residual holds more than the CMM's repeatability.
//!
//! Re-probing the same points does not resample the part's own point-to-point scatter (its
//! roughness and local form at each point are measured again, identically), so the pure error
//! is the CMM's share only, a lower bound of the noise of a mean: `σ² = σ²_part + σ²_CMM / k`.
//! The analysis passes `σ̂_mean` to the diagnosis as the CMM's floor, and the diagnosis
//! estimates the total from the means' residual ([`crate::measurement::noise`]); the lack of
//! fit against the pure error alone then rejects on any real part and is reported as such.
//!
//! Points are paired by their id in the files; every file must hold the same ids (a point
//! measured in some files only is refused, naming it: it cannot enter the pure error, and a
//! mean of fewer measurements would have another σ). The same id must be the same place: the
//! nominal positions (feet of the projections) of a pair may differ by at most
//! [`SAME_POINT_MM`].

use std::collections::BTreeMap;

use serde::Serialize;

use crate::numerics::stats;

/// Largest distance (mm) between the nominal positions of the same point id in two files.
pub const SAME_POINT_MM: f64 = 0.5;

/// One measurement of the part: point ids, their nominal positions (mm) and deviations (mm).
#[derive(Debug, Clone, Copy)]
pub struct Measurement<'a> {
    pub name: &'a str,
    pub ids: &'a [String],
    pub positions: &'a [[f64; 3]],
    pub deviations: &'a [f64],
}

/// Why repeat measurements could not be combined.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RepeatError {
    #[error("repeat {file}: the point id `{id}` appears {count} times; each point once")]
    DuplicateId {
        file: String,
        id: String,
        count: usize,
    },
    #[error("repeat {file}: {} point(s) of {first} are not in it: {}; every repeat measures the same points (leave them out of {first} too, or measure them again)", .ids.len(), .ids.join(", "))]
    Missing {
        file: String,
        first: String,
        ids: Vec<String>,
    },
    #[error("repeat {file}: {} point(s) are not in {first}: {}; every repeat measures the same points", .ids.len(), .ids.join(", "))]
    Extra {
        file: String,
        first: String,
        ids: Vec<String>,
    },
    #[error("repeat {file}: point `{id}` lies {distance:.3} mm from the point `{id}` of {first} (at most {limit} mm): not the same place on the part")]
    Moved {
        file: String,
        first: String,
        id: String,
        distance: f64,
        limit: f64,
    },
    #[error("pure error needs at least 2 measurements of the part, got {0}")]
    TooFew(usize),
}

/// The point with the largest spread over the repeats.
#[derive(Debug, Clone, Serialize)]
pub struct Spread {
    pub id: String,
    /// `max_j y_ij − min_j y_ij` (mm).
    pub range: f64,
    /// Its standard deviation over the repeats in units of the pooled σ.
    pub ratio: f64,
}

/// σ from repeat measurements.
#[derive(Debug, Clone, Serialize)]
pub struct PureError {
    /// File names, the first one's point order is kept.
    pub files: Vec<String>,
    /// Measurements per point (`k`).
    pub repeats: usize,
    /// Points (`n`).
    pub points: usize,
    /// σ of one measurement, `√(SS_pe / (n(k − 1)))` (mm).
    pub sigma: f64,
    /// Degrees of freedom `n(k − 1)`.
    pub dof: usize,
    /// σ of the mean of the `k` measurements, `σ / √k` (mm): the σ the analysis uses.
    pub sigma_mean: f64,
    /// The point whose measurements differ the most.
    pub largest: Option<Spread>,
    /// The mean deviation of each point, in the first file's order (mm).
    #[serde(skip)]
    pub mean: Vec<f64>,
}

/// Combines `k ≥ 2` measurements of the same points (paired by id, module doc).
pub fn pure_error(parts: &[Measurement]) -> Result<PureError, RepeatError> {
    let [first, rest @ ..] = parts else {
        return Err(RepeatError::TooFew(0));
    };
    if rest.is_empty() {
        return Err(RepeatError::TooFew(1));
    }
    fn index_of<'m>(m: &Measurement<'m>) -> Result<BTreeMap<&'m str, usize>, RepeatError> {
        let mut map = BTreeMap::new();
        for (i, id) in m.ids.iter().enumerate() {
            if map.insert(id.as_str(), i).is_some() {
                return Err(RepeatError::DuplicateId {
                    file: m.name.to_string(),
                    id: id.clone(),
                    count: m.ids.iter().filter(|x| *x == id).count(),
                });
            }
        }
        Ok(map)
    }
    let first_index = index_of(first)?;
    let n = first.ids.len();
    let k = parts.len();
    // values[i][j]: point i (first file's order), measurement j
    let mut values: Vec<Vec<f64>> = first.deviations.iter().map(|&d| vec![d]).collect();
    for m in rest {
        let index = index_of(m)?;
        let missing: Vec<String> = first
            .ids
            .iter()
            .filter(|id| !index.contains_key(id.as_str()))
            .cloned()
            .collect();
        if !missing.is_empty() {
            return Err(RepeatError::Missing {
                file: m.name.to_string(),
                first: first.name.to_string(),
                ids: missing,
            });
        }
        let extra: Vec<String> = m
            .ids
            .iter()
            .filter(|id| !first_index.contains_key(id.as_str()))
            .cloned()
            .collect();
        if !extra.is_empty() {
            return Err(RepeatError::Extra {
                file: m.name.to_string(),
                first: first.name.to_string(),
                ids: extra,
            });
        }
        for (i, id) in first.ids.iter().enumerate() {
            let j = index[id.as_str()];
            let (a, b) = (first.positions[i], m.positions[j]);
            let distance =
                ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
            if distance.is_nan() || distance > SAME_POINT_MM {
                return Err(RepeatError::Moved {
                    file: m.name.to_string(),
                    first: first.name.to_string(),
                    id: id.clone(),
                    distance,
                    limit: SAME_POINT_MM,
                });
            }
            values[i].push(m.deviations[j]);
        }
    }
    let mean: Vec<f64> = values
        .iter()
        .map(|v| v.iter().sum::<f64>() / k as f64)
        .collect();
    let ss: Vec<f64> = values
        .iter()
        .zip(&mean)
        .map(|(v, m)| v.iter().map(|y| (y - m).powi(2)).sum())
        .collect();
    let dof = n * (k - 1);
    let sigma = if dof > 0 {
        (ss.iter().sum::<f64>() / dof as f64).sqrt()
    } else {
        0.0
    };
    let largest = (0..n).max_by(|&a, &b| ss[a].total_cmp(&ss[b])).map(|i| {
        let (lo, hi) = values[i]
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        Spread {
            id: first.ids[i].clone(),
            range: hi - lo,
            ratio: if sigma > 0.0 {
                (ss[i] / (k - 1) as f64).sqrt() / sigma
            } else {
                0.0
            },
        }
    });
    Ok(PureError {
        files: parts.iter().map(|m| m.name.to_string()).collect(),
        repeats: k,
        points: n,
        sigma,
        dof,
        sigma_mean: sigma / (k as f64).sqrt(),
        largest,
        mean,
    })
}

/// The lack-of-fit test of a fit to the means against the pure error.
#[derive(Debug, Clone, Serialize)]
pub struct LackOfFit {
    /// `(RSS / (n − p)) / σ²_mean`.
    pub f: f64,
    /// `n − p`.
    pub dof_fit: usize,
    /// `n(k − 1)`.
    pub dof_pure: usize,
    /// `P(F(n − p, n(k − 1)) > f)`.
    pub p_value: f64,
}

/// The lack-of-fit test of a fit with residual sum of squares `rss` (mm²) and rank `p` to `n`
/// of the means (`n = pe.points` unless some were left out of the fit).
pub fn lack_of_fit(pe: &PureError, rss: f64, n: usize, rank: usize) -> LackOfFit {
    let dof_fit = n.saturating_sub(rank);
    let var_mean = pe.sigma_mean * pe.sigma_mean;
    let f = if dof_fit > 0 && var_mean > 0.0 {
        rss / dof_fit as f64 / var_mean
    } else {
        f64::NAN
    };
    LackOfFit {
        f,
        dof_fit,
        dof_pure: pe.dof,
        p_value: if f.is_finite() {
            stats::f_sf(f, dof_fit as f64, pe.dof as f64)
        } else {
            1.0
        },
    }
}

/// One sentence on the pure error and the lack of fit of the baseline (location errors alone).
pub fn sentence(pe: &PureError, l: &LackOfFit) -> String {
    let mut s = format!(
        "Noise: the CMM's repeatability σ = {:.2} µm from {} repeat measurements of the {} points \
         (pure error, {} degrees of freedom): {:.2} µm for their mean, which is analysed. \
         Probing again does not resample the part's own point-to-point scatter, so this is a \
         lower bound of the noise: the diagnosis adds the part's scatter, estimated from the data.",
        pe.sigma * 1e3,
        pe.repeats,
        pe.points,
        pe.dof,
        pe.sigma_mean * 1e3
    );
    if let Some(l) = pe.largest.as_ref().filter(|l| l.ratio > 3.0) {
        s += &format!(
            " Point {} differs the most between the measurements ({:.1} µm, {:.1} σ): a probing \
             fault in one of them inflates σ.",
            l.id,
            l.range * 1e3,
            l.ratio
        );
    }
    s += &format!(
        " Lack of fit of the location errors against the pure error alone: F = {:.2} on ({}, {}) \
         dof, p = {:.2e}: {}.",
        l.f,
        l.dof_fit,
        l.dof_pure,
        l.p_value,
        if l.p_value < 0.05 {
            "the residual holds more than the CMM's repeatability (structure, or the part's own \
             scatter: the diagnosis tells which)"
        } else {
            "the residual is consistent with the CMM's repeatability"
        }
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::random::Sampler;

    fn ids(n: usize) -> Vec<String> {
        (1..=n).map(|i| i.to_string()).collect()
    }

    #[test]
    fn pure_error_ignores_any_shape_and_recovers_sigma() {
        // 3 measurements of 400 points whose shape is a large arbitrary structure: σ̂ is the
        // noise's σ = 2 µm within its sampling error (√(1/(2·800)) ≈ 2.5 %; 4 sd = 10 %).
        let n = 400;
        let id = ids(n);
        let pos: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.0, 0.0]).collect();
        let shape: Vec<f64> = (0..n).map(|i| 0.05 * (i as f64 / 7.0).sin()).collect();
        let mut rng = Sampler::new(4);
        let ys: Vec<Vec<f64>> = (0..3)
            .map(|_| shape.iter().map(|s| s + 0.002 * rng.normal()).collect())
            .collect();
        let ms: Vec<Measurement> = ys
            .iter()
            .map(|y| Measurement {
                name: "p",
                ids: &id,
                positions: &pos,
                deviations: y,
            })
            .collect();
        let pe = pure_error(&ms).unwrap();
        assert_eq!((pe.repeats, pe.points, pe.dof), (3, 400, 800));
        assert!((pe.sigma / 0.002 - 1.0).abs() < 0.1, "{}", pe.sigma);
        assert!((pe.sigma_mean - pe.sigma / 3f64.sqrt()).abs() < 1e-15);
        // The mean is the shape to within σ/√3.
        let err = pe
            .mean
            .iter()
            .zip(&shape)
            .map(|(m, s)| (m - s).abs())
            .fold(0.0, f64::max);
        assert!(err < 5.0 * 0.002 / 3f64.sqrt(), "{err}");
        // Lack of fit of a model that explains nothing: F huge, p ≈ 0.
        let rss: f64 = pe.mean.iter().map(|m| m * m).sum();
        let l = lack_of_fit(&pe, rss, n, 0);
        assert!(l.f > 100.0 && l.p_value < 1e-12, "{l:?}");
        // Of the true shape: F ≈ 1.
        let rss: f64 = pe
            .mean
            .iter()
            .zip(&shape)
            .map(|(m, s)| (m - s).powi(2))
            .sum();
        let l = lack_of_fit(&pe, rss, n, 0);
        assert!(l.p_value > 0.01, "{l:?}");
    }

    #[test]
    fn pairs_by_id_in_any_order_and_names_what_does_not_pair() {
        let a_ids = ids(4);
        let pos = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
        let a = Measurement {
            name: "a.csv",
            ids: &a_ids,
            positions: &pos,
            deviations: &[0.001, 0.002, 0.003, 0.004],
        };
        // the same points, reversed order
        let b_ids: Vec<String> = a_ids.iter().rev().cloned().collect();
        let b_pos: Vec<[f64; 3]> = pos.iter().rev().copied().collect();
        let b = Measurement {
            name: "b.csv",
            ids: &b_ids,
            positions: &b_pos,
            deviations: &[0.004, 0.003, 0.002, 0.003],
        };
        let pe = pure_error(&[a, b]).unwrap();
        // point 1: 0.001 and 0.003 → mean 0.002, ss 2e-6; others 0
        assert!((pe.mean[0] - 0.002).abs() < 1e-15);
        assert!((pe.mean[3] - 0.004).abs() < 1e-15);
        assert!((pe.sigma - (2e-6f64 / 4.0).sqrt()).abs() < 1e-15);
        assert_eq!(pe.largest.as_ref().unwrap().id, "1");
        // a point missing from the repeat
        let c = Measurement {
            name: "c.csv",
            ids: &a_ids[..3],
            positions: &pos[..3],
            deviations: &[0.0; 3],
        };
        let e = pure_error(&[a, c]).unwrap_err();
        assert_eq!(
            e,
            RepeatError::Missing {
                file: "c.csv".into(),
                first: "a.csv".into(),
                ids: vec!["4".into()]
            }
        );
        assert!(
            e.to_string().contains("`4`") || e.to_string().contains(": 4;"),
            "{e}"
        );
        // the same id elsewhere on the part
        let moved = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 2.0, 0.0]];
        let d = Measurement {
            positions: &moved,
            name: "d.csv",
            ..a
        };
        assert!(matches!(
            pure_error(&[a, d]),
            Err(RepeatError::Moved { ref id, .. }) if id == "4"
        ));
        assert_eq!(pure_error(&[a]).unwrap_err(), RepeatError::TooFew(1));
    }
}
