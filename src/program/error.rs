//! The errors of a part program, each with the offending values.

/// Why a part program could not be made or read back.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ProgramError {
    #[error("chord tolerance {0} mm: expected a finite number in [1e-5, 1] mm")]
    BadTolerance(f64),
    #[error("feed {0} mm/min: expected a positive finite number")]
    BadFeed(f64),
    #[error("L0 = {0} mm is not a positive finite length")]
    BadL0(f64),
    #[error("spindle speed {0} 1/min: expected a number in [1, 100000]")]
    BadSpindle(f64),
    #[error("tool number {0}: expected 1 to 99")]
    BadTool(u32),
    #[error("the {0} dialect has no tool-centre-point mode this program can use (offered: fanuc G43.4, sinumerik TRAORI, heidenhain FUNCTION TCPM)")]
    NoTcp(&'static str),
    #[error("inverse kinematics of surface {surface}: {source}")]
    Kinematics {
        surface: char,
        source: crate::sensitivity::SensitivityError,
    },
    #[error(
        "surface {surface}: {positions} positions and the chord error is still {error:e} mm > \
         {tolerance} mm between u = {u0} and u = {u1} (the axes turn too fast there)"
    )]
    NotConverged {
        surface: char,
        positions: usize,
        error: f64,
        tolerance: f64,
        u0: f64,
        u1: f64,
    },
    #[error("G-code line {line}: the tool tip of the TCP block has no machine axes: {source}")]
    TipKinematics {
        line: usize,
        source: crate::machine::MachineError,
    },
    #[error("G-code line {line}: {message} (found `{text}`)")]
    GCode {
        line: usize,
        message: &'static str,
        text: String,
    },
}
