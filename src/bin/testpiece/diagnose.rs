//! `testpiece diagnose FILE [--sigma MM] [--machine M] [--json]`: the sim-to-real gap of a
//! measured part.

use testpiece::analysis::{Analysis, AnalysisOptions, Diagnosis};
use testpiece::gap::DiagnosisReport;
use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::Branch;
use testpiece::settings::MachineChoice;

use crate::common::{
    analyse_files, branch, cmm_noise, leave_to_exit, machine, mm, mpe, print_json, threads,
    to_json, Mpe,
};

/// the sim-to-real gap of a measured part: where, which effect, how far [--json]
///
/// Diagnoses the sim-to-real gap of a measured S-shape part: the baseline (the machine's location
/// errors, physical mode) is fitted, the residual located (per curve, region, reversal), every
/// candidate of effects.md added one at a time and cross-validated (then pairs of the significant
/// ones when no single candidate explains the gap), and a verdict given (an effect id, with a
/// second one when a pair explains the gap, none or unexplained) with its detection limit. When
/// the pair's second effect is significant but below the detection limit, the first is named
/// alone and the second listed as possible below the limit.
///
/// FILE: any CMM export of shared/spec/cmm-csv.md; every point is matched to the nominal surfaces
/// by projection of its own coordinates, and the model (baseline and candidate signatures) is built
/// at the matched points.
/// Any layout: 30 to 200 points or more, a curve not measured, ids of your own, rows in any order.
/// `layout` in the JSON (and a `Layout:` line when it is not the built-in 4 x 25) says what it
/// limits: points per curve, the smooth basis's degree there (min(5, m/2 - 1) on m points),
/// curves not measured, effects the location errors absorb entirely on these points.
/// A scanning CMM's file (500 points or more, no ids needed) is read as a scan: its points
/// grouped by surface and scan line of constant height, or in height bands where the heights
/// form no lines (staggered rulings, a cloud); `scan` in the JSON and a `Scan:` line give its
/// lines or bands, `separability` and a `Separability:` line what its heights tell apart.
/// The machine's location errors are then identified with what the diagnosis found (as
/// `testpiece identify`, default --effects auto): `corrected` holds that final answer.
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the measured part (any CMM export)
    #[arg(value_name = "FILE")]
    files: Vec<String>,
    /// the same part measured again (the same point ids; give it once per repeat)
    ///
    /// The pure error of the measurements' differences is the CMM's repeatability; their mean
    /// is diagnosed with σ/√k as the CMM's share, a floor to which the part's own scatter
    /// (which probing again does not resample) is added from the data, and the lack of fit of
    /// the location errors against the pure error alone is reported: `repeat` {pure_error
    /// {sigma, dof, sigma_mean, largest}, lack_of_fit {f, dof_fit, dof_pure, p_value}, summary}.
    /// Not with --sigma or --mpe.
    #[arg(long, value_name = "FILE2", verbatim_doc_comment)]
    repeat: Vec<String>,
    /// CMM repeatability (1σ, mm): the CMM's share of σ, a floor; default: σ estimated
    ///
    /// From the data: the differences of the two heights of each ruling (structure along the
    /// tool path cancels in them) pooled with the variogram nugget of the residual, or the
    /// smaller when they disagree; with --sigma the part's own scatter is added when σ̂ is
    /// significantly above it. A σ̂ significantly above what a CMM and a finished flank give
    /// (3 µm, or √(σ² + 2.5²) µm with --sigma) is structure, never noise (JSON structure.noise:
    /// estimator, estimated, part_scatter, ceiling, implausible, used and every estimate).
    #[arg(long, value_name = "MM", value_parser = mm, allow_negative_numbers = true, verbatim_doc_comment)]
    sigma: Option<f64>,
    /// the CMM's MPE_E = A + L/K µm (L = distance from the part origin, mm; R0 the
    /// repeatability range, µm)
    ///
    /// σ_i = max(MPE_E/√3, R0/1.693), the median used; not with --sigma. `noise` in the JSON
    /// says which σ and where from.
    #[arg(long, value_name = "A,K[,R0]", value_parser = mpe, verbatim_doc_comment)]
    mpe: Option<Mpe>,
    /// keep single-point outliers in the diagnosis
    ///
    /// By default a point beyond the Bonferroni bound of the externally studentised residual (fit
    /// of the baseline plus a smooth basis per curve, robust σ, α = 0.05 over the points),
    /// isolated along its curve and explained by no candidate (a chip, dirt, a probing error) is
    /// left out and named: `points_excluded` [{id, reason}], `outliers` {points [{id, curve, size
    /// (mm), statistic}], rule, threshold, sigma, excluded, verdict_all_points (the verdict with
    /// every point)}.
    #[arg(long, verbatim_doc_comment)]
    keep_outliers: bool,
    /// the machine whose location errors are the baseline and whose axes the backlash, scale and
    /// reversal candidates use
    ///
    /// paper000 (B head / C table, default), paper002 (B-C tilting table); paper001 (A-B head)
    /// has no C axis for the catalogue's backlash_c and c_index, so its parts are diagnosed on
    /// paper000's machine and the summary says so.
    #[arg(long, value_name = "paper000|paper001|paper002", default_value = "paper000", value_parser = machine, verbatim_doc_comment)]
    machine: MachineChoice,
    /// the pivot-to-tip length (mm)
    #[arg(long, value_name = "MM", default_value_t = PAPER000_L0, value_parser = mm, allow_negative_numbers = true)]
    l0: f64,
    /// the B-axis branch of the inverse kinematics
    #[arg(long, value_name = "signed|positive", default_value = "signed", value_parser = branch)]
    branch: Branch,
    /// the feed the part was cut with (mm/min): a servo lag the diagnosis names (fitted with the
    /// rounding of the path by the lag all axes share) is stated as the position loop's time
    /// constant (1/Kv, ms) at it
    #[arg(long, value_name = "MM_PER_MIN", default_value_t = testpiece::settings::feed::PROGRAMME_FEED, value_parser = mm, allow_negative_numbers = true)]
    feed: f64,
    /// leave out the rows the reader rejects instead of refusing the file
    #[arg(long)]
    exclude_bad_rows: bool,
    /// threads the reading, the part model, the diagnosis and the exact-model refinement use
    /// (default: the machine's cores); the results are the same, bit for bit, on any count
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
    /// the report as JSON (shared/spec/cli.md); default: the plain-language summary
    ///
    /// `corrected`: {parameters (the final location errors and effect parameters,
    /// {NAME: {value, std, unit, status, t}}), baseline_parameters, effects_included,
    /// shift (per location error, in std of the final answer), basis (effects,
    /// structure or baseline), summary}.
    /// verdict.kind is noise, unexplained or named; verdict.effect the id (none,
    /// unexplained or an effect of effects.md), verdict.with the pair's second effect.
    /// Each `where` entry names its group (curve, region, lean, reversal) with the
    /// group's own fields (a reversal: axis, s in mm of tool path, nearest point id,
    /// of_verdict, marked) and whether the residual is concentrated there (> 1.5x its
    /// share).
    #[arg(long, verbatim_doc_comment)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), String> {
    let settings = AnalysisOptions {
        machine: a.machine,
        l0: a.l0,
        branch: a.branch,
        noise_sigma: a.sigma,
        noise_mpe: cmm_noise(a.sigma, a.mpe.as_ref())?,
        keep_outliers: a.keep_outliers,
        exclude_bad_rows: a.exclude_bad_rows,
        feed: a.feed,
        threads: threads(a.threads),
        ..AnalysisOptions::default()
    };
    let [file] = a.files.as_slice() else {
        return Err("diagnose needs exactly one FILE (see `testpiece diagnose --help`)".into());
    };
    let analysis = analyse_files(file, &a.repeat, &settings)?;
    let printed = print(&analysis.0, file, a.json);
    leave_to_exit(analysis);
    printed
}

/// The report of `analysis` (of `file`) on stdout: its JSON or its summary.
fn print(analysis: &Analysis, file: &str, json: bool) -> Result<(), String> {
    let report = match &analysis.diagnosis {
        Diagnosis::Made { report, .. } => report,
        Diagnosis::NotMade { reason } => return Err(format!("{file}: {reason}")),
    };
    if json {
        print_json(&report_json(report, analysis)?)
    } else {
        // The σ from an MPE is stated in the summary; a σ given or estimated is in the JSON.
        print!("{}", report.summary);
        println!("Corrected: {}", analysis.correction.summary);
        Ok(())
    }
}

/// The report plus `corrected` (the final answer), every excluded point or row, the outliers,
/// the noise and the repeat.
fn report_json(report: &DiagnosisReport, a: &Analysis) -> Result<serde_json::Value, String> {
    let c = &a.correction;
    let mut v = to_json(report)?;
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
        excluded
            .push(serde_json::json!({"id": format!("line {}", r.line), "reason": r.to_string()}));
    }
    v["points_excluded"] = serde_json::Value::Array(excluded);
    v["outliers"] = to_json(&a.outliers)?;
    v["noise"] = to_json(&a.noise)?;
    if let Some(r) = &a.repeat {
        v["repeat"] = to_json(r)?;
    }
    if let Some(l) = &a.scan {
        v["scan"] = to_json(l)?;
    }
    Ok(v)
}
