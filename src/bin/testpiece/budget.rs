//! `testpiece budget FILE --cl PATH [--trace PATH]`: the error budget per point (issue 10).

use testpiece::analysis::{AnalysisOptions, Session};
use testpiece::budget::{error_budget, read_cl, read_trace, Budget, BudgetOptions, TraceMachine};
use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::description::MachineDescription;
use testpiece::machine::Branch;
use testpiece::sensitivity::Mode;
use testpiece::toolpath::TOOL_RADIUS;

use crate::common::{branch, file_name, mm, mode, print_json, read};

/// error budget per point: design, CAM path (--cl), NC trace, machine, tool, CMM
///
/// The error budget of a measured S-shape part (paper 000 §3-§6), point by point: how much of the
/// measured normal deviation of FILE (any CMM export of cmm-csv.md) comes from
///   design    the overcut of the exact envelope of the ideal flank path (eq. 2-5)
///   cam       the CAM path of --cl PATH minus the design (discrete positions, §4.1 Fig. 13)
///   nc        the NC trace of --trace PATH minus the CAM path (§5.1; 0 without a trace)
///   machine   the location errors identified after subtracting the path's deviation (eq. 14)
///   tool      -dR, the tool-radius error, with --tool-radius (§3.2)
///   residual  measured - all of the above (so the sources add up to the measurement)
///   cmm       the CMM's MPE band ±(3 + L/75) µm, L = distance from the part origin (§6)
/// All in mm; + = material left, - = overcut.
///
/// Without --json: CSV, one row per point:
///   id,curve,measured,design,cam,nc,machine,tool,residual,cmm,cam_chord_bound,nc_chord_bound
/// A bad CL or trace line is reported with its line, column, the text found and what was expected.
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the measured part (any CMM export)
    #[arg(value_name = "FILE")]
    files: Vec<String>,
    /// CAM cutter locations: CSV with a header x,y,z,i,j,k (tool tip, unit tool axis, part frame,
    /// mm), or APT GOTO/x,y,z,i,j,k records (TLAXIS, UNITS/MM|INCHES, CUTTER, FEDRAT, RAPID,
    /// PARTNO, comments ... are recognised and skipped)
    #[arg(long, value_name = "PATH", verbatim_doc_comment)]
    cl: Option<String>,
    /// NC controller trace: CSV with the machine's axes X,Y,Z,B,C (mm, degrees) and optionally
    /// time (s), replayed through the nominal direct kinematics
    #[arg(long, value_name = "PATH", verbatim_doc_comment)]
    trace: Option<String>,
    /// the machine of the trace (JSON description, as for `testpiece forward`); default paper
    /// 000's B head / C table with --l0
    #[arg(long, value_name = "FILE", verbatim_doc_comment)]
    machine: Option<String>,
    /// {points: [{id, design, cam, nc, machine, tool, residual, ...}], summary: {source: {min,
    /// max}}, per_curve, cl, trace, parameters, notes}
    #[arg(long, verbatim_doc_comment)]
    json: bool,
    /// also fit the tool-radius error dR (mm)
    #[arg(long)]
    tool_radius: bool,
    /// the defect's displaced point, normal and reference (as `testpiece sensitivity`)
    #[arg(long, value_name = "physical|paper", default_value = "physical", value_parser = mode)]
    mode: Mode,
    /// the B-axis branch of the inverse kinematics
    #[arg(long, value_name = "signed|positive", default_value = "signed", value_parser = branch)]
    branch: Branch,
    /// the pivot-to-tip length (mm)
    #[arg(long, value_name = "MM", default_value_t = PAPER000_L0, value_parser = mm, allow_negative_numbers = true)]
    l0: f64,
    /// radius of the tool cylinder at every position (mm)
    #[arg(long, value_name = "MM", default_value_t = TOOL_RADIUS, value_parser = mm, allow_negative_numbers = true)]
    radius: f64,
    /// a priori σ of the deviations (mm)
    #[arg(long, value_name = "MM", value_parser = mm, allow_negative_numbers = true)]
    sigma: Option<f64>,
    /// skips the exact-model check of the identification
    #[arg(long)]
    no_refine: bool,
    /// leave out the rows the reader rejects instead of refusing the file
    #[arg(long)]
    exclude_bad_rows: bool,
}

pub fn run(a: Args) -> Result<(), String> {
    let cl_path =
        a.cl.as_deref()
            .ok_or("`testpiece budget` needs --cl PATH (a CAM cutter-location file)")?;
    let [file] = a.files.as_slice() else {
        return Err("`testpiece budget` needs exactly one FILE (see --help)".to_string());
    };
    let machine = trace_machine(a.machine.as_deref(), a.l0)?;
    let cl = read_cl(&read(cl_path)?, &file_name(cl_path)).map_err(|e| e.to_string())?;
    let trace = match &a.trace {
        Some(p) => Some(read_trace(&read(p)?, &file_name(p), &machine).map_err(|e| e.to_string())?),
        None => None,
    };
    let opts = a.options();
    let bytes = read(file)?;
    let session = Session::new(&opts.analysis).map_err(|e| format!("{file}: {e}"))?;
    let b = error_budget(
        &session,
        &bytes,
        &file_name(file),
        &cl,
        trace.as_ref(),
        &opts,
    )
    .map_err(|e| format!("{file}: {e}"))?;
    if a.json {
        return print_json(&b);
    }
    print_csv(&b);
    Ok(())
}

impl Args {
    /// The budget's settings: the tool cylinder and the identification's.
    fn options(&self) -> BudgetOptions {
        BudgetOptions::default()
            .with_tool_radius(self.radius)
            .with_analysis(AnalysisOptions {
                mode: self.mode,
                branch: self.branch,
                l0: self.l0,
                tool_radius: self.tool_radius,
                exclude_bad_rows: self.exclude_bad_rows,
                noise_sigma: self.sigma,
                refine: !self.no_refine,
                ..AnalysisOptions::default()
            })
    }
}

/// The machine that replays the trace: the description of --machine FILE, else paper 000's.
fn trace_machine(path: Option<&str>, l0: f64) -> Result<TraceMachine, String> {
    let Some(p) = path else {
        return Ok(TraceMachine::paper000(l0));
    };
    let text = std::fs::read_to_string(p).map_err(|e| format!("{p}: {e}"))?;
    let d = MachineDescription::from_json(&text).map_err(|e| format!("{p}: {e}"))?;
    TraceMachine::from_description(&d).map_err(|e| format!("{p}: {e}"))
}

/// `id,curve,measured,design,cam,nc,machine,tool,residual,cmm,cam_chord_bound,nc_chord_bound`.
fn print_csv(b: &Budget) {
    println!(
        "id,curve,measured,design,cam,nc,machine,tool,residual,cmm,cam_chord_bound,nc_chord_bound"
    );
    for p in &b.points {
        println!(
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            p.id,
            p.curve,
            p.measured,
            p.design,
            p.cam,
            p.nc,
            p.machine,
            p.tool,
            p.residual,
            p.cmm,
            p.cam_chord_bound,
            p.nc_chord_bound.map_or(String::new(), |v| v.to_string())
        );
    }
}
