//! The settings an analysis and a plan share, as typed values checked once: the machine
//! ([`machine_choice`]) and the CMM noise ([`cmm_noise`]).

pub mod cmm_noise;
pub mod feed;
pub mod machine_choice;

pub use cmm_noise::{CmmNoise, NoiseError, NoiseKind};
pub use machine_choice::{MachineChoice, MachineInfo};
