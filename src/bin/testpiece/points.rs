//! `testpiece points [--json] [--part ...]`: the built-in measurement points.

use testpiece::part::{builtin_points, ConeFrustum, SShape, FLAT_COLUMNS};

use crate::common::{part, print_json, Part};

/// the 100 built-in measurement points: id,curve,u,v,x,y,z,nx,ny,nz,h
///
/// Prints the 100 built-in measurement points of the ISO 10791-7 S-shape (25 per curve at equal arc
/// length from 5 % to 95 %: ids 1-25 A_Z11, 26-50 A_Z25, 51-75 B_Z11, 76-100 B_Z25) as CSV
/// `id,curve,u,v,x,y,z,nx,ny,nz,h`: surface parameters (v = z/30), point (mm), outward unit normal,
/// and h = contact height above the flank tool's tip along its axis (mm).
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// {"points": [{id, curve, surface, u, v, x, y, z, nx, ny, nz, h}, ...]}
    #[arg(long)]
    json: bool,
    /// M3_15|M3_45: the cone frustums of paper 002 Table 3 instead
    ///
    /// 24 points (every 15°) on the circles at 25 % and 75 % of the thickness, `curve` =
    /// <part>_Z<level>
    #[arg(long, value_name = "s-shape|M3_15|M3_45", default_value = "s-shape", value_parser = part, verbatim_doc_comment)]
    part: Part,
    /// places the cone frustum with the paper's offsets d = 62.5, p = 30 mm
    #[arg(long)]
    offsets: bool,
}

pub fn run(a: Args) -> Result<(), String> {
    match a.part.cone(a.offsets) {
        Some(cone) => cone_points(&cone, a.json),
        None => s_shape_points(a.json),
    }
}

/// The S-shape's 100 points.
fn s_shape_points(json: bool) -> Result<(), String> {
    let pts = builtin_points(&SShape::iso());
    if json {
        return print_json(&serde_json::json!({ "points": pts }));
    }
    println!("id,curve,{FLAT_COLUMNS}");
    for p in &pts {
        println!("{},{},{}", p.id, p.curve, p.flat().csv_fields());
    }
    Ok(())
}

/// A cone frustum's 24 points, `curve` = <part>_Z<level>.
fn cone_points(cone: &ConeFrustum, json: bool) -> Result<(), String> {
    let pts = cone.builtin_points();
    if json {
        return print_json(&serde_json::json!({ "part": cone, "points": pts }));
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
    Ok(())
}
