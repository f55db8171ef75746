//! `testpiece identify FILE`: identify the machine's errors from a measured part; `identify FILE1
//! FILE2 ...` pools several parts ([`pool`]).

mod compensation;
mod pool;
mod text;

use testpiece::analysis::{Analysis, AnalysisOptions, Fitted};
use testpiece::final_fit::correct::EffectsChoice;
use testpiece::identify::monte_carlo::{
    monte_carlo, CmmMpe, MonteCarloOptions, MonteCarloReport, Noise,
};
use testpiece::identify::{export, ExcludedPoint, Identification, IdentifyOptions};
use testpiece::machine::chain::PAPER000_L0;
use testpiece::settings::MachineChoice;

use crate::common::{
    analyse_files, branch_name, cmm_noise, machine, mm, mpe, print_json, seed, threads, to_json,
    whole, ModeBranch, Mpe,
};

/// the machine errors, groups, uncertainty and residuals; --compensation: the errors as the controller's kinematic description and the part after correction
///
/// Identifies the 8 ISO 230-1 location errors (EC0Y EA0Z EB0Z EA0C EB0C EX0B EA0B EC0B; rad, EX0B
/// in mm) and, with --tool-radius, the tool-radius error dR (mm, + = a larger tool) from the
/// measured deviations of FILE: any CMM export of shared/spec/cmm-csv.md (delimited tables with
/// header synonyms, any separator, decimal comma, µm or inch columns; PC-DMIS XYZIJK; PowerInspect;
/// the DMIS output of the plan's program, FA(P<id>_<curve>)=FEAT/POINT,CART,x,y,z,i,j,k).
/// Weighted least squares on the linearised defect (paper 000 eq. 14), SVD of the unit-scaled
/// design: rank, condition number, and the groups of parameters the part cannot separate
/// (condition index >= 30) or sees only weakly (std above 1/4 of a typical error, 1e-4 rad or
/// 0.01 mm). Every point is matched to the nominal surfaces by projection of its own
/// coordinates; the design is the sensitivity at the matched points. A file with a bad row is
/// refused with every bad row listed (line, column, text found, what was expected).
///
/// One answer per part: after this baseline identification the sim-to-real gap is diagnosed (as
/// `testpiece diagnose`), and the reported errors are the final identification:
/// - an effect named (e.g. backlash_y, or a pair): the location errors are fitted together with the
///   effect's signature columns (parameters <id>.<parameter>, e.g. backlash_y.b in mm), refined with
///   the exact model like the baseline; `shift` gives each error's move from the baseline in std;
///   equivalent effects are tried in its place and the report says whether the errors depend on it;
/// - `unexplained`: no effect is fitted; the structure is modelled as a correlated error along the
///   tool path (squared-exponential covariance, amplitude and length by REML) and the errors are
///   fitted by generalised least squares: their std include the structure;
/// - `none`: the baseline stands.
///
/// Several files (FILE1 FILE2 ...): one machine from the pooled points of several parts (or
/// repeated measurements) of the same machine and settings. The location errors are shared; with
/// --tool-radius each part gets its own dR[k] (another or a reground tool per part);
/// --setup-per-part adds each part's CMM datum alignment Rz[k] (rad), Tx[k], Ty[k] (mm). Point ids
/// become k:id. The JSON has the fields of one file plus `pooled: true`, `parts` (name, points,
/// residual_rms, residual_mean per part), `shared` and `per_part` (parameter names). No
/// exact-model refinement on the pool, and no gap diagnosis: the pool is NOT corrected for any
/// effect (`corrected: false`); identify the parts one by one for their diagnosis and corrected
/// errors.
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the measured part (any CMM export); several: a pool of parts of one machine
    #[arg(value_name = "FILE")]
    files: Vec<String>,
    #[command(flatten)]
    model: ModeBranch,
    /// also fit the tool-radius error dR (mm, + = a larger tool)
    #[arg(long)]
    tool_radius: bool,
    /// auto (default): what the diagnosis names; none: the baseline alone (the answer before
    /// the diagnosis); ID[,ID]: fit these effects of effects.md whatever the diagnosis says (e.g.
    /// --effects backlash_c,setup_error)
    #[arg(long, value_name = "auto|none|ID[,ID]", value_parser = effects, verbatim_doc_comment)]
    effects: Option<EffectsChoice>,
    /// {parameters (the final answer), baseline_parameters, effects_included, shift, verdict,
    /// correction, groups, rank, condition, residual, points_used, points_excluded, ...}
    #[arg(long, verbatim_doc_comment)]
    json: bool,
    /// the correction in the controller's terms
    ///
    /// Only separable location errors with |value| >= 2 std are entered (the others listed with
    /// why, and kept on the part). Each axis's line (rotary: point and direction; linear:
    /// direction), the tool tip at the reference pose and the offset vectors machine zero ->
    /// rotation centres -> tool tip, in the machine frame, before (nominal) and after entering
    /// them, each number with its std propagated from the entered errors; the same as a
    /// SINUMERIK orientable toolholder ($TC_CARR1..20, type M/T/P), tool length, CEC squareness
    /// slopes and work offset, with std, and where each entered error goes (a kinematic
    /// parameter, the squareness table, the work offset, or nowhere); the predicted part after
    /// compensation on the measured points (measured minus the entered errors' part: a named
    /// effect or dR is not a location error and stays, said in the notes) and on withheld curves
    /// (each curve predicted by the fit of the others); with --json the field `compensation`
    #[arg(long, verbatim_doc_comment)]
    compensation: bool,
    /// the compensation table of the final answer: name, iso_230_1, value, unit, std, status,
    /// fitted_with (effect ids joined by +, structure, or none)
    #[arg(long, value_name = "csv|json", value_parser = export_format, verbatim_doc_comment)]
    export: Option<Export>,
    /// the same part measured again (same point ids; once per repeat)
    ///
    /// The mean of the measurements is identified; the pure error of their differences / √k is
    /// the CMM's share of its σ, a floor to which the part's own scatter is added from the data,
    /// and the JSON's `repeat` gives the pure error and the lack of fit of the location errors
    /// against it. Not with --sigma, --mpe or a pool.
    #[arg(long, value_name = "FILE2", verbatim_doc_comment)]
    repeat: Vec<String>,
    /// the CMM's σ of the deviations (mm): a floor; the part's own scatter is added when the
    /// data show it significantly
    #[arg(long, value_name = "MM", value_parser = mm, allow_negative_numbers = true)]
    sigma: Option<f64>,
    /// the CMM's MPE_E = A + L/K µm and optionally its repeatability range R0 (µm)
    ///
    /// L = the point's distance from the part origin (mm); σ_i = max(MPE_E/√3, R0/1.693) per
    /// point (the Monte Carlo's rule), the median used as the σ of every point; not with --sigma.
    /// The report says which σ and where from.
    #[arg(long, value_name = "A,K[,R0]", value_parser = mpe, verbatim_doc_comment)]
    mpe: Option<Mpe>,
    /// keep the single-point outliers in the fit
    ///
    /// By default a point whose deviation from the fit of the baseline plus a smooth basis per
    /// curve is beyond the Bonferroni bound (externally studentised residual against a robust σ,
    /// α = 0.05 over the points), isolated along its curve and explained by no candidate effect
    /// (a chip, dirt, a probing error) is left out of the identification and the diagnosis and
    /// listed under points_excluded with its size and statistic; the JSON's `outliers` gives the
    /// test (points, rule, threshold, sigma) and verdict_all_points, the verdict with every point
    #[arg(long, verbatim_doc_comment)]
    keep_outliers: bool,
    /// leave out the rows the reader rejects (listed under points_excluded)
    #[arg(long)]
    exclude_bad_rows: bool,
    /// skips the exact-model check
    ///
    /// By default the exact eq. 12 is evaluated at the linear solution and Levenberg-Marquardt
    /// refines it when the linearisation error exceeds 0.1 σ (reported under "refinement")
    #[arg(long, verbatim_doc_comment)]
    no_refine: bool,
    /// threads the reading, the part model, the diagnosis and the exact-model refinement use
    /// (default: the machine's cores); the results are the same, bit for bit, on any count
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
    /// adds a Monte Carlo check of N runs
    ///
    /// With the noise of the CMM of --mpe, else of the paper's CMM: MPE_E = ±(3 + L/75) µm,
    /// R0 = 3 µm; σ = max(MPE/√3, R0/1.693) per point
    #[arg(long, value_name = "N", value_parser = whole, verbatim_doc_comment)]
    monte_carlo: Option<usize>,
    /// the seed of the Monte Carlo
    #[arg(long, value_name = "S", default_value_t = 7, value_parser = seed)]
    seed: u64,
    /// the chain: paper000 (B head / C table), paper001 (A-B head), paper002 (B-C tilting table)
    #[arg(long, value_name = "paper000|paper001|paper002", default_value = "paper000", value_parser = machine)]
    machine: MachineChoice,
    /// the pivot-to-tip length (mm)
    #[arg(long, value_name = "MM", default_value_t = PAPER000_L0, value_parser = mm, allow_negative_numbers = true)]
    l0: f64,
    /// the feed the part was cut with (mm/min): a servo lag the diagnosis names is stated as the
    /// position loop's time constant (1/Kv, ms) at it
    #[arg(long, value_name = "MM_PER_MIN", default_value_t = testpiece::settings::feed::PROGRAMME_FEED, value_parser = mm, allow_negative_numbers = true)]
    feed: f64,
    /// with several files: each part's CMM datum alignment Rz[k] (rad), Tx[k], Ty[k] (mm)
    #[arg(long)]
    setup_per_part: bool,
}

/// `--export csv|json`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Export {
    Csv,
    Json,
}

fn export_format(s: &str) -> Result<Export, String> {
    match s {
        "csv" => Ok(Export::Csv),
        "json" => Ok(Export::Json),
        _ => Err("expected csv or json".into()),
    }
}

/// `--effects auto|none|ID[,ID]`.
fn effects(s: &str) -> Result<EffectsChoice, String> {
    s.parse()
        .map_err(|e: testpiece::effects::GapError| e.to_string())
}

pub fn run(a: Args) -> Result<(), String> {
    let settings = a.settings()?;
    if a.files.len() >= 2 {
        a.check_pool()?;
        return pool::run(&a.files, settings, a.setup_per_part, a.json);
    }
    if a.setup_per_part {
        return Err("--setup-per-part needs several files to pool".to_string());
    }
    let [file] = a.files.as_slice() else {
        return Err("`testpiece identify` needs a FILE (see --help)".to_string());
    };
    let (analysis, fitted) = analyse_files(file, &a.repeat, &settings)?;
    let id = with_bad_rows(&analysis);
    if let Some(f) = a.export {
        print_export(f, &id, &analysis);
        return Ok(());
    }
    let mc = match a.monte_carlo {
        Some(runs) => Some(monte_carlo_check(
            runs,
            a.seed,
            settings.noise_mpe,
            &analysis,
            &fitted,
            &id,
        )?),
        None => None,
    };
    let compensation = a
        .compensation
        .then(|| testpiece::compensation::compensation(&analysis));
    if a.json {
        let mut v = report_json(&a, &analysis, &id)?;
        if let Some(mc) = mc {
            v["monte_carlo"] = to_json(&mc)?;
        }
        if let Some(c) = compensation {
            v["compensation"] = to_json(&c)?;
        }
        return print_json(&v);
    }
    let (mode, branch) = (a.model.mode.name(), branch_name(a.model.branch));
    text::print(
        mode,
        branch,
        &id,
        &analysis,
        compensation.as_ref(),
        mc.as_ref(),
    );
    Ok(())
}

impl Args {
    /// The analysis settings of the options.
    fn settings(&self) -> Result<AnalysisOptions, String> {
        Ok(AnalysisOptions {
            machine: self.machine,
            l0: self.l0,
            mode: self.model.mode,
            branch: self.model.branch,
            tool_radius: self.tool_radius,
            exclude_bad_rows: self.exclude_bad_rows,
            noise_sigma: self.sigma,
            noise_mpe: cmm_noise(self.sigma, self.mpe.as_ref())?,
            keep_outliers: self.keep_outliers,
            refine: !self.no_refine,
            known: None,
            effects: self.effects.clone().unwrap_or_default(),
            feed: self.feed,
            threads: threads(self.threads),
        })
    }

    /// The options a pool refuses: it is not diagnosed and takes one σ.
    fn check_pool(&self) -> Result<(), String> {
        if !self.repeat.is_empty() {
            return Err(
                "--repeat takes one FILE (the part measured again), not a pool".to_string(),
            );
        }
        if self.export.is_some() || self.monte_carlo.is_some() {
            return Err("--export and --monte-carlo take one FILE, not a pool".to_string());
        }
        if self.compensation {
            return Err(
                "--compensation takes one FILE: a pool is not diagnosed, so what the correction \
                 leaves on a part is not known (identify the parts one by one)"
                    .to_string(),
            );
        }
        if self.mpe.is_some() || self.keep_outliers {
            return Err(
                "--mpe and --keep-outliers take one FILE: a pool is not tested for outliers \
                 (identify the parts one by one) and takes --sigma for the CMM noise"
                    .to_string(),
            );
        }
        if self
            .effects
            .as_ref()
            .is_some_and(|e| *e != EffectsChoice::None)
        {
            return Err(
                "--effects: a pool is not diagnosed, so it cannot be corrected for an effect; \
                 identify the parts one by one"
                    .to_string(),
            );
        }
        Ok(())
    }
}

/// The final identification, with the rows the reader left out (--exclude-bad-rows) among the
/// excluded points.
fn with_bad_rows(analysis: &Analysis) -> Identification {
    let mut id = analysis.identification.clone();
    for r in &analysis.file.excluded {
        id.points_excluded.push(ExcludedPoint {
            id: format!("line {}", r.line),
            reason: r.to_string(),
        });
    }
    id
}

/// `--export`: the compensation table of the final answer.
fn print_export(format: Export, id: &Identification, analysis: &Analysis) {
    let fitted_with = &analysis.correction.fitted_with;
    match format {
        Export::Csv => print!("{}", export::compensation_csv(id, fitted_with)),
        Export::Json => println!("{}", export::compensation_json(id, fitted_with)),
    }
}

/// `--monte-carlo N`: N identifications of the fitted design with the CMM's noise (of --mpe, else
/// paper 000's CMM).
fn monte_carlo_check(
    runs: usize,
    seed: u64,
    mpe: Option<CmmMpe>,
    analysis: &Analysis,
    fitted: &Fitted,
    id: &Identification,
) -> Result<MonteCarloReport, String> {
    let mut opts = IdentifyOptions::default();
    if let Some(s) = analysis.noise.sigma {
        opts = opts.with_sigma(s);
    }
    let cmm = mpe.unwrap_or_else(CmmMpe::paper000);
    let noise = Noise::from_mpe(&cmm, &analysis.lengths());
    let o = MonteCarloOptions::default().with_runs(runs).with_seed(seed);
    monte_carlo(
        &fitted.design,
        &fitted.observations,
        &id.values(),
        &noise,
        &o,
        &opts,
    )
    .map_err(|e| e.to_string())
}

/// `--json`: the identification with the settings, the baseline, the correction, the outliers,
/// the noise and the repeat.
fn report_json(
    a: &Args,
    analysis: &Analysis,
    id: &Identification,
) -> Result<serde_json::Value, String> {
    let mut v = to_json(id)?;
    v["mode"] = serde_json::json!(a.model.mode.name());
    v["branch"] = serde_json::json!(branch_name(a.model.branch));
    if let Some(r) = &analysis.refinement {
        v["refinement"] = to_json(r)?;
    }
    let c = &analysis.correction;
    v["baseline_parameters"] = to_json(&analysis.baseline.identification.parameters)?;
    v["effects_included"] = to_json(&c.effects_included)?;
    v["shift"] = to_json(&c.shift)?;
    v["verdict"] = to_json(&c.verdict)?;
    v["correction"] = to_json(c)?;
    v["outliers"] = to_json(&analysis.outliers)?;
    v["noise"] = to_json(&analysis.noise)?;
    if let Some(r) = &analysis.repeat {
        v["repeat"] = to_json(r)?;
    }
    Ok(v)
}
