//! `testpiece envelope`: deviation left by the flank path (paper 000 §3-4), optionally with a tool
//! rotation-profile error and multi-layer milling (paper 001 §2-3), or on a cone frustum.

use testpiece::part::{builtin_points, ConeFrustum, SShape, Surface};
use testpiece::toolpath::{
    multilayer_deviation, points_deviation, surface_max_overcut, FlankPath, LayerPlan, ToolProfile,
    TOOL_RADIUS,
};

use crate::common::{number, part, whole, Part};

/// flank-path deviation at the points (id,curve,deviation); --surface-max per surface
///
/// Deviation left by the flank tool path of paper 000 eq. 2 (cylindrical tool, radius 10 mm) at the
/// 100 built-in points, as the exact envelope of the tool (paper 000 §4.1, Fig. 13, refined in u):
/// CSV `id,curve,deviation` (mm; + = material left, - = overcut).
///
/// Tool rotation profile and multi-layer milling (paper 001): any of --profile, --rho, --phi,
/// --layers, --pitch, --cutting-length switches to the columns
/// `id,curve,deviation,layer,height,own_layer,own_deviation` (layer = the one that cut deepest,
/// height = contact height on its tool, own_* = the point's first layer alone, i.e. without
/// inter-layer interference).
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// instead, per surface, the largest overcut over Z 0..30 and where it is:
    /// `surface,max_overcut,u,z` (max_overcut > 0 in mm, z in mm)
    #[arg(long, verbatim_doc_comment)]
    surface_max: bool,
    /// tool radius error (mm, + = a larger tool), path unchanged
    #[arg(long, value_name = "MM", default_value_t = 0.0, value_parser = number, allow_negative_numbers = true)]
    dr: f64,
    /// {"points": [...]} or {"surfaces": [...]}, same fields as the CSV
    #[arg(long)]
    json: bool,
    /// the tool profile: `paper001` (Table 2 radii) or a CSV file `height,radius` (mm above the
    /// tip, mm)
    #[arg(long, value_name = "paper001|FILE", verbatim_doc_comment)]
    profile: Option<String>,
    /// tool setup error: parallel offset (mm)
    #[arg(long, value_name = "MM", value_parser = number, allow_negative_numbers = true)]
    rho: Option<f64>,
    /// tool setup error: inclination (rad)
    #[arg(long, value_name = "RAD", value_parser = number, allow_negative_numbers = true)]
    phi: Option<f64>,
    /// number of axial layers (default 1)
    #[arg(long, value_name = "N", value_parser = whole)]
    layers: Option<usize>,
    /// the distance between layer tips (mm, default 3)
    #[arg(long, value_name = "MM", value_parser = number, allow_negative_numbers = true)]
    pitch: Option<f64>,
    /// the cutting length of the tool (mm, default 50)
    #[arg(long, value_name = "MM", value_parser = number, allow_negative_numbers = true)]
    cutting_length: Option<f64>,
    /// M3_15|M3_45: the cone frustums of paper 002 Table 3 instead (48 points, `curve` =
    /// <part>_Z<level>)
    #[arg(long, value_name = "s-shape|M3_15|M3_45", default_value = "s-shape", value_parser = part, verbatim_doc_comment)]
    part: Part,
    /// places the cone frustum with d = 62.5, p = 30 mm
    #[arg(long)]
    offsets: bool,
}

impl Args {
    /// Whether a profile or layer option is given (the layered columns).
    fn layered(&self) -> bool {
        self.profile.is_some()
            || self.rho.is_some()
            || self.phi.is_some()
            || self.layers.is_some()
            || self.pitch.is_some()
            || self.cutting_length.is_some()
    }
}

pub fn run(a: Args) -> Result<(), String> {
    let profile = a.profile.as_deref().map(read_profile).transpose()?;
    let layered = a.layered();
    if let Some(cone) = a.part.cone(a.offsets) {
        if a.surface_max || layered {
            return Err(
                "--surface-max and the profile/layer options apply to the S-shape only".into(),
            );
        }
        return cone_deviation(&cone, a.dr, a.json);
    }
    let part = SShape::iso();
    if a.surface_max {
        if a.dr != 0.0 || layered {
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
        return print_rows(a.json, "surfaces", "surface,max_overcut,u,z", &maxima);
    }
    if layered {
        return layered_deviation(&a, &part, profile);
    }
    let dev = points_deviation(&part, &builtin_points(&part), a.dr).map_err(|e| e.to_string())?;
    print_rows(a.json, "points", "id,curve,deviation", &dev)
}

/// The deviation at a cone frustum's points (surface A's flank path).
fn cone_deviation(cone: &ConeFrustum, dr: f64, json: bool) -> Result<(), String> {
    let path = FlankPath::new(cone, Surface::A);
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
    print_rows(json, "points", "id,curve,deviation", &rows)
}

/// The deviation with a tool profile, setup error and layers (paper 001).
fn layered_deviation(a: &Args, part: &SShape, profile: Option<ToolProfile>) -> Result<(), String> {
    let base = match profile {
        Some(p) => p,
        None => ToolProfile::constant(TOOL_RADIUS).map_err(|e| e.to_string())?,
    };
    if a.dr != 0.0 {
        return Err("--dr cannot be combined with a profile; put the radii in the profile".into());
    }
    let tool = base
        .with_setup_error(a.rho.unwrap_or(0.0), a.phi.unwrap_or(0.0))
        .map_err(|e| e.to_string())?;
    let plan = LayerPlan::try_new(
        a.layers.unwrap_or(1),
        a.pitch.unwrap_or(3.0),
        a.cutting_length.unwrap_or(50.0),
    )
    .map_err(|e| e.to_string())?;
    let res = multilayer_deviation(part, &builtin_points(part), &tool, &plan)
        .map_err(|e| e.to_string())?;
    print_rows(
        a.json,
        "points",
        "id,curve,deviation,layer,height,own_layer,own_deviation",
        &res,
    )
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
