//! `testpiece validate [--cases N] [--seed S] [--known-sigma] [--json]`: the withheld-effect
//! benchmark of the gap diagnosis.

use testpiece::gap::effects::builtin::builtin_model;
use testpiece::gap::validate::{table, validate, ValidateOptions, ValidationModel};
use testpiece::part::SShape;

use crate::args::Args;

const HELP: &str = "\
testpiece validate [--cases N] [--seed S] [--known-sigma] [--json]

Simulates N parts (default 200) of the built-in S-shape with random machine errors (angles
±3e-4 rad, EX0B ±0.03 mm), each with one effect of effects.md at a random magnitude around its
detection limit, or none, or an effect outside the list (waviness, local bump), plus noise
σ = 1.5 µm; diagnoses each with the effect withheld from the baseline; prints per-effect accuracy,
the confusion matrix, detection limits and the shrink achieved versus achievable.
--known-sigma  give σ to the diagnosis as the CMM repeatability (default: estimated).
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["cases", "seed"])?;
    let json = args.flag("json");
    let known = args.flag("known-sigma");
    let parse = |name: &str, default: u64| -> Result<u64, String> {
        args.value(name).map_or(Ok(default), |s| {
            s.parse()
                .map_err(|_| format!("--{name}: `{s}` is not a whole number"))
        })
    };
    let cases = parse("cases", 200)? as usize;
    let seed = parse("seed", 1)?;
    args.reject_unknown("validate")?;
    let m = builtin_model(&SShape::iso()).map_err(|e| e.to_string())?;
    let model = ValidationModel {
        points: m.points,
        baseline: m.baseline,
        candidates: m.candidates,
    };
    let opts = ValidateOptions::default()
        .with_cases(cases)
        .with_seed(seed)
        .with_known_sigma(known);
    let r = validate(&model, &opts).map_err(|e| e.to_string())?;
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&r).map_err(|e| e.to_string())?
        );
    } else {
        print!("{}", table(&r));
    }
    Ok(())
}
