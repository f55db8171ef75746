//! `testpiece points [--json] [--part ...]`: the built-in measurement points.

use crate::args::Args;
use testpiece::part::{builtin_points, ConeFrustum, SShape, FLAT_COLUMNS};

const HELP: &str = "\
testpiece points [--json] [--part s-shape|M3_15|M3_45] [--offsets]

Prints the 100 built-in measurement points of the ISO 10791-7 S-shape (25 per curve at equal arc
length from 5 % to 95 %: ids 1-25 A_Z11, 26-50 A_Z25, 51-75 B_Z11, 76-100 B_Z25) as CSV
`id,curve,u,v,x,y,z,nx,ny,nz,h`: surface parameters (v = z/30), point (mm), outward unit normal,
and h = contact height above the flank tool's tip along its axis (mm).
With --json: {\"points\": [{id, curve, surface, u, v, x, y, z, nx, ny, nz, h}, ...]}.

  --part M3_15|M3_45  the cone frustums of paper 002 Table 3 instead: 24 points (every 15°) on
                      the circles at 25 % and 75 % of the thickness, `curve` = <part>_Z<level>;
                      --offsets places them with the paper's offsets d = 62.5, p = 30 mm
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["part"])?;
    let json = args.flag("json");
    let offsets = args.flag("offsets");
    let part = args.value("part").unwrap_or("s-shape").to_string();
    args.reject_unknown("points")?;
    if !args.positional.is_empty() {
        return Err(format!(
            "`testpiece points` takes no arguments, found `{}`",
            args.positional.join(" ")
        ));
    }
    let cone = match part.to_ascii_uppercase().as_str() {
        "S-SHAPE" | "S_SHAPE" | "SSHAPE" => None,
        "M3_15" => Some(ConeFrustum::m3_15(offsets)),
        "M3_45" => Some(ConeFrustum::m3_45(offsets)),
        _ => {
            return Err(format!(
                "unknown part `{part}` (expected s-shape, M3_15 or M3_45)"
            ))
        }
    };
    if let Some(cone) = cone {
        let pts = cone.builtin_points();
        if json {
            return print_json(serde_json::json!({ "part": cone, "points": pts }));
        }
        println!("id,curve,{FLAT_COLUMNS}");
        for p in &pts {
            println!(
                "{},{}_Z{},{}",
                p.id,
                cone.name,
                p.level,
                p.flat().csv_fields()
            );
        }
        return Ok(());
    }
    let pts = builtin_points(&SShape::iso());
    if json {
        return print_json(serde_json::json!({ "points": pts }));
    }
    println!("id,curve,{FLAT_COLUMNS}");
    for p in &pts {
        println!("{},{},{}", p.id, p.curve, p.flat().csv_fields());
    }
    Ok(())
}

fn print_json(v: serde_json::Value) -> Result<(), String> {
    println!(
        "{}",
        serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
    );
    Ok(())
}
