//! The withheld-effect benchmark of the gap diagnosis (`testpiece validate`): simulated parts
//! whose answer is known, diagnosed with the effect withheld from the baseline. A product
//! feature beside the pipeline, not a stage of it: it builds parts with [`crate::random`] and
//! calls [`crate::gap::diagnose`] as any user of the diagnosis would.
//!
//! - [`single`]: one effect of effects.md (or none, or an out-of-list shape) per part;
//! - [`pairs`]: two effects at once (`validate --pairs`);
//! - [`parameter_error`]: the identified location errors against the simulated truth.

pub mod pairs;
pub mod parameter_error;
pub mod single;

pub use pairs::{pairs_table, validate_pairs, PairCase, PairValidation};
pub use parameter_error::{answer_error, AnswerError, ErrorComparison, ErrorSummary};
pub use single::{
    effect_parameters, machine_errors, table, validate, validate_with, ParameterErrors,
    ValidateOptions, ValidationModel,
};
