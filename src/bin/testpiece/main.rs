//! `testpiece`: the command line of `shared/spec/cli.md`. Argument parsing and printing only;
//! every number comes from the library. Each command is a module with its options (a clap
//! `Args` struct whose doc comments are its `--help`) and a `run` made of named steps; what
//! several commands share is in [`common`].
//!
//! The command line is native only: compiled for `wasm32` (as `wasm-pack test` builds every
//! target of the package) it is an empty program, and clap, a native-only dependency, is not
//! needed there.

#[cfg(not(target_arch = "wasm32"))]
mod budget;
#[cfg(not(target_arch = "wasm32"))]
mod common;
#[cfg(not(target_arch = "wasm32"))]
mod compare;
#[cfg(not(target_arch = "wasm32"))]
mod diagnose;
#[cfg(not(target_arch = "wasm32"))]
mod envelope;
#[cfg(not(target_arch = "wasm32"))]
mod forward;
#[cfg(not(target_arch = "wasm32"))]
mod identify;
#[cfg(not(target_arch = "wasm32"))]
mod info;
#[cfg(not(target_arch = "wasm32"))]
mod machine;
#[cfg(not(target_arch = "wasm32"))]
mod plan;
#[cfg(not(target_arch = "wasm32"))]
mod points;
#[cfg(not(target_arch = "wasm32"))]
mod program;
#[cfg(not(target_arch = "wasm32"))]
mod sensitivity;
#[cfg(not(target_arch = "wasm32"))]
mod simulate;
#[cfg(not(target_arch = "wasm32"))]
mod validate;

#[cfg(not(target_arch = "wasm32"))]
use std::error::Error as _;
#[cfg(not(target_arch = "wasm32"))]
use std::process::ExitCode;

#[cfg(not(target_arch = "wasm32"))]
use clap::error::{ContextKind, ContextValue, ErrorKind};
#[cfg(not(target_arch = "wasm32"))]
use clap::{Parser, Subcommand};

#[cfg(not(target_arch = "wasm32"))]
const AFTER_HELP: &str = "\
The whole test, in order: plan (where to probe, what it will tell; DMIS for the CMM) -> program
(the finishing pass) -> machine and measure -> identify / diagnose / budget -> identify
--compensation (the errors in the controller's terms, the part after correction).

Every command accepts --help. Units are mm and rad. Errors go to stderr with a non-zero exit.
On a terminal, identify and diagnose show the analysis's stages on one stderr line (cleared at
the end); piped or redirected, nothing is written there.";

/// five-axis machine geometric errors from a measured ISO 10791-7 S-shape test piece
#[cfg(not(target_arch = "wasm32"))]
#[derive(Parser)]
#[command(
    name = "testpiece",
    version,
    arg_required_else_help = true,
    args_override_self = true,
    after_help = AFTER_HELP
)]
#[cfg(not(target_arch = "wasm32"))]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[cfg(not(target_arch = "wasm32"))]
#[derive(Subcommand)]
enum Command {
    Info(info::Args),
    Sensitivity(sensitivity::Args),
    Machine(machine::Args),
    Forward(forward::Args),
    Points(points::Args),
    Envelope(envelope::Args),
    Simulate(simulate::Args),
    Identify(identify::Args),
    Diagnose(diagnose::Args),
    Compare(compare::Args),
    Budget(budget::Args),
    Validate(validate::Args),
    Plan(plan::Args),
    Program(program::Args),
}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return refused(e),
    };
    let result = match cli.command {
        Command::Info(a) => info::run(a),
        Command::Sensitivity(a) => sensitivity::run(a),
        Command::Machine(a) => machine::run(a),
        Command::Forward(a) => forward::run(a),
        Command::Points(a) => points::run(a),
        Command::Envelope(a) => envelope::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Identify(a) => identify::run(a),
        Command::Diagnose(a) => diagnose::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Budget(a) => budget::run(a),
        Command::Validate(a) => validate::run(a),
        Command::Plan(a) => plan::run(a),
        Command::Program(a) => program::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::FAILURE
        }
    }
}

/// What clap stops at: help and version (stdout, success), usage errors (stderr, exit 2). A value
/// a parser of [`common`] refused is reported as ``error: --option `value`: what was expected``.
#[cfg(not(target_arch = "wasm32"))]
fn refused(e: clap::Error) -> ExitCode {
    if e.kind() == ErrorKind::ValueValidation {
        if let (Some(ContextValue::String(arg)), Some(ContextValue::String(value)), Some(why)) = (
            e.get(ContextKind::InvalidArg),
            e.get(ContextKind::InvalidValue),
            e.source(),
        ) {
            let option = arg.split(' ').next().unwrap_or(arg);
            eprintln!("error: {option} `{value}`: {why}");
            return ExitCode::from(2);
        }
    }
    e.exit()
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use clap::CommandFactory;

    /// clap's own consistency check of every command's definition (names, defaults, value names).
    #[test]
    fn definitions_are_consistent() {
        super::Cli::command().debug_assert();
    }
}

/// The command line is native only (see the crate doc).
#[cfg(target_arch = "wasm32")]
fn main() {}
