//! What a fit estimates, by kind: the typed id of a parameter with its unit ([`id`]: a machine
//! error, the tool-radius term, an effect's parameter, a part's term, a user's column), the
//! candidate effects of spec/effects.md by id ([`effect`]: each with its parameters and their
//! units, as effects.md defines them) and the errors of naming them in text that comes in
//! ([`error`]).
//!
//! Units are set here, where a parameter is defined, and travel with it (mm, rad: the
//! machine's [`crate::machine::Unit`]); nothing reads a unit from a name.

pub mod effect;
pub mod error;
pub mod id;

pub use effect::{backlash_axes, Effect, Shape, BACKLASH_AXES, SCALE_AXES};
pub use error::ParameterError;
pub use id::{ParamId, ParamKind, PartTerm, TOOL_RADIUS};
