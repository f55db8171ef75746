//! The signatures of the candidate effects of `shared/spec/effects.md` and the part model they
//! are evaluated on (the effects themselves, with their ids, parameters and units, are
//! [`crate::parameter::Effect`]).
//!
//! - [`effect`]: each effect's signature formula;
//! - [`data`]: the plain-data inputs of a diagnosis ([`GapInput`]: deviations, point metadata,
//!   the baseline design and the candidates' signatures);
//! - the part model: where the columns of each signature come from. [`builtin`] computes what the
//!   formulas need from the geometry (effect points, envelope, tool-tip path length of
//!   [`path_length`]), [`machine`] from the machine's axis path (backlash and scale columns, axis
//!   reversals); what depends only on the settings is [`path_model`]; it, the machine's error
//!   set and the built-in points' model are built once by [`prepared`] (the prepared settings,
//!   a value the caller holds and passes);
//! - [`catalogue`]: a machine's own effect catalogue; [`location_equivalent`]: candidates that
//!   are a location error of the machine under another name; [`nuisance`]: shapes no candidate
//!   names, for the model spread;
//! - [`error`]: the one error type of the part model and the diagnosis built on it.

pub mod builtin;
pub mod catalogue;
pub mod data;
pub mod effect;
pub mod error;
pub mod family;
pub mod location_equivalent;
pub mod machine;
pub mod nuisance;
pub mod path_length;
pub mod path_model;
pub mod prepared;

pub use data::{Candidate, Family, GapInput, NamedColumns, PointMeta, Reversal};
pub use effect::EffectPoint;
pub use error::GapError;
