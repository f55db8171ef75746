//! `testpiece envelope [--surface-max] [--dr MM] [--json]`: deviation left by the flank path.

use crate::args::Args;
use testpiece::part::{builtin_points, SShape, Surface};
use testpiece::toolpath::{points_deviation, surface_max_overcut};

const HELP: &str = "\
testpiece envelope [--surface-max] [--dr MM] [--json]

Deviation left by the flank tool path of paper 000 eq. 2 (cylindrical tool, radius 10 mm) at the
100 built-in points, as the exact envelope of the tool (paper 000 §4.1, Fig. 13, refined in u):
CSV `id,curve,deviation` (mm; + = material left, - = overcut).

  --surface-max  instead, per surface, the largest overcut over Z 0..30 and where it is:
                 `surface,max_overcut,u,z` (max_overcut > 0 in mm, z in mm)
  --dr MM        tool radius error (+ = a larger tool), path unchanged (points only)
  --json         {\"points\": [{id, curve, deviation}]} or {\"surfaces\": [{surface, max_overcut, u, z}]}
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["dr"])?;
    let json = args.flag("json");
    let surface_max = args.flag("surface-max");
    let dr: f64 = match args.value("dr") {
        Some(s) => s
            .parse()
            .map_err(|_| format!("--dr expects a number of mm, found `{s}`"))?,
        None => 0.0,
    };
    args.reject_unknown("envelope")?;
    if !args.positional.is_empty() {
        return Err(format!(
            "`testpiece envelope` takes no arguments, found `{}`",
            args.positional.join(" ")
        ));
    }
    let part = SShape::iso();
    if surface_max {
        if dr != 0.0 {
            return Err(
                "--dr applies to the points only; the surface maximum is for the nominal tool"
                    .into(),
            );
        }
        let maxima = Surface::BOTH
            .iter()
            .map(|s| surface_max_overcut(&part, *s))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        if json {
            let v = serde_json::json!({ "surfaces": maxima });
            println!(
                "{}",
                serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
            );
        } else {
            println!("surface,max_overcut,u,z");
            for m in &maxima {
                println!(
                    "{},{:?},{:?},{:?}",
                    m.surface.name(),
                    m.max_overcut,
                    m.u,
                    m.z
                );
            }
        }
        return Ok(());
    }
    let dev = points_deviation(&part, &builtin_points(&part), dr).map_err(|e| e.to_string())?;
    if json {
        let v = serde_json::json!({ "points": dev });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    } else {
        println!("id,curve,deviation");
        for d in &dev {
            println!("{},{},{:?}", d.id, d.curve, d.deviation);
        }
    }
    Ok(())
}
