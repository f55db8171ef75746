//! `testpiece envelope`: deviation left by the flank path (paper 000 §3-4), optionally with a tool
//! rotation-profile error and multi-layer milling (paper 001 §2-3), or on a cone frustum.

use crate::args::Args;
use testpiece::part::{builtin_points, ConeFrustum, SShape, Surface};
use testpiece::toolpath::{
    multilayer_deviation, points_deviation, surface_max_overcut, FlankPath, LayerPlan, ToolProfile,
    TOOL_RADIUS,
};

const HELP: &str = "\
testpiece envelope [--surface-max] [--dr MM] [--json]
                   [--profile paper001|FILE] [--rho MM] [--phi RAD]
                   [--layers N] [--pitch MM] [--cutting-length MM]
                   [--part s-shape|M3_15|M3_45] [--offsets]

Deviation left by the flank tool path of paper 000 eq. 2 (cylindrical tool, radius 10 mm) at the
100 built-in points, as the exact envelope of the tool (paper 000 §4.1, Fig. 13, refined in u):
CSV `id,curve,deviation` (mm; + = material left, - = overcut).

  --surface-max      instead, per surface, the largest overcut over Z 0..30 and where it is:
                     `surface,max_overcut,u,z` (max_overcut > 0 in mm, z in mm)
  --dr MM            tool radius error (+ = a larger tool), path unchanged
  --json             {\"points\": [...]} or {\"surfaces\": [...]}, same fields as the CSV

Tool rotation profile and multi-layer milling (paper 001); any of these switches to the columns
`id,curve,deviation,layer,height,own_layer,own_deviation` (layer = the one that cut deepest,
height = contact height on its tool, own_* = the point's first layer alone, i.e. without
inter-layer interference):
  --profile P        `paper001` (Table 2 radii) or a CSV file `height,radius` (mm above the tip, mm)
  --rho MM, --phi RAD  tool setup error: parallel offset and inclination
  --layers N         number of axial layers (default 1); --pitch MM between layer tips (default 3);
  --cutting-length MM  of the tool (default 50)

  --part M3_15|M3_45 the cone frustums of paper 002 Table 3 instead (48 points, `curve` =
                     <part>_Z<level>); --offsets places them with d = 62.5, p = 30 mm
";

fn number(args: &Args, name: &str) -> Result<Option<f64>, String> {
    args.value(name)
        .map(|s| {
            s.parse::<f64>()
                .map_err(|_| format!("--{name} expects a number, found `{s}`"))
        })
        .transpose()
}

fn read_profile(spec: &str) -> Result<ToolProfile, String> {
    if spec.eq_ignore_ascii_case("paper001") {
        return Ok(ToolProfile::paper_001_table_2());
    }
    let text =
        std::fs::read_to_string(spec).map_err(|e| format!("cannot read profile `{spec}`: {e}"))?;
    let mut table = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let cells: Vec<&str> = line.split([',', ';', '\t']).map(str::trim).collect();
        if line.trim().is_empty() || (i == 0 && cells[0].parse::<f64>().is_err()) {
            continue;
        }
        let parse = |k: usize| {
            cells
                .get(k)
                .and_then(|c| c.parse::<f64>().ok())
                .ok_or_else(|| {
                    format!(
                        "profile `{spec}` line {}: expected `height,radius`, found `{line}`",
                        i + 1
                    )
                })
        };
        table.push((parse(0)?, parse(1)?));
    }
    ToolProfile::try_new(&table).map_err(|e| format!("profile `{spec}`: {e}"))
}

fn print_rows<T: serde::Serialize>(
    json: bool,
    key: &str,
    header: &str,
    rows: &[T],
) -> Result<(), String> {
    if json {
        let v = serde_json::json!({ key: rows });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    println!("{header}");
    let cols: Vec<&str> = header.split(',').collect();
    for r in rows {
        let v = serde_json::to_value(r).map_err(|e| e.to_string())?;
        let cells: Vec<String> = cols
            .iter()
            .map(|c| match &v[*c] {
                serde_json::Value::String(s) => s.clone(),
                other => other.to_string(),
            })
            .collect();
        println!("{}", cells.join(","));
    }
    Ok(())
}

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(
        rest,
        &[
            "dr",
            "profile",
            "rho",
            "phi",
            "layers",
            "pitch",
            "cutting-length",
            "part",
        ],
    )?;
    let json = args.flag("json");
    let surface_max = args.flag("surface-max");
    let offsets = args.flag("offsets");
    let dr = number(&args, "dr")?.unwrap_or(0.0);
    let profile = args.value("profile").map(read_profile).transpose()?;
    let rho = number(&args, "rho")?;
    let phi = number(&args, "phi")?;
    let layers = args
        .value("layers")
        .map(|s| {
            s.parse::<usize>()
                .map_err(|_| format!("--layers expects a whole number, found `{s}`"))
        })
        .transpose()?;
    let pitch = number(&args, "pitch")?;
    let cutting_length = number(&args, "cutting-length")?;
    let part_name = args.value("part").unwrap_or("s-shape").to_string();
    args.reject_unknown("envelope")?;
    if !args.positional.is_empty() {
        return Err(format!(
            "`testpiece envelope` takes no arguments, found `{}`",
            args.positional.join(" ")
        ));
    }
    let layered = profile.is_some()
        || rho.is_some()
        || phi.is_some()
        || layers.is_some()
        || pitch.is_some()
        || cutting_length.is_some();

    let cone = match part_name.to_ascii_uppercase().as_str() {
        "S-SHAPE" | "S_SHAPE" | "SSHAPE" => None,
        "M3_15" => Some(ConeFrustum::m3_15(offsets)),
        "M3_45" => Some(ConeFrustum::m3_45(offsets)),
        _ => {
            return Err(format!(
                "unknown part `{part_name}` (expected s-shape, M3_15 or M3_45)"
            ))
        }
    };
    if let Some(cone) = cone {
        if surface_max || layered {
            return Err(
                "--surface-max and the profile/layer options apply to the S-shape only".into(),
            );
        }
        let path = FlankPath::new(&cone, Surface::A);
        let mut rows = Vec::new();
        for p in cone.builtin_points() {
            let hit = path
                .deviation_at(&p.point, &p.normal, p.u, TOOL_RADIUS + dr)
                .map_err(|e| e.to_string())?;
            rows.push(serde_json::json!({
                "id": p.id,
                "curve": format!("{}_Z{}", cone.name, p.level),
                "deviation": hit.deviation,
            }));
        }
        return print_rows(json, "points", "id,curve,deviation", &rows);
    }

    let part = SShape::iso();
    if surface_max {
        if dr != 0.0 || layered {
            return Err(
                "--surface-max is for the nominal tool; --dr and the profile/layer options apply to the points"
                    .into(),
            );
        }
        let maxima = Surface::BOTH
            .iter()
            .map(|s| surface_max_overcut(&part, *s))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        return print_rows(json, "surfaces", "surface,max_overcut,u,z", &maxima);
    }
    let points = builtin_points(&part);
    if layered {
        let base = match profile {
            Some(p) => p,
            None => ToolProfile::constant(TOOL_RADIUS).map_err(|e| e.to_string())?,
        };
        let tool = if dr != 0.0 {
            return Err(
                "--dr cannot be combined with a profile; put the radii in the profile".into(),
            );
        } else {
            base.with_setup_error(rho.unwrap_or(0.0), phi.unwrap_or(0.0))
                .map_err(|e| e.to_string())?
        };
        let plan = LayerPlan::try_new(
            layers.unwrap_or(1),
            pitch.unwrap_or(3.0),
            cutting_length.unwrap_or(50.0),
        )
        .map_err(|e| e.to_string())?;
        let res = multilayer_deviation(&part, &points, &tool, &plan).map_err(|e| e.to_string())?;
        return print_rows(
            json,
            "points",
            "id,curve,deviation,layer,height,own_layer,own_deviation",
            &res,
        );
    }
    let dev = points_deviation(&part, &points, dr).map_err(|e| e.to_string())?;
    print_rows(json, "points", "id,curve,deviation", &dev)
}
