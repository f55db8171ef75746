//! The errors of a measurement plan, each with the offending values.

/// Why a measurement plan could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    #[error(
        "{per_curve} points per curve: expected 1 to {max} (4 curves: A_Z11, A_Z25, B_Z11, B_Z25)"
    )]
    PointsPerCurve { per_curve: usize, max: usize },
    #[error("{total} points in all: expected 4 to {max} (spread over the 4 curves)")]
    TotalPoints { total: usize, max: usize },
    #[error(transparent)]
    Noise(#[from] crate::settings::NoiseError),
    #[error("L0 = {0} mm is not a positive finite length")]
    BadL0(f64),
    #[error("design at the plan's points: {0}")]
    Design(crate::analysis::AnalysisError),
    #[error("predicted identification: {0}")]
    Identify(crate::identify::IdentifyError),
    #[error("effect signatures at the plan's points: {0}")]
    Effects(crate::effects::GapError),
    #[error(
        "probe path: no way up from the touch of point {id}: moving out along its normal by up \
         to {escape} mm, the probe does not keep {clearance} mm from the part on the way up"
    )]
    ProbeNoWayUp {
        id: usize,
        escape: f64,
        clearance: f64,
    },
    #[error(
        "probe path: the clearance move from point {from} to point {to} comes within \
         {distance:.3} mm of the part (expected at least {clearance} mm)"
    )]
    ProbeMove {
        from: usize,
        to: usize,
        distance: f64,
        clearance: f64,
    },
    #[error("DMIS line {line}: {message} (found `{text}`)")]
    Dmis {
        line: usize,
        message: &'static str,
        text: String,
    },
}
