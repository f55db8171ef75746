//! `testpiece plan`: the measurement plan (issue 19, step 1): points, predicted std, groups,
//! detection limits; DMIS and CSV programs for the CMM.

use crate::args::Args;
use crate::identify::{machine_and_l0, parse_mpe};
use testpiece::machine::Branch;
use testpiece::plan::{nominal_csv, plan, split_total, Plan, PlanOptions};
use testpiece::sensitivity::Mode;

const HELP: &str = "\
testpiece plan [--points N | --per-curve N] [--sigma MM | --mpe A,K[,R0]]
               [--machine paper000|paper001|paper002] [--l0 MM] [--mode physical|paper]
               [--branch signed|positive] [--tool-radius] [--json] [--dmis FILE] [--csv FILE]

The measurement plan of the S-shape, before any part exists: the points to measure and what an
identification on them will be able to tell.
  points            N per curve at equal arc length from 5 % to 95 % (the built-in layout with
                    25 replaced by N), ids 1.. in the order A_Z11, A_Z25, B_Z11, B_Z25
  parameters        the predicted std of every location error (same names and units as
                    `identify`: rad, EX0B in mm) and its status (identified, weak,
                    not_separable): exactly what `identify FILE --sigma σ --effects none` reports
                    on a part measured at these points
  groups            the combinations the part cannot separate (and the weak ones)
  detection_limits  per effect of effects.md and parameter, the smallest size whose part the
                    location errors cannot absorb reaches 2.5 σ RMS over the points (the
                    diagnosis's rule); null when the location errors absorb it entirely

--points N        N points in all, spread over the 4 curves (remainder to the first ones)
--per-curve N     N points per curve (default 25: the 100 built-in points)
--sigma MM        the CMM's standard uncertainty of one deviation (mm)
--mpe A,K[,R0]    or its MPE_E = A + L/K µm: σ = median of max(MPE_E(L)/√3, R0/1.693) over the
                  points (default: paper 000's CMM, 3 + L/75 µm, R0 = 3 µm)
--json            {points, parameters: {NAME: {std, status, unit}}, groups, rank, condition,
                   detection_limits: {effect: {parameter: size}}, detection_detail, noise, notes}
--dmis FILE       writes the plan as a DMIS program (ISO 22093): per point a point feature with
                  its nominal position and outward normal, and its measurement (PTMEAS) with
                  the approach vector; coordinates in the part frame (mm)
--csv FILE        writes the nominal table id,curve,x,y,z,nx,ny,nz (mm)
Without --json: one line per parameter (name, predicted std, unit, status), the groups, then
one line per effect parameter with its detection limit.
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(
        rest,
        &[
            "points",
            "per-curve",
            "sigma",
            "mpe",
            "machine",
            "l0",
            "mode",
            "branch",
            "dmis",
            "csv",
        ],
    )?;
    let count = |name: &str| -> Result<Option<usize>, String> {
        args.value(name)
            .map(|t| {
                t.parse::<usize>()
                    .map_err(|_| format!("--{name} `{t}`: expected a whole number of points"))
            })
            .transpose()
    };
    let per_curve = match (count("points")?, count("per-curve")?) {
        (Some(_), Some(_)) => {
            return Err("--points and --per-curve both set the number of points: give one".into())
        }
        (Some(n), None) => split_total(n).map_err(|e| e.to_string())?,
        (None, Some(n)) => [n; 4],
        (None, None) => [25; 4],
    };
    let sigma = args
        .value("sigma")
        .map(|t| {
            t.parse::<f64>()
                .map_err(|_| format!("--sigma `{t}`: expected a number of mm"))
        })
        .transpose()?;
    let mpe = parse_mpe(&args, sigma)?;
    let (machine, l0) = machine_and_l0(&args)?;
    let (mode, branch) = crate::simulate::mode_and_branch(&args)?;
    let tool_radius = args.flag("tool-radius");
    let json = args.flag("json");
    let dmis = args.value("dmis").map(str::to_string);
    let csv = args.value("csv").map(str::to_string);
    args.reject_unknown("plan")?;
    if !args.positional.is_empty() {
        return Err(format!(
            "`testpiece plan` takes no file, found `{}`",
            args.positional.join(" ")
        ));
    }
    let opts = PlanOptions {
        per_curve,
        sigma,
        mpe,
        machine,
        l0,
        mode: Mode::parse(&mode).map_err(|e| e.to_string())?,
        branch: Branch::parse(&branch)
            .ok_or_else(|| format!("--branch `{branch}`: expected signed or positive"))?,
        tool_radius,
    };
    let p = plan(&opts).map_err(|e| e.to_string())?;
    if let Some(path) = dmis {
        std::fs::write(&path, p.dmis()).map_err(|e| format!("{path}: {e}"))?;
    }
    if let Some(path) = csv {
        std::fs::write(&path, nominal_csv(&p.points)).map_err(|e| format!("{path}: {e}"))?;
    }
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&p).map_err(|e| e.to_string())?
        );
    } else {
        print_text(&p);
    }
    Ok(())
}

fn print_text(p: &Plan) {
    println!("{} points; {}", p.points.len(), p.noise.summary);
    println!("parameter  predicted std  unit  status");
    for (name, q) in &p.parameters.0 {
        let std = q.std.map_or("-".to_string(), |s| format!("{s:.3e}"));
        let status = serde_json::to_value(q.status).unwrap_or_default();
        println!(
            "{name:<8} {std:>14} {:>5}  {}",
            q.unit,
            status.as_str().unwrap_or("")
        );
    }
    for g in &p.groups {
        println!("group: {}", g.explanation);
    }
    println!("effect.parameter  detection limit  unit");
    for d in &p.detection_detail {
        for q in &d.parameters {
            let size = q
                .size
                .map_or("never visible".to_string(), |s| format!("{s:.3e}"));
            let name = format!("{}.{}", d.effect.id(), q.name);
            println!("{name:<20} {size:>14} {}", q.unit);
        }
    }
    for n in &p.notes {
        println!("note: {n}");
    }
}
