//! `testpiece program`: the finishing flank pass as a CL file or ISO G-code (issue 19, step 2).

use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::Branch;
use testpiece::program::clearance::{replay, waypoints, PartGrid};
use testpiece::program::{program, Dialect, ProgramOptions};
use testpiece::settings::MachineChoice;

use crate::common::{branch, machine, mm, number};

/// the finishing flank pass as a CL file (budget --cl) or G-code in a controller's dialect
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
///
/// Around the cut: Z to the machine's home (G53 G00 Z0 / G0 SUPA Z0 / L Z+0 R0 FMAX M91) first,
/// tool call with length compensation, spindle and coolant; then per surface the rotary axes
/// alone at a safe height, X Y, Z down to 3 mm clear of the part, feed along the tool axis into
/// the pass and, after it, along the axis until the tool clears the part again; Z home, M05,
/// M09, M30. The replay of these moves with the tool (Ø20 x 60 mm) and holder (Ø50 x 100 mm)
/// against the walls and a base plate at z = -10 mm is in --json (`clearance`).
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
    /// RAPID before each positioning move, the format `testpiece budget FILE --cl` reads;
    /// gcode: the program in --dialect, X Y Z B C (X Y Z A B on paper001's A-B head) in the
    /// chain's machine axes (or the tip with --tcp), mm and degrees
    #[arg(long, value_name = "cl|gcode", default_value = "cl", value_parser = format, verbatim_doc_comment)]
    format: Format,
    /// feed of the pass (mm/min; default 1000): the tool-tip speed (inverse-time G93 on the
    /// pass in machine axes)
    #[arg(long, value_name = "MM_PER_MIN", value_parser = number, allow_negative_numbers = true, verbatim_doc_comment)]
    feed: Option<f64>,
    /// the controller's dialect: iso (ISO 6983-1 words as RS274/NGC), fanuc, linuxcnc,
    /// sinumerik (840D sl), heidenhain (TNC 640 Klartext); words of 8 significant digits at
    /// most, the dialect's comments, tool call, length compensation and machine-coordinate retract
    #[arg(long, value_name = "iso|fanuc|linuxcnc|sinumerik|heidenhain", default_value = "iso", value_parser = dialect, verbatim_doc_comment)]
    dialect: Dialect,
    /// tool-centre-point mode: the tip in the part frame and the rotary angles, F at the tip
    /// (fanuc G43.4, sinumerik TRAORI, heidenhain FUNCTION TCPM; not iso, linuxcnc)
    #[arg(long, verbatim_doc_comment)]
    tcp: bool,
    /// spindle speed (1/min; default 6000)
    #[arg(long, value_name = "RPM", value_parser = number)]
    spindle: Option<f64>,
    /// tool number and length-offset register (default 1)
    #[arg(long, value_name = "N")]
    tool: Option<u32>,
    /// {settings, machine, passes: [{surface, positions: [{u, tip, axis, axes, singular}],
    /// max_interval_error, max_step, max_scallop}], motion: {steps, z_safe, start,
    /// approach_lengths}, notes, rounding_bound (mm), clearance: {min_rapid, min_rapid_certain,
    /// min_plate, long_feed_moves_across, min_axial_end, sampling_bound, ...} (mm)}
    #[arg(long, verbatim_doc_comment)]
    json: bool,
}

/// `--format cl|gcode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Cl,
    Gcode,
}

fn dialect(s: &str) -> Result<Dialect, String> {
    Dialect::parse(s).ok_or_else(|| "expected iso, fanuc, linuxcnc, sinumerik or heidenhain".into())
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
        dialect: a.dialect,
        tcp: a.tcp,
        spindle: a.spindle.unwrap_or(defaults.spindle),
        tool: a.tool.unwrap_or(defaults.tool),
    };
    let p = program(&opts).map_err(|e| e.to_string())?;
    if a.json {
        let mut v = serde_json::to_value(&p).map_err(|e| e.to_string())?;
        let c = replay(
            &opts.chain(),
            &p.motion.start,
            &waypoints(&p.motion),
            &PartGrid::s_shape(),
        );
        v["rounding_bound"] = serde_json::json!(p.rounding_bound());
        v["clearance"] = serde_json::to_value(&c).map_err(|e| e.to_string())?;
        println!("{v}");
        return Ok(());
    }
    match a.format {
        Format::Cl => print!("{}", p.cl_apt()),
        Format::Gcode => print!("{}", p.gcode()),
    }
    Ok(())
}
