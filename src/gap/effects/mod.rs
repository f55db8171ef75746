//! The part model of a diagnosis: where the columns of each [`super::Effect`]'s signature come
//! from. The formulas live with the effect ([`super::effect`]); this module computes what they
//! need from the geometry ([`builtin`]: effect points, envelope, tool-tip path length of
//! [`path_length`]) and from the machine's axis path ([`machine`]: backlash and scale columns,
//! axis reversals). What depends only on the settings is [`path_model`]; both it and whole part
//! models are computed once per settings (and points) and kept by [`cache`].

pub mod builtin;
pub mod cache;
pub mod catalogue;
pub mod location_equivalent;
pub mod machine;
pub mod path_length;
pub mod path_model;

pub use super::effect::EffectPoint;
