//! `testpiece program`: the finishing flank pass as a CL file or ISO G-code (issue 19, step 2).

use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::Branch;
use testpiece::program::{program, ProgramOptions};
use testpiece::settings::MachineChoice;

use crate::common::{branch, machine, mm, number};

/// the finishing flank pass as a CL file (budget --cl) or ISO G-code in machine axes
///
/// The finishing flank pass of both walls of the S-shape (surface A, then B, each in increasing u),
/// a flat end mill of diameter 20 mm with its tip on the flank path of paper 000 eq. 2 and its
/// axis on the ruling. ROUGHING IS NOT INCLUDED (remove the stock before this pass); the header
/// comments say so and name the machine, L0, tool, branch, tolerance and software version.
///
/// Positions are placed so that, between two of them, (1) the scallop R - sqrt(R² - s²/4) of the
/// tip step s (paper 000 eq. 7), (2) the chord of the tip path and (3) the controller's linear
/// interpolation of the machine axes (tool tip and top of the flank) all stay within --tolerance.
/// The axis values are the inverse kinematics of the analysis with the chosen B branch, through the
/// vertical zone as the analysis assumes.
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the chain, as for `identify`: paper000 (B head / C table), paper001 (A-B head), paper002
    /// (B-C tilting table)
    #[arg(long, value_name = "paper000|paper001|paper002", default_value = "paper000", value_parser = machine, verbatim_doc_comment)]
    machine: MachineChoice,
    /// the pivot-to-tip length (mm)
    #[arg(long, value_name = "MM", default_value_t = PAPER000_L0, value_parser = mm, allow_negative_numbers = true)]
    l0: f64,
    /// the B-axis branch: signed (the analysis's) or positive (B >= 0)
    #[arg(long, value_name = "signed|positive", default_value = "signed", value_parser = branch)]
    branch: Branch,
    /// chord tolerance (mm; default 0.001)
    #[arg(long, value_name = "MM", value_parser = number, allow_negative_numbers = true)]
    tolerance: Option<f64>,
    /// cl: APT CL data, GOTO/x,y,z,i,j,k per position (tool tip, unit tool axis, part frame, mm),
    /// the format `testpiece budget FILE --cl` reads; gcode: ISO G-code, G01 X Y Z B C (X Y Z A B
    /// on paper001's A-B head) in the chain's machine axes, mm and degrees, no RTCP; G00 approach
    /// and retract 50 mm along the tool axis at each surface's start and end
    #[arg(long, value_name = "cl|gcode", default_value = "cl", value_parser = format, verbatim_doc_comment)]
    format: Format,
    /// feed of the pass (mm/min; default 1000)
    #[arg(long, value_name = "MM_PER_MIN", value_parser = number, allow_negative_numbers = true)]
    feed: Option<f64>,
    /// {settings, machine, passes: [{surface, positions: [{u, tip, axis, axes, singular}],
    /// max_interval_error, max_step, max_scallop}], notes}
    #[arg(long, verbatim_doc_comment)]
    json: bool,
}

/// `--format cl|gcode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Cl,
    Gcode,
}

fn format(s: &str) -> Result<Format, String> {
    match s {
        "cl" => Ok(Format::Cl),
        "gcode" => Ok(Format::Gcode),
        _ => Err("expected cl or gcode".into()),
    }
}

pub fn run(a: Args) -> Result<(), String> {
    let defaults = ProgramOptions::default();
    let opts = ProgramOptions {
        machine: a.machine,
        l0: a.l0,
        branch: a.branch,
        tolerance: a.tolerance.unwrap_or(defaults.tolerance),
        feed: a.feed.unwrap_or(defaults.feed),
    };
    let p = program(&opts).map_err(|e| e.to_string())?;
    if a.json {
        println!("{}", serde_json::to_string(&p).map_err(|e| e.to_string())?);
        return Ok(());
    }
    match a.format {
        Format::Cl => print!("{}", p.cl_apt()),
        Format::Gcode => print!("{}", p.gcode().map_err(|e| e.to_string())?),
    }
    Ok(())
}
