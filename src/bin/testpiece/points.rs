//! `testpiece points [--json]`: the 100 built-in measurement points.

use crate::args::Args;
use testpiece::part::{builtin_points, SShape};

const HELP: &str = "\
testpiece points [--json]

Prints the 100 built-in measurement points of the ISO 10791-7 S-shape (25 per curve at equal arc
length from 5 % to 95 %: ids 1-25 A_Z11, 26-50 A_Z25, 51-75 B_Z11, 76-100 B_Z25) as CSV
`id,curve,u,v,x,y,z,nx,ny,nz,h`: surface parameters (v = z/30), point (mm), outward unit normal,
and h = contact height above the flank tool's tip along its axis (mm).
With --json: {\"points\": [{id, curve, surface, u, v, x, y, z, nx, ny, nz, h}, ...]}.
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &[])?;
    let json = args.flag("json");
    args.reject_unknown("points")?;
    if !args.positional.is_empty() {
        return Err(format!(
            "`testpiece points` takes no arguments, found `{}`",
            args.positional.join(" ")
        ));
    }
    let pts = builtin_points(&SShape::iso());
    if json {
        let v = serde_json::json!({ "points": pts });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    println!("id,curve,u,v,x,y,z,nx,ny,nz,h");
    for p in &pts {
        println!(
            "{},{},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?}",
            p.id,
            p.curve,
            p.u,
            p.v,
            p.point.x,
            p.point.y,
            p.point.z,
            p.normal.x,
            p.normal.y,
            p.normal.z,
            p.h
        );
    }
    Ok(())
}
