//! `testpiece identify FILE`: identify the machine's errors from a measured part.

use crate::args::Args;
use testpiece::analysis::{AnalysisOptions, Fitted};
use testpiece::final_fit::correct::{Basis, EffectsChoice};
use testpiece::identify::monte_carlo::{monte_carlo, CmmMpe, MonteCarloOptions, Noise};
use testpiece::identify::{export, ExcludedPoint, IdentifyOptions, Status};
use testpiece::machine::Branch;
use testpiece::pool::{identify_pooled, PoolOptions};
use testpiece::sensitivity::Mode;
use testpiece::settings::MachineChoice;

const HELP: &str = "\
testpiece identify FILE [--mode physical|paper] [--branch signed|positive] [--tool-radius]
                        [--effects auto|none|ID[,ID]]
                        [--json | --export csv|json] [--sigma MM | --mpe A,K[,R0]]
                        [--keep-outliers] [--no-refine]
                        [--exclude-bad-rows] [--monte-carlo RUNS] [--seed S]
                        [--machine paper000|paper001|paper002] [--l0 MM]
testpiece identify FILE1 FILE2 ... [--json] [--setup-per-part] [same options]

Identifies the 8 ISO 230-1 location errors (EC0Y EA0Z EB0Z EA0C EB0C EX0B EA0B EC0B; rad, EX0B
in mm) and, with --tool-radius, the tool-radius error dR (mm, + = a larger tool) from the
measured deviations of FILE: any CMM export of shared/spec/cmm-csv.md (delimited tables with
header synonyms, any separator, decimal comma, µm or inch columns; PC-DMIS XYZIJK; PowerInspect).
Weighted least squares on the linearised defect (paper 000 eq. 14), SVD of the unit-scaled
design: rank, condition number, and the groups of parameters the part cannot separate
(condition index >= 30) or sees only weakly (std above 1/4 of a typical error, 1e-4 rad or
0.01 mm). Every point is matched to the nominal surfaces by projection of its own
coordinates; the design is the sensitivity at the matched points. A file with a bad row is
refused with every bad row listed (line, column, text found, what was expected).

One answer per part: after this baseline identification the sim-to-real gap is diagnosed (as
`testpiece diagnose`), and the reported errors are the final identification:
- an effect named (e.g. backlash_y, or a pair): the location errors are fitted together with the
  effect's signature columns (parameters <id>.<parameter>, e.g. backlash_y.b in mm), refined with
  the exact model like the baseline; `shift` gives each error's move from the baseline in std;
  equivalent effects are tried in its place and the report says whether the errors depend on it;
- `unexplained`: no effect is fitted; the structure is modelled as a correlated error along the
  tool path (squared-exponential covariance, amplitude and length by REML) and the errors are
  fitted by generalised least squares: their std include the structure;
- `none`: the baseline stands.

--effects X       auto (default): what the diagnosis names; none: the baseline alone (the
                  answer before the diagnosis); ID[,ID]: fit these effects of effects.md whatever
                  the diagnosis says (e.g. --effects backlash_c,setup_error)
--json            {parameters (the final answer), baseline_parameters, effects_included, shift,
                  verdict, correction, groups, rank, condition, residual, points_used,
                  points_excluded, ...}
--compensation    the correction in the controller's terms: each axis's line (rotary: point
                  and direction; linear: direction), the tool tip at the reference pose and the
                  offset vectors machine zero -> rotation centres -> tool tip, in the machine
                  frame, before (nominal) and after entering the identified location errors, and the predicted part after compensation (measured minus the location
                  errors' part: a named effect or dR is not a location error and stays, said
                  in the notes); with --json the field `compensation`
--export csv|json the compensation table of the final answer: name, iso_230_1, value, unit, std,
                  status, fitted_with (effect ids joined by +, structure, or none)
--repeat FILE2    the same part measured again (same point ids; once per repeat): the mean
                  of the measurements is identified with σ = the pure error of their
                  differences / √k, and the JSON's `repeat` gives the pure error and the lack
                  of fit of the location errors. Not with --sigma, --mpe or a pool.
--sigma MM        a priori σ of the deviations instead of the residual's
--mpe A,K[,R0]    the CMM's MPE_E = A + L/K µm (L = the point's distance from the part origin,
                  mm) and optionally its repeatability range R0 (µm): σ_i = max(MPE_E/√3,
                  R0/1.693) per point (the Monte Carlo's rule), the median used as the σ of
                  every point; not with --sigma. The report says which σ and where from.
--keep-outliers   keep the single-point outliers in the fit. By default a point whose deviation
                  from the fit of the baseline plus a smooth basis per curve is beyond the
                  Bonferroni bound (externally studentised residual against a robust σ, α = 0.05
                  over the points), isolated along its curve and explained by no candidate effect
                  (a chip, dirt, a probing error) is left out of the identification and the
                  diagnosis and listed under points_excluded with its size and statistic; the
                  JSON's `outliers` gives the test (points, rule, threshold, sigma) and
                  verdict_all_points, the verdict with every point
--exclude-bad-rows  leave out the rows the reader rejects (listed under points_excluded)
--no-refine       skips the exact-model check: by default the exact eq. 12 is evaluated at the
                  linear solution and Levenberg-Marquardt refines it when the linearisation error
                  exceeds 0.1 σ (reported under \"refinement\")
--machine M       the chain: paper000 (B head / C table, default), paper001 (A-B head),
                  paper002 (B-C tilting table); --l0 its pivot-to-tip length (mm, 499.889)
--monte-carlo N   adds a Monte Carlo check (N runs, --seed, default 7) with the noise of the
                  CMM of --mpe, else of the paper's CMM: MPE_E = ±(3 + L/75) µm, R0 = 3 µm;
                  σ = max(MPE/√3, R0/1.693) per point

Several files: one machine from the pooled points of several parts (or repeated measurements)
of the same machine and settings. The location errors are shared; with --tool-radius each part
gets its own dR[k] (another or a reground tool per part); --setup-per-part adds each part's CMM
datum alignment Rz[k] (rad), Tx[k], Ty[k] (mm). Point ids become k:id. The JSON has the fields
of one file plus `pooled: true`, `parts` (name, points, residual_rms, residual_mean per part),
`shared` and `per_part` (parameter names). No exact-model refinement on the pool, and no gap
diagnosis: the pool is NOT corrected for any effect (`corrected: false`); identify the parts
one by one for their diagnosis and corrected errors.
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(
        rest,
        &[
            "mode",
            "branch",
            "export",
            "sigma",
            "mpe",
            "monte-carlo",
            "seed",
            "machine",
            "l0",
            "effects",
            "repeat",
        ],
    )?;
    let (mode, branch) = crate::simulate::mode_and_branch(&args)?;
    let tool_radius = args.flag("tool-radius");
    let json = args.flag("json");
    let no_refine = args.flag("no-refine");
    let with_compensation = args.flag("compensation");
    let exclude_bad_rows = args.flag("exclude-bad-rows");
    let export_fmt = args.value("export").map(str::to_string);
    let sigma = match args.value("sigma") {
        Some(t) => Some(
            t.parse::<f64>()
                .map_err(|_| format!("--sigma `{t}`: expected a number of mm"))?,
        ),
        None => None,
    };
    let runs = match args.value("monte-carlo") {
        Some(t) => Some(
            t.parse::<usize>()
                .map_err(|_| format!("--monte-carlo `{t}`: expected a number of runs"))?,
        ),
        None => None,
    };
    let seed: u64 = match args.value("seed") {
        Some(t) => t
            .parse()
            .map_err(|_| format!("--seed `{t}`: expected a non-negative integer"))?,
        None => 7,
    };
    let noise_mpe = parse_mpe(&args, sigma)?;
    let keep_outliers = args.flag("keep-outliers");
    let (machine, l0) = machine_and_l0(&args)?;
    let setup_per_part = args.flag("setup-per-part");
    let effects: EffectsChoice = args
        .value("effects")
        .unwrap_or("auto")
        .parse()
        .map_err(|e| format!("--effects: {e}"))?;
    let repeats: Vec<String> = args
        .values("repeat")
        .into_iter()
        .map(str::to_string)
        .collect();
    args.reject_unknown("identify")?;
    let settings = AnalysisOptions {
        machine,
        l0,
        mode: Mode::parse(&mode).map_err(|e| e.to_string())?,
        branch: Branch::parse(&branch)
            .ok_or_else(|| format!("--branch `{branch}`: expected signed or positive"))?,
        tool_radius,
        exclude_bad_rows,
        noise_sigma: sigma,
        noise_mpe,
        keep_outliers,
        refine: !no_refine,
        known: None,
        effects,
    };
    if args.positional.len() >= 2 {
        if !repeats.is_empty() {
            return Err(
                "--repeat takes one FILE (the part measured again), not a pool".to_string(),
            );
        }
        if export_fmt.is_some() || runs.is_some() {
            return Err("--export and --monte-carlo take one FILE, not a pool".to_string());
        }
        if with_compensation {
            return Err(
                "--compensation takes one FILE: a pool is not diagnosed, so what the correction \
                 leaves on a part is not known (identify the parts one by one)"
                    .to_string(),
            );
        }
        if settings.noise_mpe.is_some() || settings.keep_outliers {
            return Err(
                "--mpe and --keep-outliers take one FILE: a pool is not tested for outliers \
                 (identify the parts one by one) and takes --sigma for the CMM noise"
                    .to_string(),
            );
        }
        if args.value("effects").is_some_and(|e| e != "none") {
            return Err(
                "--effects: a pool is not diagnosed, so it cannot be corrected for an effect; \
                 identify the parts one by one"
                    .to_string(),
            );
        }
        return pooled(&args.positional, settings, setup_per_part, json);
    }
    if setup_per_part {
        return Err("--setup-per-part needs several files to pool".to_string());
    }
    let [file] = args.positional.as_slice() else {
        return Err("`testpiece identify` needs a FILE (see --help)".to_string());
    };
    if let Some(f) = &export_fmt {
        if f != "csv" && f != "json" {
            return Err(format!("--export `{f}`: expected csv or json"));
        }
    }
    let (analysis, fitted) = crate::diagnose::analyse_files(file, &repeats, &settings)?;
    let lengths = analysis.lengths();
    let Fitted {
        design,
        observations: obs,
    } = fitted;
    let mut opts = IdentifyOptions::default();
    if let Some(s) = analysis.noise.sigma {
        opts = opts.with_sigma(s);
    }
    let mut id = analysis.identification.clone();
    for r in &analysis.file.excluded {
        id.points_excluded.push(ExcludedPoint {
            id: format!("line {}", r.line),
            reason: r.to_string(),
        });
    }
    let refinement = analysis.refinement.clone();
    let fitted_with = &analysis.correction.fitted_with;
    if let Some(f) = export_fmt {
        if f == "csv" {
            print!("{}", export::compensation_csv(&id, fitted_with));
        } else {
            println!("{}", export::compensation_json(&id, fitted_with));
        }
        return Ok(());
    }
    let mc = match runs {
        Some(r) => {
            let cmm = noise_mpe.unwrap_or_else(CmmMpe::paper000);
            let noise = Noise::from_mpe(&cmm, &lengths);
            let o = MonteCarloOptions::default().with_runs(r).with_seed(seed);
            Some(
                monte_carlo(&design, &obs, &id.values(), &noise, &o, &opts)
                    .map_err(|e| e.to_string())?,
            )
        }
        None => None,
    };
    if json {
        let mut v = serde_json::to_value(&id).map_err(|e| e.to_string())?;
        v["mode"] = serde_json::json!(mode);
        v["branch"] = serde_json::json!(branch);
        if let Some(r) = &refinement {
            v["refinement"] = serde_json::to_value(r).map_err(|e| e.to_string())?;
        }
        let c = &analysis.correction;
        v["baseline_parameters"] =
            serde_json::to_value(&analysis.baseline.identification.parameters)
                .map_err(|e| e.to_string())?;
        v["effects_included"] =
            serde_json::to_value(&c.effects_included).map_err(|e| e.to_string())?;
        v["shift"] = serde_json::to_value(&c.shift).map_err(|e| e.to_string())?;
        v["verdict"] = serde_json::to_value(c.verdict).map_err(|e| e.to_string())?;
        v["correction"] = serde_json::to_value(c).map_err(|e| e.to_string())?;
        v["outliers"] = serde_json::to_value(&analysis.outliers).map_err(|e| e.to_string())?;
        v["noise"] = serde_json::to_value(&analysis.noise).map_err(|e| e.to_string())?;
        if let Some(r) = &analysis.repeat {
            v["repeat"] = serde_json::to_value(r).map_err(|e| e.to_string())?;
        }
        if let Some(mc) = mc {
            v["monte_carlo"] = serde_json::to_value(mc).map_err(|e| e.to_string())?;
        }
        if with_compensation {
            v["compensation"] =
                serde_json::to_value(testpiece::compensation::compensation(&analysis))
                    .map_err(|e| e.to_string())?;
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    println!(
        "mode {mode}, branch {branch}: {} points used, {} excluded",
        id.points_used,
        id.points_excluded.len()
    );
    println!(
        "rank {} (solved {}), condition {:.4}",
        id.rank, id.rank_used, id.condition
    );
    println!(
        "{:<6} {:>14} {:>12} {:<4} status",
        "name", "value", "std", "unit"
    );
    for p in &id.parameters.0 {
        let std = p.std.map_or("-".to_string(), |s| format!("{s:.3e}"));
        let status = match p.status {
            Status::Identified => "identified",
            Status::Weak => "weak",
            Status::NotSeparable => "not separable",
        };
        println!(
            "{:<6} {:>14.6e} {:>12} {:<4} {status}",
            p.name, p.value, std, p.unit
        );
    }
    for g in &id.groups {
        println!("group: {}", g.explanation);
        for e in &g.estimable {
            println!(
                "  {} = {:.6e} ± {}",
                e.combination.text,
                e.value,
                e.std.map_or("-".into(), |s| format!("{s:.3e}"))
            );
        }
    }
    println!(
        "residual: rms {:.6} mm, max |r| {:.6} mm, MAD {:.6} mm, RMSE {:.6} mm",
        id.residual.rms, id.residual.max_abs, id.residual.mad, id.residual.rmse
    );
    for c in &id.per_curve {
        println!(
            "  {}: rms {:.6} mm, max |r| {:.6} mm",
            c.curve, c.stats.rms, c.stats.max_abs
        );
    }
    if let Some(r) = &refinement {
        println!("exact model: {}", r.reason);
    }
    println!("final answer: {}", analysis.correction.summary);
    let shifts: Vec<String> = analysis
        .correction
        .shift
        .0
        .iter()
        .filter_map(|s| s.std.map(|v| format!("{} {v:+.1}", s.parameter)))
        .collect();
    if analysis.correction.basis != Basis::Baseline && !shifts.is_empty() {
        println!("shift from the baseline (std): {}", shifts.join(", "));
    }
    for x in &id.points_excluded {
        println!("excluded {}: {}", x.id, x.reason);
    }
    if !analysis.outliers.summary.is_empty() {
        println!("Outliers: {}", analysis.outliers.summary);
        if let Some(v) = analysis
            .outliers
            .verdict_all_points
            .filter(|_| analysis.outliers.excluded)
        {
            println!("With every point, outliers included, the verdict would be `{v}`.");
        }
    }
    println!("{}", analysis.noise.summary);
    if with_compensation {
        crate::compensation::print(&testpiece::compensation::compensation(&analysis));
    }
    if let Some(mc) = mc {
        println!(
            "Monte Carlo ({} runs, seed {}, σ {:.2e}..{:.2e} mm):",
            mc.runs, mc.seed, mc.sigma_min, mc.sigma_max
        );
        for p in &mc.parameters {
            println!(
                "  {:<6} std MC {:.3e}, predicted {:.3e}",
                p.name, p.std_mc, p.std_predicted
            );
        }
    }
    Ok(())
}

/// The file name of a path (for messages and part names).
pub fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .map_or(path.to_string(), |n| n.to_string_lossy().into_owned())
}

/// `identify FILE1 FILE2 ...`: one machine from the pooled points.
fn pooled(
    files: &[String],
    analysis: AnalysisOptions,
    setup_per_part: bool,
    json: bool,
) -> Result<(), String> {
    let data = files
        .iter()
        .map(|f| std::fs::read(f).map_err(|e| format!("{f}: {e}")))
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
    let r = identify_pooled(&list, &opts).map_err(|e| e.to_string())?;
    let id = &r.identification;
    if json {
        let mut v = serde_json::to_value(id).map_err(|e| e.to_string())?;
        v["pooled"] = serde_json::json!(true);
        v["corrected"] = serde_json::json!(false);
        v["correction_note"] = serde_json::json!(POOL_NOT_CORRECTED);
        v["parts"] = serde_json::to_value(&r.parts).map_err(|e| e.to_string())?;
        v["shared"] = serde_json::json!(r.shared);
        v["per_part"] = serde_json::json!(r.per_part);
        v["mode"] = serde_json::json!(opts.analysis.mode.name());
        v["branch"] = serde_json::to_value(opts.analysis.branch).map_err(|e| e.to_string())?;
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
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
        println!("{:<8} {:>14.6e} {:>12} {}", p.name, p.value, std, p.unit);
    }
    for g in &id.groups {
        println!("group: {}", g.explanation);
    }
    println!(
        "residual: rms {:.6} mm, max |r| {:.6} mm",
        id.residual.rms, id.residual.max_abs
    );
    println!("{POOL_NOT_CORRECTED}");
    Ok(())
}

/// What a pooled identification says about the correction of issue 17.
const POOL_NOT_CORRECTED: &str = "The pool is not diagnosed and NOT corrected for any unmodelled \
    effect: these are baseline values. Identify the parts one by one for their diagnosis and \
    corrected errors.";

/// `--mpe A,K[,R0]` (µm, mm, µm): the CMM's MPE; refused together with `--sigma`.
pub fn parse_mpe(args: &Args, sigma: Option<f64>) -> Result<Option<CmmMpe>, String> {
    let Some(t) = args.value("mpe") else {
        return Ok(None);
    };
    if let Some(s) = sigma {
        return Err(format!(
            "--sigma {s} and --mpe {t} both give the CMM noise: give one of them \
             (--sigma the σ in mm, --mpe the MPE A + L/K in µm)"
        ));
    }
    let v: Vec<f64> = t
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("--mpe `{t}`: expected A,K or A,K,R0 (numbers: µm, mm, µm)"))?;
    let (a, k, r0) = match v.as_slice() {
        [a, k] => (*a, *k, 0.0),
        [a, k, r0] => (*a, *k, *r0),
        _ => {
            return Err(format!(
                "--mpe `{t}`: expected A,K or A,K,R0 (MPE_E = A + L/K µm, R0 in µm)"
            ))
        }
    };
    CmmMpe::try_new(a, k, r0)
        .map(Some)
        .map_err(|e| format!("--mpe `{t}`: {e}"))
}

/// `--machine paper000|paper001|paper002` and `--l0 MM` (default paper 000's 499.889 mm).
pub fn machine_and_l0(args: &Args) -> Result<(MachineChoice, f64), String> {
    let machine = match args.value("machine").unwrap_or("paper000") {
        "paper000" => MachineChoice::Paper000,
        "paper001" => MachineChoice::Paper001,
        "paper002" => MachineChoice::Paper002,
        m => {
            return Err(format!(
                "--machine `{m}`: expected paper000, paper001 or paper002"
            ))
        }
    };
    let l0 = match args.value("l0") {
        Some(t) => t
            .parse::<f64>()
            .map_err(|_| format!("--l0 `{t}`: expected a length in mm"))?,
        None => testpiece::machine::chain::PAPER000_L0,
    };
    Ok((machine, l0))
}
