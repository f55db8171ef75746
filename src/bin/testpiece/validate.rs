//! `testpiece validate [--machine M] [--cases N] [--seed S] [--known-sigma] [--exact] [--pairs]
//! [--json]`: the withheld-effect benchmark of the gap diagnosis.

use testpiece::machine::chain::PAPER000_L0;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::SensitivityOptions;
use testpiece::settings::MachineChoice;
use testpiece::validate::shapes::Shape;
use testpiece::validate::{
    conditions_table, exact_machine_part, exact_machine_part_on, pairs_table, run_conditions,
    table, validate, validate_pairs, validate_with, ValidateOptions, ValidationModel, CONDITIONS,
};

use crate::args::Args;

const HELP: &str = "\
testpiece validate [--machine paper000|paper001|paper002] [--cases N] [--seed S] [--known-sigma]
                   [--exact] [--pairs] [--spikes] [--json]

Simulates N parts (default 200) of the built-in S-shape with random machine errors (angles
±3e-4 rad, EX0B ±0.03 mm), each with one effect of effects.md at a random magnitude around its
detection limit, or none, or an effect outside the list (waviness, local bump), plus noise
σ = 1.5 µm; diagnoses each with the effect withheld from the baseline; prints per-effect accuracy,
the confusion matrix, detection limits and the shrink achieved versus achievable.

--machine M    the machine the parts are made and diagnosed on (default paper000, the B head /
               C table): paper001 (A-B head, X table) or paper002 (B-C tilting table), with
               L0 = 499.889 mm where the machine has a pivot, signed B: its own location errors
               as the baseline and its own candidates (those whose physics it has: no C-axis
               effects on paper001, which has backlash_a and a_index; no pivot_length on
               paper002). The standard table, --exact and --pairs work on every machine;
               --conditions only on paper000.
--shapes standard|extended  the out-of-list shapes: waviness 150-600 mm and bump (standard), or
               short waves 80-150 mm, a gouge, a quadratic straightness of one linear axis, a
               cyclic C error of 2 periods a turn (extended).
--known-sigma  give σ to the diagnosis as the CMM repeatability (default: estimated).
--spikes       add a single-point spike of 25-40 µm (random sign) at a random point of every
               case; prints how often the spike is named as an outlier. Every case goes
               through the outlier test as `testpiece diagnose` does (named points left out).
--exact        simulate the machine part with the exact eq. 12 defect (the diagnosis still fits
               the linear baseline); default: the linear twin.
--pairs        instead: N parts with TWO effects each (every pair of candidates the part can tell
               apart, in turn, each at 1.5..6 x its detection limit); prints how often both are
               named (the verdict's effect, its `with` and their equivalents), and how often
               among the parts where each effect is visible beyond the baseline and the other
               (joint ratio > 1: only there can any rule name both).
--json         the report as JSON.

Each part is also identified as `identify` would answer, on the linear design (no exact-model
refinement): the baseline (the machine's location errors alone) and the final answer (fitted
with the effect the verdict names; by generalised least squares with the structure's covariance
when `unexplained`; the baseline when `none`). Both are compared with the simulated location
errors, baseline / final side by side, per group of expected verdict (detectable effects,
unexplained, none) and per effect (its detectable parts):
  largest error  median over the parts of max |value - true| over the machine's location
                 errors (paper000's 8; `testpiece machine --machine M`), in typical units
                 (1e-4 rad for angles, 0.01 mm for lengths);
  coverage       share of the location errors with |value - true| <= 2 std (%; a parameter
                 without std is not covered). An honest std covers about 95 %.
In --json: per part `basis`, `baseline_error` and `final_error` (with `per_parameter`: signed
error in typical units, std in typical units, z = error / std), per group `parameter_error`, per
effect `per_effect[].parameter_error`.
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["cases", "seed", "conditions", "shapes", "machine"])?;
    let (machine, _) = crate::identify::machine_and_l0(&args)?;
    let json = args.flag("json");
    let known = args.flag("known-sigma");
    let exact = args.flag("exact");
    let pairs = args.flag("pairs");
    let spikes = args.flag("spikes");
    let parse = |name: &str, default: u64| -> Result<u64, String> {
        args.value(name).map_or(Ok(default), |s| {
            s.parse()
                .map_err(|_| format!("--{name}: `{s}` is not a whole number"))
        })
    };
    let cases = parse("cases", 200)? as usize;
    let seed = parse("seed", 1)?;
    let conditions = args.value("conditions").map(str::to_string);
    let shapes: &'static [Shape] = match args.value("shapes").unwrap_or("standard") {
        "standard" => &Shape::STANDARD,
        "extended" => &Shape::EXTENDED,
        other => {
            return Err(format!(
                "--shapes `{other}`: expected standard (waviness, bump) or extended (short wave, \
                 gouge, straightness, cyclic C)"
            ))
        }
    };
    args.reject_unknown("validate")?;
    let part = SShape::iso();
    let sens = SensitivityOptions::default().with_chain(machine.chain(PAPER000_L0));
    let model = if machine == MachineChoice::Paper000 {
        ValidationModel::at(&part, &builtin_points(&part))
    } else {
        ValidationModel::on(
            &part,
            &builtin_points(&part),
            &testpiece::analysis::AnalysisOptions {
                machine,
                ..Default::default()
            },
        )
    }
    .map_err(|e| e.to_string())?;
    if conditions.is_some() && machine != MachineChoice::Paper000 {
        return Err(format!(
            "--conditions: only on paper000 (--machine {}: use the standard table, --exact or \
             --pairs)",
            machine_id(machine)
        ));
    }
    if let Some(which) = conditions {
        let which: Vec<&str> = if which == "all" {
            Vec::new()
        } else {
            which.split(',').map(str::trim).collect()
        };
        if let Some(bad) = which.iter().find(|w| !CONDITIONS.contains(w)) {
            return Err(format!(
                "--conditions: unknown condition `{bad}` (known: all, {})",
                CONDITIONS.join(", ")
            ));
        }
        let exact = exact_machine_part(&model.baseline.names).map_err(|e| e.to_string())?;
        let r = run_conditions(&part, &model, exact.as_ref(), &which, cases, seed)
            .map_err(|e| e.to_string())?;
        show(json, &r, conditions_table)?;
        return Ok(());
    }
    let opts = ValidateOptions::default()
        .with_cases(cases)
        .with_seed(seed)
        .with_known_sigma(known)
        .with_spikes(spikes)
        .with_shapes(shapes);
    if pairs {
        let r = validate_pairs(&model, &opts).map_err(|e| e.to_string())?;
        show(json, &r, pairs_table)?;
        return Ok(());
    }
    let r = if exact {
        let exact_part = if machine == MachineChoice::Paper000 {
            exact_machine_part(&model.baseline.names)
        } else {
            exact_machine_part_on(&model, builtin_points(&part), &sens)
        }
        .map_err(|e| e.to_string())?;
        validate_with(&model, &opts, exact_part.as_ref())
    } else {
        validate(&model, &opts)
    }
    .map_err(|e| e.to_string())?;
    if machine != MachineChoice::Paper000 && !json {
        println!("machine: {}", machine.describe());
    }
    show(json, &r, table)?;
    Ok(())
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
        println!(
            "{}",
            serde_json::to_string_pretty(r).map_err(|e| e.to_string())?
        );
    } else {
        print!("{}", table(r));
    }
    Ok(())
}
