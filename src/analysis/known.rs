//! A deviation the process explains (a CAM path, an NC trace), subtracted before the fits.

use super::error::AnalysisError;
use super::options::KnownDeviation;

/// The measured deviations minus the known ones (issue 10), checked point for point.
pub(super) fn minus_known(
    mut deviations: Vec<f64>,
    known: Option<&KnownDeviation>,
) -> Result<Vec<f64>, AnalysisError> {
    if let Some(k) = known {
        if k.values.len() != deviations.len() || k.values.iter().any(|v| !v.is_finite()) {
            return Err(AnalysisError::Known {
                what: k.source.clone(),
                values: k.values.len(),
                points: deviations.len(),
            });
        }
        for (d, v) in deviations.iter_mut().zip(&k.values) {
            *d -= v;
        }
    }
    Ok(deviations)
}

/// The sentence the reports carry when a known deviation was subtracted.
pub(super) fn known_note(k: &KnownDeviation) -> String {
    let max = k.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    format!(
        "The deviation explained by the {} (max |{:.1}| µm) was subtracted from the measurement before the identification and the gap diagnosis: it is not blamed on the machine.",
        k.source,
        max * 1e3
    )
}
