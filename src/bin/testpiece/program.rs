//! `testpiece program`: the finishing flank pass as a CL file or ISO G-code (issue 19, step 2).

use crate::args::Args;
use crate::identify::machine_and_l0;
use testpiece::machine::Branch;
use testpiece::program::{program, ProgramOptions};

const HELP: &str = "\
testpiece program [--machine paper000|paper001|paper002] [--l0 MM] [--branch signed|positive]
                  [--tolerance MM] [--format cl|gcode] [--feed MM_PER_MIN] [--json]

The finishing flank pass of both walls of the S-shape (surface A, then B, each in increasing u),
a flat end mill of diameter 20 mm with its tip on the flank path of paper 000 eq. 2 and its
axis on the ruling. ROUGHING IS NOT INCLUDED (remove the stock before this pass); the header
comments say so and name the machine, L0, tool, branch, tolerance and software version.

Positions are placed so that, between two of them, (1) the scallop R - sqrt(R² - s²/4) of the
tip step s (paper 000 eq. 7), (2) the chord of the tip path and (3) the controller's linear
interpolation of the machine axes (tool tip and top of the flank) all stay within --tolerance.
The axis values are the inverse kinematics of the analysis with the chosen B branch, through the
vertical zone as the analysis assumes.

--format cl      (default) APT CL data: GOTO/x,y,z,i,j,k per position (tool tip, unit tool axis,
                 part frame, mm): the format `testpiece budget FILE --cl` reads
--format gcode   ISO G-code: G01 X Y Z B C (X Y Z A B on paper001's A-B head) in the chain's
                 machine axes, mm and degrees, no RTCP; G00 approach and retract 50 mm along the
                 tool axis at each surface's start and end
--tolerance MM   chord tolerance (default 0.001)
--feed F         feed of the pass (mm/min, default 1000)
--machine, --l0  the chain (default paper000, L0 = 499.889 mm), as for `identify`
--branch         signed (default; the analysis's) or positive (B >= 0)
--json           {settings, machine, passes: [{surface, positions: [{u, tip, axis, axes,
                  singular}], max_interval_error, max_step, max_scallop}], notes}
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(
        rest,
        &["machine", "l0", "branch", "tolerance", "format", "feed"],
    )?;
    let (machine, l0) = machine_and_l0(&args)?;
    let branch = args.value("branch").unwrap_or("signed");
    let branch = Branch::parse(branch)
        .ok_or_else(|| format!("--branch `{branch}`: expected signed or positive"))?;
    let number = |name: &str, default: f64| -> Result<f64, String> {
        args.value(name).map_or(Ok(default), |t| {
            t.parse::<f64>()
                .map_err(|_| format!("--{name} `{t}`: expected a number"))
        })
    };
    let defaults = ProgramOptions::default();
    let opts = ProgramOptions {
        machine,
        l0,
        branch,
        tolerance: number("tolerance", defaults.tolerance)?,
        feed: number("feed", defaults.feed)?,
    };
    let format = args.value("format").unwrap_or("cl").to_string();
    let json = args.flag("json");
    args.reject_unknown("program")?;
    if !args.positional.is_empty() {
        return Err(format!(
            "`testpiece program` takes no file, found `{}`",
            args.positional.join(" ")
        ));
    }
    let p = program(&opts).map_err(|e| e.to_string())?;
    if json {
        println!("{}", serde_json::to_string(&p).map_err(|e| e.to_string())?);
        return Ok(());
    }
    match format.as_str() {
        "cl" => print!("{}", p.cl_apt()),
        "gcode" => print!("{}", p.gcode().map_err(|e| e.to_string())?),
        f => return Err(format!("--format `{f}`: expected cl or gcode")),
    }
    Ok(())
}
