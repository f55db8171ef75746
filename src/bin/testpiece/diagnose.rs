//! `testpiece diagnose FILE [--sigma MM] [--json]`: the sim-to-real gap of a measured part.

use testpiece::gap::effects::builtin::{builtin_model, PartModel};
use testpiece::gap::{diagnose, GapInput};
use testpiece::part::SShape;

use crate::args::Args;

const HELP: &str = "\
testpiece diagnose FILE [--sigma MM] [--json]

Diagnoses the sim-to-real gap of a measured S-shape part: the baseline (the 8 location errors,
physical mode) is fitted, the residual located (per curve, region, reversal), every candidate of
effects.md added one at a time and cross-validated, and a verdict given (an effect id, none or
unexplained) with its detection limit.

FILE: the canonical CSV `id,curve,x,y,z,nx,ny,nz,deviation` (mm) of the 100 built-in points.
--sigma MM   CMM repeatability (1σ, mm); default: estimated from the data.
--json       the report as JSON (shared/spec/cli.md); default: the plain-language summary.
";

/// Deviations of the built-in points from a measured file, in built-in order. Kept behind this
/// one function: the canonical CSV of the built-in points (ids 1-100, positions checked within
/// 1e-3 mm of the built-in points).
pub fn read_deviations(text: &str, model: &PartModel) -> Result<Vec<f64>, String> {
    let t = testpiece::gap::table::Table::parse(text).map_err(|e| e.to_string())?;
    let ids = t.numbers("id").map_err(|e| e.to_string())?;
    let dev = t.numbers("deviation").map_err(|e| e.to_string())?;
    let pts = testpiece::part::builtin_points(&SShape::iso());
    let xyz = ["x", "y", "z"]
        .iter()
        .map(|c| t.numbers(c).ok())
        .collect::<Option<Vec<_>>>();
    let mut out = vec![f64::NAN; model.points.len()];
    for (row, (&id, &d)) in ids.iter().zip(&dev).enumerate() {
        let k = model
            .points
            .iter()
            .position(|p| f64::from(p.id) == id)
            .ok_or_else(|| {
                format!(
                    "line {}: point id {id} is not one of the 100 built-in points",
                    row + 2
                )
            })?;
        if let Some(xyz) = &xyz {
            let p = pts[k].point;
            let dist = ((xyz[0][row] - p.x).powi(2)
                + (xyz[1][row] - p.y).powi(2)
                + (xyz[2][row] - p.z).powi(2))
            .sqrt();
            if dist > 1e-3 {
                return Err(format!(
                    "line {}: point {id} lies {dist:.4} mm from built-in point {id}; only the built-in layout is supported by `diagnose` in this version",
                    row + 2
                ));
            }
        }
        out[k] = d;
    }
    if let Some(k) = out.iter().position(|v| v.is_nan()) {
        return Err(format!(
            "point {} is missing from the file",
            model.points[k].id
        ));
    }
    Ok(out)
}

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["sigma"])?;
    let json = args.flag("json");
    let sigma = args
        .value("sigma")
        .map(|s| {
            s.parse::<f64>()
                .map_err(|_| format!("--sigma: `{s}` is not a number"))
        })
        .transpose()?;
    args.reject_unknown("diagnose")?;
    let [file] = args.positional.as_slice() else {
        return Err("diagnose needs exactly one FILE (see `testpiece diagnose --help`)".into());
    };
    let text = std::fs::read_to_string(file).map_err(|e| format!("{file}: {e}"))?;
    let model = builtin_model(&SShape::iso()).map_err(|e| e.to_string())?;
    let deviations = read_deviations(&text, &model)?;
    let report = diagnose(&GapInput {
        deviations,
        points: model.points,
        baseline: model.baseline,
        candidates: model.candidates,
        noise_sigma: sigma,
        reversals: model.reversals,
    })
    .map_err(|e| e.to_string())?;
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?
        );
    } else {
        print!("{}", report.summary);
    }
    Ok(())
}
