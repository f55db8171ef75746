//! `testpiece diagnose FILE [--sigma MM] [--machine M] [--json]`: the sim-to-real gap of a
//! measured part.

use testpiece::analysis::{analyse_parts, Analysis, AnalysisOptions, Diagnosis, Fitted};
use testpiece::machine::Branch;

use crate::args::Args;

const HELP: &str = "\
testpiece diagnose FILE [--repeat FILE2 ...] [--sigma MM | --mpe A,K[,R0]] [--keep-outliers]
                        [--machine paper000|paper001|paper002] [--l0 MM]
                        [--branch signed|positive] [--exclude-bad-rows] [--json]

Diagnoses the sim-to-real gap of a measured S-shape part: the baseline (the machine's location
errors, physical mode) is fitted, the residual located (per curve, region, reversal), every candidate of
effects.md added one at a time and cross-validated (then pairs of the significant ones when no
single candidate explains the gap), and a verdict given (an effect id, with a second one when a
pair explains the gap, none or unexplained) with its detection limit.

FILE: any CMM export of shared/spec/cmm-csv.md; every point is matched to the nominal surfaces
by projection of its own coordinates, and the model (baseline and candidate signatures) is built
at the matched points.
--repeat FILE2  the same part measured again (the same point ids; give it once per repeat):
             σ is the pure error of the measurements' differences (no estimator), their mean is
             diagnosed with σ/√k, and the lack of fit of the location errors (F against the pure
             error) is reported: `repeat` {pure_error {sigma, dof, sigma_mean, largest},
             lack_of_fit {f, dof_fit, dof_pure, p_value}, summary}. Not with --sigma or --mpe.
--sigma MM   CMM repeatability (1σ, mm); default: estimated from the data: the smallest of
             estimates each blind to another kind of structure (fit plus a smooth basis per
             curve, its robust and second-difference versions, the variogram nugget) and, when
             that fit's residual is not white (a test calibrated for the fit, p < 1e-4), with
             each curve's strongest sinusoid along the tool path removed and from a tapered
             periodogram, so a short waviness is structure, not noise (JSON
             structure.noise: every estimate, smooth_whiteness_p, not_white). An estimate above
             3 µm is questioned in the report: give the CMM's figure or a repeat.
--mpe A,K[,R0]  the CMM's MPE_E = A + L/K µm (L = distance from the part origin, mm; R0 the
             repeatability range, µm): σ_i = max(MPE_E/√3, R0/1.693), the median used; not
             with --sigma. `noise` in the JSON says which σ and where from.
--keep-outliers  keep single-point outliers in the diagnosis. By default a point beyond the
             Bonferroni bound of the externally studentised residual (fit of the baseline plus a
             smooth basis per curve, robust σ, α = 0.05 over the points), isolated along its
             curve and explained by no candidate (a chip, dirt, a probing error) is left out and
             named: `points_excluded` [{id, reason}], `outliers` {points [{id, curve, size (mm),
             statistic}], rule, threshold, sigma, excluded, verdict_all_points (the verdict
             with every point)}.
--machine M  the machine whose location errors are the baseline and whose axes the backlash,
             scale and reversal candidates use: paper000 (B head / C table, default),
             paper002 (B-C tilting table); paper001 (A-B head) has no C axis for the catalogue's
             backlash_c and c_index, so its parts are diagnosed on paper000's machine and the
             summary says so. --l0 the pivot-to-tip length (mm, 499.889); --branch the B-axis
             branch of the inverse kinematics (signed, default, or positive).
--exclude-bad-rows  leave out the rows the reader rejects instead of refusing the file.
Any layout: 30 to 200 points or more, a curve not measured, ids of your own, rows in any order.
`layout` in the JSON (and a `Layout:` line when it is not the built-in 4 x 25) says what it
limits: points per curve, the smooth basis's degree there (min(5, m/2 - 1) on m points),
curves not measured, effects the location errors absorb entirely on these points.
The machine's location errors are then identified with what the diagnosis found (as
`testpiece identify`, default --effects auto): `corrected` holds that final answer.
--json       the report as JSON (shared/spec/cli.md); default: the plain-language summary.
             `corrected`: {parameters (the final location errors and effect parameters,
             {NAME: {value, std, unit, status, t}}), baseline_parameters, effects_included,
             shift (per location error, in std of the final answer), basis (effects,
             structure or baseline), summary}.
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
    let args = Args::parse(rest, &["sigma", "mpe", "machine", "l0", "branch", "repeat"])?;
    let json = args.flag("json");
    let exclude_bad_rows = args.flag("exclude-bad-rows");
    let sigma = args
        .value("sigma")
        .map(|s| {
            s.parse::<f64>()
                .map_err(|_| format!("--sigma: `{s}` is not a number"))
        })
        .transpose()?;
    let noise_mpe = crate::identify::parse_mpe(&args, sigma)?;
    let keep_outliers = args.flag("keep-outliers");
    let (machine, l0) = crate::identify::machine_and_l0(&args)?;
    let (_, branch) = crate::simulate::mode_and_branch(&args)?;
    let repeats: Vec<String> = args
        .values("repeat")
        .into_iter()
        .map(str::to_string)
        .collect();
    args.reject_unknown("diagnose")?;
    let [file] = args.positional.as_slice() else {
        return Err("diagnose needs exactly one FILE (see `testpiece diagnose --help`)".into());
    };
    let settings = AnalysisOptions {
        machine,
        l0,
        branch: Branch::parse(&branch)
            .ok_or_else(|| format!("--branch `{branch}`: expected signed or positive"))?,
        noise_sigma: sigma,
        noise_mpe,
        keep_outliers,
        exclude_bad_rows,
        ..AnalysisOptions::default()
    };
    let (a, _) = analyse_files(file, &repeats, &settings)?;
    let report = match &a.diagnosis {
        Diagnosis::Made { report, .. } => report,
        Diagnosis::NotMade { reason } => return Err(format!("{file}: {reason}")),
    };
    if json {
        let c = &a.correction;
        let mut v = serde_json::to_value(report).map_err(|e| e.to_string())?;
        v["corrected"] = serde_json::json!({
            "parameters": a.identification.parameters,
            "baseline_parameters": a.baseline.identification.parameters,
            "effects_included": c.effects_included,
            "shift": c.shift,
            "basis": c.basis,
            "std_includes_structure": c.std_includes_structure,
            "summary": c.summary,
        });
        let mut excluded: Vec<serde_json::Value> = a
            .identification
            .points_excluded
            .iter()
            .map(|x| serde_json::json!({"id": x.id, "reason": x.reason}))
            .collect();
        for r in &a.file.excluded {
            excluded.push(
                serde_json::json!({"id": format!("line {}", r.line), "reason": r.to_string()}),
            );
        }
        v["points_excluded"] = serde_json::Value::Array(excluded);
        v["outliers"] = serde_json::to_value(&a.outliers).map_err(|e| e.to_string())?;
        v["noise"] = serde_json::to_value(&a.noise).map_err(|e| e.to_string())?;
        if let Some(r) = &a.repeat {
            v["repeat"] = serde_json::to_value(r).map_err(|e| e.to_string())?;
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    } else {
        // The σ from an MPE is stated in the summary; a σ given or estimated is in the JSON.
        print!("{}", report.summary);
        println!("Corrected: {}", a.correction.summary);
    }
    Ok(())
}

/// Reads FILE and its repeats (the same points measured again) and analyses their mean
/// ([`analyse_parts`]); errors name the file.
pub fn analyse_files(
    file: &str,
    repeats: &[String],
    settings: &AnalysisOptions,
) -> Result<(Analysis, Fitted), String> {
    let mut contents = Vec::new();
    for f in std::iter::once(file).chain(repeats.iter().map(String::as_str)) {
        let bytes = std::fs::read(f).map_err(|e| format!("{f}: {e}"))?;
        let name = std::path::Path::new(f)
            .file_name()
            .map_or(f.to_string(), |n| n.to_string_lossy().into_owned());
        contents.push((bytes, name));
    }
    let files: Vec<(&[u8], &str)> = contents
        .iter()
        .map(|(b, n)| (b.as_slice(), n.as_str()))
        .collect();
    analyse_parts(&files, settings).map_err(|e| format!("{file}: {e}"))
}
