//! A generator of measured parts that is not the fitter (issue 29 item 4): parts made from the
//! physics of machining and measuring, for `testpiece validate --generator physics`
//! ([`super::physics_bench`] scores them with the shipped analysis).
//!
//! The product's own benchmark ([`super::single`]) builds linear twins from the very signature
//! columns the diagnosis fits; its figures are a ceiling. Here a part is machined: the flank path
//! of paper 000 eq. 2 timed at a feed ([`command`]), its axes following their commands through
//! position loops integrated in time ([`servo`]) and a play with a servo settling
//! ([`backlash`]), the tool pose through the exact kinematic chain with the location errors and
//! error motions as functions of axis position ([`motion`], [`crate::machine::direct`]), the head
//! warming, the flank wearing, the tool's radius and taper ([`machining`]); the surface is the
//! envelope of the tool bodies at those poses ([`envelope`]). It is then measured: placed on the
//! CMM, perhaps moving while measured, probed with a lobed probe ([`measuring`]), with CMM noise
//! (Gaussian or not), the part's own surface scatter, and repeats ([`noise`]). [`case`] draws the
//! parts.
//!
//! **Independence.** Nothing in this folder imports the candidate effects (`crate::effects`), the
//! simulator of effects by their signatures (`crate::simulate`), the diagnosis (`crate::gap`) or
//! the analysis (`crate::analysis`): it uses the part, the tool path and the machine only
//! (`tests/it/validate_physics.rs` reads these files and checks it). How much of a deviation the
//! location errors absorb is given by the caller ([`case::Visible`]).
//!
//! **Seeds.** Seeds 1-6 are the DEVELOPMENT seeds: every decision constant of the product may be
//! tuned on them. Every other seed is HELD OUT: it is scored only once every constant is frozen,
//! once, and its figures are the ones that count (101-103 first; each later round on fresh
//! seeds, BENCHMARKS.md).
//!
//! Units: mm, rad, seconds (the loops), minutes (the warm-up), mm/min (feeds).

pub mod backlash;
pub mod case;
pub mod command;
pub mod envelope;
pub mod machining;
pub mod measuring;
pub mod motion;
pub mod noise;
pub mod servo;

pub use case::{GeneratedPart, Generator, Kind, Physics};
pub use machining::{Machining, Workshop};

/// The development seeds (decision constants may be tuned on them).
pub const DEVELOPMENT_SEEDS: [u64; 3] = [1, 2, 3];
/// The held-out seeds (scored only with every constant frozen).
pub const HELD_OUT_SEEDS: [u64; 3] = [101, 102, 103];

/// Why a part could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    #[error("path step {step} mm: expected a positive finite length")]
    BadStep { step: f64 },
    #[error("the machine: {0}")]
    Machine(#[from] crate::machine::MachineError),
    #[error("no tool of the pass reaches the normal line at ({x}, {y}, {z})")]
    NoToolReaches { x: f64, y: f64, z: f64 },
}
