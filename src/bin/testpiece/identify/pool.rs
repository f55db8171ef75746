//! `testpiece identify FILE1 FILE2 ...`: one machine from the pooled points of several parts.

use testpiece::analysis::{prepare, AnalysisOptions};
use testpiece::pool::{identify_pooled, PoolError, PoolOptions, PooledIdentification};

use crate::common::{file_name, print_json, read, to_json};

/// What a pooled identification says about the correction of issue 17.
const POOL_NOT_CORRECTED: &str = "The pool is not diagnosed and NOT corrected for any unmodelled \
    effect: these are baseline values. Identify the parts one by one for their diagnosis and \
    corrected errors.";

/// Reads the files, identifies the pool and prints it (JSON or text).
pub fn run(
    files: &[String],
    analysis: AnalysisOptions,
    setup_per_part: bool,
    json: bool,
) -> Result<(), String> {
    let data = files
        .iter()
        .map(|f| read(f))
        .collect::<Result<Vec<_>, _>>()?;
    let names: Vec<String> = files.iter().map(|f| file_name(f)).collect();
    let list: Vec<(&[u8], &str)> = data
        .iter()
        .zip(&names)
        .map(|(b, n)| (b.as_slice(), n.as_str()))
        .collect();
    let opts = PoolOptions {
        analysis,
        setup_per_part,
    };
    let prepared = prepare(&opts.analysis).map_err(|source| {
        PoolError::Part {
            name: names[0].clone(),
            source,
        }
        .to_string()
    })?;
    let r = identify_pooled(&prepared, &list, &opts).map_err(|e| e.to_string())?;
    if json {
        print_json(&report_json(&r, &opts)?)
    } else {
        print_text(&r);
        Ok(())
    }
}

/// The identification's fields plus `pooled`, `corrected`, `parts`, `shared`, `per_part`.
fn report_json(r: &PooledIdentification, opts: &PoolOptions) -> Result<serde_json::Value, String> {
    let mut v = to_json(&r.identification)?;
    v["pooled"] = serde_json::json!(true);
    v["corrected"] = serde_json::json!(false);
    v["correction_note"] = serde_json::json!(POOL_NOT_CORRECTED);
    v["parts"] = to_json(&r.parts)?;
    v["shared"] = serde_json::json!(r.shared);
    v["per_part"] = serde_json::json!(r.per_part);
    v["mode"] = serde_json::json!(opts.analysis.mode.name());
    v["branch"] = to_json(&opts.analysis.branch)?;
    Ok(v)
}

/// The parts, the shared and per-part parameters, the groups and the residual.
fn print_text(r: &PooledIdentification) {
    let id = &r.identification;
    println!(
        "pooled: {} parts, {} points; rank {}, condition {:.4}",
        r.parts.len(),
        id.points_used,
        id.rank,
        id.condition
    );
    for p in &r.parts {
        println!(
            "  [{}] {}: {} points, residual rms {:.6} mm, mean {:.6} mm",
            p.index, p.name, p.points, p.residual_rms, p.residual_mean
        );
    }
    for p in &id.parameters.0 {
        let std = p.std.map_or("-".to_string(), |s| format!("{s:.3e}"));
        println!(
            "{:<8} {:>14.6e} {:>12} {}",
            p.name(),
            p.value,
            std,
            p.unit()
        );
    }
    for g in &id.groups {
        println!("group: {}", g.explanation);
    }
    println!(
        "residual: rms {:.6} mm, max |r| {:.6} mm",
        id.residual.rms, id.residual.max_abs
    );
    println!("{POOL_NOT_CORRECTED}");
}
