//! Physical signatures of the candidate effects of effects.md at measured points, per unit of
//! each parameter, in `physical` mode (deviation = (machined − nominal)·N, + = material left).
//!
//! Implemented here from the part geometry and the flank path: `tool_radius`, `tool_taper`
//! ([`tool`]), `overcut` ([`overcut`]), `thermal_drift` ([`thermal`], with the tool-tip path
//! length of [`path_length`]), `setup_error`, `c_index` ([`rigid`]), `pivot_length` ([`pivot`]).
//! `scale_x/y/z` and `backlash_*` use the machine's axis path and reversal model of the
//! kinematics stage ([`machine`]).

pub mod builtin;
pub mod machine;
pub mod overcut;
pub mod path_length;
pub mod pivot;
pub mod rigid;
pub mod thermal;
pub mod tool;

use nalgebra::Vector3;

/// What an effect's signature needs to know about a measured point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EffectPoint {
    /// Nominal point (mm, part frame).
    pub p: Vector3<f64>,
    /// Outward unit normal.
    pub n: Vector3<f64>,
    /// Contact height above the tool tip (mm).
    pub h: f64,
    /// Tool-tip path length from the start of A (mm).
    pub s: f64,
}
