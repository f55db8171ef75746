//! `testpiece diagnose FILE [--sigma MM] [--json]`: the sim-to-real gap of a measured part.

use testpiece::analysis::{diagnose_points, measurement_points};
use testpiece::cmm::{read_and_match, ReadOptions};
use testpiece::part::SShape;

use crate::args::Args;

const HELP: &str = "\
testpiece diagnose FILE [--sigma MM] [--json]

Diagnoses the sim-to-real gap of a measured S-shape part: the baseline (the 8 location errors,
physical mode) is fitted, the residual located (per curve, region, reversal), every candidate of
effects.md added one at a time and cross-validated (then pairs of the significant ones when no
single candidate explains the gap), and a verdict given (an effect id, with a second one when a
pair explains the gap, none or unexplained) with its detection limit.

FILE: any CMM export of shared/spec/cmm-csv.md; every point is matched to the nominal surfaces
by projection of its own coordinates, and the model (baseline and candidate signatures) is built
at the matched points.
--sigma MM   CMM repeatability (1σ, mm); default: estimated from the data.
--exclude-bad-rows  leave out the rows the reader rejects instead of refusing the file.
--json       the report as JSON (shared/spec/cli.md); default: the plain-language summary.
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["sigma"])?;
    let json = args.flag("json");
    let exclude_bad_rows = args.flag("exclude-bad-rows");
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
    let bytes = std::fs::read(file).map_err(|e| format!("{file}: {e}"))?;
    let opts = ReadOptions::default().with_exclude_bad_rows(exclude_bad_rows);
    let name = std::path::Path::new(file)
        .file_name()
        .map_or(file.clone(), |n| n.to_string_lossy().into_owned());
    let part = SShape::iso();
    let matched = read_and_match(&bytes, &name, &opts).map_err(|e| format!("{file}: {e}"))?;
    let points = measurement_points(&part, &matched);
    let report = diagnose_points(&part, &points, &matched.deviations(), sigma)
        .map_err(|e| format!("{file}: {e}"))?;
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
