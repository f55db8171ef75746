//! `testpiece budget FILE --cl PATH [--trace PATH]`: the error budget per point (issue 10).

use crate::args::Args;
use testpiece::analysis::AnalysisOptions;
use testpiece::budget::{error_budget, read_cl, read_trace, BudgetOptions, TraceMachine};
use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::description::MachineDescription;
use testpiece::machine::Branch;
use testpiece::sensitivity::Mode;

const HELP: &str = "\
testpiece budget FILE --cl PATH [--trace PATH] [--machine FILE] [--json]
                      [--tool-radius] [--mode physical|paper] [--branch signed|positive]
                      [--l0 MM] [--radius MM] [--sigma MM] [--no-refine] [--exclude-bad-rows]

The error budget of a measured S-shape part (paper 000 §3-§6), point by point: how much of the
measured normal deviation of FILE (any CMM export of cmm-csv.md) comes from
  design    the overcut of the exact envelope of the ideal flank path (eq. 2-5)
  cam       the CAM path of --cl minus the design (discrete positions, §4.1 Fig. 13)
  nc        the NC trace of --trace minus the CAM path (§5.1; 0 without a trace)
  machine   the location errors identified after subtracting the path's deviation (eq. 14)
  tool      -dR, the tool-radius error, with --tool-radius (§3.2)
  residual  measured - all of the above (so the sources add up to the measurement)
  cmm       the CMM's MPE band ±(3 + L/75) µm, L = distance from the part origin (§6)
All in mm; + = material left, - = overcut.

--cl PATH        CAM cutter locations: CSV with a header x,y,z,i,j,k (tool tip, unit tool axis,
                 part frame, mm), or APT GOTO/x,y,z,i,j,k records (TLAXIS, UNITS/MM|INCHES,
                 CUTTER, FEDRAT, RAPID, PARTNO, comments ... are recognised and skipped)
--trace PATH     NC controller trace: CSV with the machine's axes X,Y,Z,B,C (mm, degrees) and
                 optionally time (s), replayed through the nominal direct kinematics
--machine FILE   the machine of the trace (JSON description, as for `testpiece forward`);
                 default paper 000's B head / C table with --l0 (499.889 mm)
--radius MM      radius of the tool cylinder at every position (default 10)
--json           {points: [{id, design, cam, nc, machine, tool, residual, ...}],
                  summary: {source: {min, max}}, per_curve, cl, trace, parameters, notes}
Without --json: CSV, one row per point:
  id,curve,measured,design,cam,nc,machine,tool,residual,cmm,cam_chord_bound,nc_chord_bound
A bad CL or trace line is reported with its line, column, the text found and what was expected.
";

fn read(path: &str) -> Result<Vec<u8>, String> {
    std::fs::read(path).map_err(|e| format!("{path}: {e}"))
}

fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .map_or(path.to_string(), |n| n.to_string_lossy().into_owned())
}

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(
        rest,
        &[
            "cl", "trace", "machine", "mode", "branch", "l0", "radius", "sigma",
        ],
    )?;
    let (mode, branch) = crate::simulate::mode_and_branch(&args)?;
    let number = |name: &str| -> Result<Option<f64>, String> {
        match args.value(name) {
            Some(t) => t
                .parse::<f64>()
                .map(Some)
                .map_err(|_| format!("--{name} `{t}`: expected a number of mm")),
            None => Ok(None),
        }
    };
    let l0 = number("l0")?.unwrap_or(PAPER000_L0);
    let radius = number("radius")?.unwrap_or(testpiece::toolpath::TOOL_RADIUS);
    let sigma = number("sigma")?;
    let cl_path = args
        .value("cl")
        .ok_or("`testpiece budget` needs --cl PATH (a CAM cutter-location file)")?
        .to_string();
    let trace_path = args.value("trace").map(str::to_string);
    let machine_path = args.value("machine").map(str::to_string);
    let json = args.flag("json");
    let tool_radius = args.flag("tool-radius");
    let no_refine = args.flag("no-refine");
    let exclude_bad_rows = args.flag("exclude-bad-rows");
    args.reject_unknown("budget")?;
    let [file] = args.positional.as_slice() else {
        return Err("`testpiece budget` needs exactly one FILE (see --help)".to_string());
    };
    let machine = match &machine_path {
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| format!("{p}: {e}"))?;
            let d = MachineDescription::from_json(&text).map_err(|e| format!("{p}: {e}"))?;
            TraceMachine::from_description(&d).map_err(|e| format!("{p}: {e}"))?
        }
        None => TraceMachine::paper000(l0),
    };
    let cl = read_cl(&read(&cl_path)?, &file_name(&cl_path)).map_err(|e| e.to_string())?;
    let trace = match &trace_path {
        Some(p) => Some(read_trace(&read(p)?, &file_name(p), &machine).map_err(|e| e.to_string())?),
        None => None,
    };
    let opts = BudgetOptions::default()
        .with_tool_radius(radius)
        .with_analysis(AnalysisOptions {
            mode: Mode::parse(&mode).map_err(|e| e.to_string())?,
            branch: Branch::parse(&branch)
                .ok_or_else(|| format!("--branch `{branch}`: expected signed or positive"))?,
            l0,
            tool_radius,
            exclude_bad_rows,
            noise_sigma: sigma,
            refine: !no_refine,
            ..AnalysisOptions::default()
        });
    let bytes = read(file)?;
    let b = error_budget(&bytes, &file_name(file), &cl, trace.as_ref(), &opts)
        .map_err(|e| format!("{file}: {e}"))?;
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&b).map_err(|e| e.to_string())?
        );
    } else {
        println!("id,curve,measured,design,cam,nc,machine,tool,residual,cmm,cam_chord_bound,nc_chord_bound");
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
    Ok(())
}
