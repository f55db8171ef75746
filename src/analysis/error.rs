//! The one error type of an analysis: each stage's own message.

use crate::cmm::CmmError;
use crate::effects::GapError;
use crate::identify::IdentifyError;
use crate::measurement::repeat::RepeatError;
use crate::sensitivity::SensitivityError;
use crate::settings::NoiseError;
use crate::simulate::SimulateError;

/// Failures of an analysis, each with the stage's own message.
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    #[error("{0}")]
    File(#[from] CmmError),
    #[error("sensitivity: {0}")]
    Sensitivity(#[from] SensitivityError),
    #[error("identification: {0}")]
    Identify(#[from] IdentifyError),
    #[error("L0 = {0} mm is not a positive finite length")]
    BadL0(f64),
    #[error("feed = {0} mm/min is not a positive finite feed")]
    BadFeed(f64),
    #[error(transparent)]
    Noise(#[from] NoiseError),
    #[error("exact model: {0}")]
    Exact(#[from] SimulateError),
    #[error("exact-model refinement: {0}")]
    Refine(IdentifyError),
    #[error("{0}")]
    Correction(GapError),
    #[error("{0}")]
    Repeat(#[from] RepeatError),
    #[error("the CMM noise is given twice: {given} and {repeats} repeat measurements of the part; give the figure or the repeats")]
    SigmaAndRepeats { given: String, repeats: usize },
    #[error(
        "known deviation ({what}): {values} values for {points} matched points, or not finite"
    )]
    Known {
        what: String,
        values: usize,
        points: usize,
    },
    #[error("no diagnosis: {reason}")]
    NotDiagnosed { reason: GapError },
    #[error(
        "the settings were prepared for {prepared}, the analysis asks for {asked}: prepare its own"
    )]
    OtherSettings { prepared: String, asked: String },
}
