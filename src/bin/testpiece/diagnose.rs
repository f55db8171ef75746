//! `testpiece diagnose FILE [--sigma MM] [--machine M] [--json]`: the sim-to-real gap of a
//! measured part.

use testpiece::analysis::{diagnose_on_machine, measurement_points, AnalysisOptions, Diagnosis};
use testpiece::cmm::{read_and_match, ReadOptions};
use testpiece::machine::Branch;
use testpiece::part::SShape;

use crate::args::Args;

const HELP: &str = "\
testpiece diagnose FILE [--sigma MM] [--machine paper000|paper001|paper002] [--l0 MM]
                        [--branch signed|positive] [--exclude-bad-rows] [--json]

Diagnoses the sim-to-real gap of a measured S-shape part: the baseline (the machine's location
errors, physical mode) is fitted, the residual located (per curve, region, reversal), every candidate of
effects.md added one at a time and cross-validated (then pairs of the significant ones when no
single candidate explains the gap), and a verdict given (an effect id, with a second one when a
pair explains the gap, none or unexplained) with its detection limit.

FILE: any CMM export of shared/spec/cmm-csv.md; every point is matched to the nominal surfaces
by projection of its own coordinates, and the model (baseline and candidate signatures) is built
at the matched points.
--sigma MM   CMM repeatability (1σ, mm); default: estimated from the data.
--machine M  the machine whose location errors are the baseline and whose axes the backlash,
             scale and reversal candidates use: paper000 (B head / C table, default),
             paper002 (B-C tilting table); paper001 (A-B head) has no C axis for the catalogue's
             backlash_c and c_index, so its parts are diagnosed on paper000's machine and the
             summary says so. --l0 the pivot-to-tip length (mm, 499.889); --branch the B-axis
             branch of the inverse kinematics (signed, default, or positive).
--exclude-bad-rows  leave out the rows the reader rejects instead of refusing the file.
--json       the report as JSON (shared/spec/cli.md); default: the plain-language summary.
             verdict.kind is noise, unexplained or named; verdict.effect the id (none,
             unexplained or an effect of effects.md), verdict.with the pair's second effect.
             Each `where` entry names its group (curve, region, lean, reversal) with the
             group's own fields (a reversal: axis, s in mm of tool path, nearest point id,
             of_verdict, marked) and whether the residual is concentrated there (> 1.5x its
             share).
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["sigma", "machine", "l0", "branch"])?;
    let json = args.flag("json");
    let exclude_bad_rows = args.flag("exclude-bad-rows");
    let sigma = args
        .value("sigma")
        .map(|s| {
            s.parse::<f64>()
                .map_err(|_| format!("--sigma: `{s}` is not a number"))
        })
        .transpose()?;
    let (machine, l0) = crate::identify::machine_and_l0(&args)?;
    let (_, branch) = crate::simulate::mode_and_branch(&args)?;
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
    let settings = AnalysisOptions {
        machine,
        l0,
        branch: Branch::parse(&branch)
            .ok_or_else(|| format!("--branch `{branch}`: expected signed or positive"))?,
        noise_sigma: sigma,
        ..AnalysisOptions::default()
    };
    let report = match diagnose_on_machine(&part, &points, &matched.deviations(), &settings) {
        Diagnosis::Made { report, .. } => report,
        Diagnosis::NotMade { reason } => return Err(format!("{file}: {reason}")),
    };
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
