//! The withheld-effect benchmark of the gap diagnosis (`testpiece validate`): simulated parts
//! whose answer is known, diagnosed with the effect withheld from the baseline. A product
//! feature beside the pipeline, not a stage of it: it builds parts with [`crate::numerics::random`] and
//! calls [`crate::gap::diagnose`] as any user of the diagnosis would.
//!
//! - [`single`]: one effect of effects.md (or none, or an out-of-list shape) per part;
//! - [`pairs`]: two effects at once (`validate --pairs`);
//! - [`parameter_error`]: the identified location errors against the simulated truth;
//! - [`shapes`]: the out-of-list shapes (waviness, bump, short wave, gouge, straightness, cyclic C);
//! - [`conditions`]: one table of the lab's conditions (noise, spikes, layouts, shapes, ...);
//! - [`physics`] and [`physics_bench`]: parts made by the physics of machining and measuring, not
//!   by the fitter's signatures (`validate --generator physics`).

pub mod conditions;
pub mod pairs;
pub mod parameter_error;
pub mod physics;
pub mod physics_bench;
pub mod shapes;
pub mod single;

/// Why a validation run stopped, with the stage's own message.
#[derive(Debug, thiserror::Error)]
pub enum ValidateError {
    #[error("{0}")]
    Model(#[from] crate::effects::GapError),
    #[error("case {case}: {source}")]
    Analysis {
        case: usize,
        source: crate::analysis::AnalysisError,
    },
    #[error("case {case}: no diagnosis was made ({reason})")]
    NotDiagnosed { case: usize, reason: String },
    #[error("the simulated machine: {0}")]
    Simulate(#[from] crate::simulate::SimulateError),
    #[error("no two candidates can be told apart on this part")]
    NoPairs,
    #[error("physics part: {0}")]
    Physics(#[from] physics::PhysicsError),
    #[error("unknown condition `{name}` (known: {})", CONDITIONS.join(", "))]
    UnknownCondition { name: String },
}

pub use conditions::{conditions_table, run_conditions, ConditionsReport, CONDITIONS};
pub use pairs::{pairs_table, validate_pairs, PairCase, PairValidation};
pub use parameter_error::{answer_error, AnswerError, ErrorComparison, ErrorSummary};
pub use single::{
    effect_parameters, exact_machine_part, exact_machine_part_on, machine_errors, table, validate,
    validate_with, MachinePart, ParameterErrors, ValidateOptions, ValidationModel,
};
