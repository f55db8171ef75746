//! `testpiece validate [--machine M] [--cases N] [--seed S] [--known-sigma] [--exact] [--pairs]
//! [--generator signatures|physics] [--json]`: the withheld-effect benchmark of the gap diagnosis.

use testpiece::machine::chain::PAPER000_L0;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::SensitivityOptions;
use testpiece::settings::MachineChoice;
use testpiece::validate::physics_bench::{
    default_threads, physics_table, PhysicsBench, PhysicsOptions,
};
use testpiece::validate::shapes::Shape;
use testpiece::validate::{
    conditions_table, exact_machine_part, exact_machine_part_on, pairs_table, run_conditions,
    table, validate, validate_pairs, validate_with, ValidateOptions, ValidationModel, CONDITIONS,
};

use crate::common::{machine, seed, whole};

/// the withheld-effect benchmark of the gap diagnosis [--cases N] [--seed S] [--json]
///
/// Simulates N parts (default 200) of the built-in S-shape with random machine errors (angles
/// ±3e-4 rad, EX0B ±0.03 mm), each with one effect of effects.md at a random magnitude around its
/// detection limit, or none, or an effect outside the list (waviness, local bump), plus noise
/// σ = 1.5 µm; diagnoses each with the effect withheld from the baseline; prints per-effect accuracy,
/// the confusion matrix, detection limits and the shrink achieved versus achievable.
///
/// Each part goes through the analysis `identify` and `diagnose` run on a file (outlier test,
/// diagnosis, fits refined on the exact model where the linearisation matters), which gives the
/// baseline (the machine's location errors alone) and the final answer (fitted with the effect
/// the verdict names; by generalised least squares with the structure's covariance when
/// `unexplained`; the baseline when `none`). Both are compared with the simulated location
/// errors, baseline / final side by side, per group of expected verdict (detectable effects,
/// unexplained, none) and per effect (its detectable parts):
///   largest error  median over the parts of max |value - true| over the machine's location
///                  errors (paper000's 8; `testpiece machine --machine M`), in typical units
///                  (1e-4 rad for angles, 0.01 mm for lengths);
///   coverage       share of the location errors with |value - true| <= 2 std (%; a parameter
///                  without std is not covered). An honest std covers about 95 %.
/// In --json: per part `basis`, `baseline_error` and `final_error` (with `per_parameter`: signed
/// error in typical units, std in typical units, z = error / std), per group `parameter_error`, per
/// effect `per_effect[].parameter_error`.
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the machine the parts are made and diagnosed on
    ///
    /// paper000 (the B head / C table), paper001 (A-B head, X table) or paper002 (B-C tilting
    /// table), with L0 = 499.889 mm where the machine has a pivot, signed B: its own location
    /// errors as the baseline and its own candidates (those whose physics it has: no C-axis
    /// effects on paper001, which has backlash_a and a_index; no pivot_length on paper002). The
    /// standard table, --exact and --pairs work on every machine; --conditions only on paper000.
    #[arg(long, value_name = "paper000|paper001|paper002", default_value = "paper000", value_parser = machine, verbatim_doc_comment)]
    machine: MachineChoice,
    /// the number of parts [default: 200; 300 with --generator physics]
    #[arg(long, value_name = "N", value_parser = whole)]
    cases: Option<usize>,
    /// the seed of the parts' random stream
    #[arg(long, value_name = "S", default_value_t = 1, value_parser = seed)]
    seed: u64,
    /// the out-of-list shapes
    ///
    /// standard: waviness 150-600 mm and bump; extended: short waves 80-150 mm, a gouge, a
    /// quadratic straightness of one linear axis, a cyclic C error of 2 periods a turn.
    #[arg(long, value_name = "standard|extended", default_value = "standard", value_parser = shapes, verbatim_doc_comment)]
    shapes: &'static [Shape],
    /// give σ to the diagnosis as the CMM repeatability (default: estimated)
    #[arg(long)]
    known_sigma: bool,
    /// add a single-point spike of 25-40 µm at a random point of every case
    ///
    /// Random sign; prints how often the spike is named as an outlier. Every case goes through
    /// the outlier test as `testpiece diagnose` does (named points left out).
    #[arg(long, verbatim_doc_comment)]
    spikes: bool,
    /// simulate the machine part with the exact eq. 12 defect (the diagnosis still fits the
    /// linear baseline); default: the linear twin
    #[arg(long, verbatim_doc_comment)]
    exact: bool,
    /// instead: N parts with TWO effects each
    ///
    /// Every pair of candidates the part can tell apart, in turn, each at 1.5..6 x its detection
    /// limit; prints how often both are named (the verdict's effect, its `with` and their
    /// equivalents), and how often among the parts where each effect is visible beyond the
    /// baseline and the other (joint ratio > 1: only there can any rule name both).
    #[arg(long, verbatim_doc_comment)]
    pairs: bool,
    /// instead: one table of the lab's conditions (paper000 only; σ never told to the diagnosis)
    ///
    /// all, or names separated by commas: standard, noise (0.5-3 µm), spikes, layout (30-200
    /// points, a missing curve), shapes (the extended out-of-list shapes), near_limit, large
    /// (large errors on the exact model), pairs.
    #[arg(long, value_name = "all|NAME,...", value_parser = conditions, verbatim_doc_comment)]
    conditions: Option<Conditions>,
    /// who makes the parts: the product's signatures (default) or the physics
    ///
    /// physics (paper000 only): parts machined and measured by models that are not the fitter
    /// (issue 29 item 4): location errors through the exact chain; one effect made by its physics
    /// (backlash with a random lag and a servo settling, position loops integrated in time with
    /// unequal gains, warm-up, wear, tool radius and taper, scale, C index, pivot length, setup,
    /// the flank overcut, straightness, cyclic and long-wave pitch errors of linear axes measured
    /// from their ISO 230-1 reference, a three-lobed probe, a part moving while measured) or
    /// none; Gaussian or heavy-tailed CMM
    /// noise, surface scatter, repeats. Prints the groups (clean, clean + scatter, repeats,
    /// below the limit, in and out of the catalogue above 2x the limit, wrong verdict), per kind,
    /// and the done-when figures; the limit is k σ with the true σ. --known-sigma gives the
    /// CMM's σ (never the part's scatter). Seeds 1-6 develop; any other seed is held out until
    /// it is scored (the ones scored so far: BENCHMARKS.md).
    #[arg(long, value_name = "signatures|physics", default_value = "signatures", value_parser = generator, verbatim_doc_comment)]
    generator: GeneratorChoice,
    /// threads the parts of --generator physics are shared between [default: the machine's cores]
    ///
    /// Each part has its own random stream and its own analysis: the report is the same for any
    /// number of threads.
    #[arg(long, value_name = "N", value_parser = threads)]
    threads: Option<usize>,
    /// the report as JSON
    #[arg(long)]
    json: bool,
}

/// Who makes the parts (`--generator`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GeneratorChoice {
    Signatures,
    Physics,
}

fn generator(s: &str) -> Result<GeneratorChoice, String> {
    match s {
        "signatures" => Ok(GeneratorChoice::Signatures),
        "physics" => Ok(GeneratorChoice::Physics),
        _ => Err("expected signatures (the product's own) or physics".into()),
    }
}

/// `--generator physics`: the physics benchmark (paper000; not with the other modes).
fn run_physics(a: &Args) -> Result<(), String> {
    let clash = [
        (a.machine != MachineChoice::Paper000, "--machine"),
        (a.pairs, "--pairs"),
        (a.exact, "--exact"),
        (a.spikes, "--spikes"),
        (a.conditions.is_some(), "--conditions"),
        (!std::ptr::eq(a.shapes, &Shape::STANDARD), "--shapes"),
    ];
    if let Some((_, flag)) = clash.iter().find(|(on, _)| *on) {
        return Err(format!(
            "--generator physics: {flag} is a setting of the signature benchmark"
        ));
    }
    let bench = PhysicsBench::builtin().map_err(|e| e.to_string())?;
    let r = bench
        .run(&PhysicsOptions {
            cases: a.cases.unwrap_or(300),
            seed: a.seed,
            cmm_sigma: a.known_sigma,
            threads: a.threads.unwrap_or_else(default_threads),
        })
        .map_err(|e| e.to_string())?;
    show(a.json, &r, physics_table)
}

/// `--threads N`: a whole number of at least 1.
fn threads(s: &str) -> Result<usize, String> {
    match whole(s)? {
        0 => Err("expected at least 1 thread".into()),
        n => Ok(n),
    }
}

/// `--shapes standard|extended`.
fn shapes(s: &str) -> Result<&'static [Shape], String> {
    match s {
        "standard" => Ok(&Shape::STANDARD),
        "extended" => Ok(&Shape::EXTENDED),
        _ => Err(
            "expected standard (waviness, bump) or extended (short wave, gouge, \
                  straightness, cyclic C)"
                .into(),
        ),
    }
}

/// `--conditions all|NAME,...`: the conditions named (none: all of them).
#[derive(Debug, Clone)]
pub struct Conditions(Vec<String>);

fn conditions(s: &str) -> Result<Conditions, String> {
    if s == "all" {
        return Ok(Conditions(Vec::new()));
    }
    let which: Vec<String> = s.split(',').map(|w| w.trim().to_string()).collect();
    match which.iter().find(|w| !CONDITIONS.contains(&w.as_str())) {
        Some(bad) => Err(format!(
            "unknown condition `{bad}` (known: all, {})",
            CONDITIONS.join(", ")
        )),
        None => Ok(Conditions(which)),
    }
}

pub fn run(a: Args) -> Result<(), String> {
    if a.generator == GeneratorChoice::Physics {
        return run_physics(&a);
    }
    if a.threads.is_some() {
        return Err(
            "--threads is a setting of --generator physics (the signature benchmark \
                    runs on one thread)"
                .into(),
        );
    }
    let cases = a.cases.unwrap_or(200);
    if a.conditions.is_some() && a.machine != MachineChoice::Paper000 {
        return Err(format!(
            "--conditions: only on paper000 (--machine {}: use the standard table, --exact or \
             --pairs)",
            machine_id(a.machine)
        ));
    }
    let part = SShape::iso();
    let sens = SensitivityOptions::default().with_chain(a.machine.chain(PAPER000_L0));
    let settings = testpiece::analysis::AnalysisOptions {
        machine: a.machine,
        ..Default::default()
    };
    let model =
        ValidationModel::on(&part, &builtin_points(&part), &settings).map_err(|e| e.to_string())?;
    if let Some(Conditions(which)) = &a.conditions {
        let which: Vec<&str> = which.iter().map(String::as_str).collect();
        let exact = exact_machine_part(&model.baseline.params).map_err(|e| e.to_string())?;
        let r = run_conditions(&part, &model, exact.as_ref(), &which, cases, a.seed)
            .map_err(|e| e.to_string())?;
        return show(a.json, &r, conditions_table);
    }
    let opts = ValidateOptions::default()
        .with_cases(cases)
        .with_seed(a.seed)
        .with_known_sigma(a.known_sigma)
        .with_spikes(a.spikes)
        .with_shapes(a.shapes);
    if a.pairs {
        let r = validate_pairs(&model, &opts).map_err(|e| e.to_string())?;
        return show(a.json, &r, pairs_table);
    }
    let r = if a.exact {
        let exact_part = if a.machine == MachineChoice::Paper000 {
            exact_machine_part(&model.baseline.params)
        } else {
            exact_machine_part_on(&model, builtin_points(&part), &sens)
        }
        .map_err(|e| e.to_string())?;
        validate_with(&model, &opts, exact_part.as_ref())
    } else {
        validate(&model, &opts)
    }
    .map_err(|e| e.to_string())?;
    if a.machine != MachineChoice::Paper000 && !a.json {
        println!("machine: {}", a.machine.describe());
    }
    show(a.json, &r, table)
}

/// The `--machine` value of a machine.
fn machine_id(m: MachineChoice) -> &'static str {
    match m {
        MachineChoice::Paper000 => "paper000",
        MachineChoice::Paper001 => "paper001",
        MachineChoice::Paper002 => "paper002",
    }
}

/// The report as JSON, or as the plain-text table `table` makes of it.
fn show<T: serde::Serialize>(json: bool, r: &T, table: fn(&T) -> String) -> Result<(), String> {
    if json {
        crate::common::print_json(r)
    } else {
        print!("{}", table(r));
        Ok(())
    }
}
