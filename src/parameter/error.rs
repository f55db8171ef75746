//! The errors of naming a parameter or an effect in text that comes in: every message carries the
//! text found and what is known.

use thiserror::Error;

use super::Effect;

/// A name that is not an effect or a parameter.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ParameterError {
    #[error("unknown effect id `{0}` (`testpiece machine` lists the ids)")]
    UnknownEffect(String),
    #[error("`{key}`: `{effect}` has the parameters {known}; write `{effect}.<parameter>`")]
    ParameterNeeded {
        key: String,
        effect: Effect,
        known: String,
    },
    #[error("`{key}`: `{effect}` has no parameter `{name}` (its parameters: {known})")]
    UnknownParameter {
        key: String,
        effect: Effect,
        name: String,
        known: String,
    },
    #[error(
        "`{name}` is not a parameter name (expected a machine error such as EX0B, dR, or an \
         effect's parameter such as tool_taper.g)"
    )]
    NotAParameter { name: String },
}
