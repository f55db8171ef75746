//! `testpiece`: the command line of `shared/spec/cli.md`. Argument parsing and printing only;
//! every number comes from the library.

mod args;
mod budget;
mod compare;
mod compensation;
mod diagnose;
mod envelope;
mod forward;
mod identify;
mod info;
mod machine;
mod plan;
mod points;
mod program;
mod sensitivity;
mod simulate;
mod validate;

use std::process::ExitCode;

const HELP: &str = "\
testpiece: five-axis machine geometric errors from a measured ISO 10791-7 S-shape test piece

Usage: testpiece <command> [options]

Commands:
  info        lengths of the four measurement curves of the built-in S-shape (mm)
  sensitivity Figure-19 defect per unit of each of the 8 location errors [--mode] [--branch]
  machine     the location errors a machine is identified with (derived from what the part
              sees), the ones left out and why, and its coordinate convention [--machine M]
  forward     tool tip and axis from axis values on stdin through --machine FILE (JSON chain)
  points      the 100 built-in measurement points: id,curve,u,v,x,y,z,nx,ny,nz,h
  envelope    flank-path deviation at the points (id,curve,deviation); --surface-max per surface
  simulate    a synthetic measured part for given errors: id,curve,x,y,z,nx,ny,nz,deviation
  identify    the machine errors, groups, uncertainty and residuals; --compensation: the
              errors as the controller's kinematic description and the part after correction
  diagnose    the sim-to-real gap of a measured part: where, which effect, how far [--json]
  compare     differences of two parts' parameters with σ_d = √(σa²+σb²), flagged at 2 and 3 σ
  budget      error budget per point: design, CAM path (--cl), NC trace, machine, tool, CMM
  validate    the withheld-effect benchmark of the gap diagnosis [--cases N] [--seed S] [--json]
  plan        the measurement plan: points, predicted std, groups, detection limits; DMIS, CSV
  program     the finishing flank pass as a CL file (budget --cl) or ISO G-code in machine axes

The whole test, in order: plan (where to probe, what it will tell; DMIS for the CMM) -> program
(the finishing pass) -> machine and measure -> identify / diagnose / budget -> identify
--compensation (the errors in the controller's terms, the part after correction).

Every command accepts --help. Units are mm and rad. Errors go to stderr with a non-zero exit.
Options for all: --version prints the version.
";

fn main() -> ExitCode {
    let raw: Vec<String> = std::env::args().skip(1).collect();
    let Some(cmd) = raw.first().map(String::as_str) else {
        eprint!("{HELP}");
        return ExitCode::from(2);
    };
    let rest = &raw[1..];
    let result = match cmd {
        "--help" | "-h" | "help" => {
            print!("{HELP}");
            Ok(())
        }
        "--version" | "-V" => {
            println!("testpiece {}", testpiece::VERSION);
            Ok(())
        }
        "info" => info::run(rest),
        "machine" => machine::run(rest),
        "points" => points::run(rest),
        "envelope" => envelope::run(rest),
        "sensitivity" => sensitivity::run(rest),
        "forward" => forward::run(rest),
        "simulate" => simulate::run(rest),
        "identify" => identify::run(rest),
        "diagnose" => diagnose::run(rest),
        "validate" => validate::run(rest),
        "budget" => budget::run(rest),
        "compare" => compare::run(rest),
        "plan" => plan::run(rest),
        "program" => program::run(rest),
        other => Err(format!(
            "unknown command `{other}`; run `testpiece --help` for the list"
        )),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::FAILURE
        }
    }
}

/// True when the command was asked for its help (then the text has been printed).
pub fn wants_help(rest: &[String], text: &str) -> bool {
    if rest.iter().any(|a| a == "--help" || a == "-h") {
        print!("{text}");
        true
    } else {
        false
    }
}
