//! `testpiece simulate`: a synthetic measured part in the canonical CSV format.

use crate::args::Args;
use testpiece::cmm::write::{canonical_csv, Precision};
use testpiece::effects::builtin::part_model_on;
use testpiece::effects::Effect;
use testpiece::identify::{Design, ISO_LOCATION_ERRORS};
use testpiece::machine::Branch;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::SensitivityOptions;
use testpiece::simulate::{parse_errors, simulate_deviation, simulate_exact};

const HELP: &str = "\
testpiece simulate --errors EX0B=0.03,EA0B=3e-4 [--effect backlash_c=1e-4,tool_taper.g=2e-4]
                   [--noise 0.0015] [--seed 7] [--mode physical|paper]
                   [--branch signed|positive] [--linear] [--machine M] [--l0 MM]

Prints a synthetic measured part at the 100 built-in points in the canonical format
`id,curve,x,y,z,nx,ny,nz,deviation` (mm; deviation = (machined - nominal)·N, + = material left).
The deviation is the exact machined defect of paper 000 eq. 12 (--linear: its linearisation,
eq. 14; they differ by < 0.3 µm at 3e-4 rad) for the given errors
(EC0Y EA0Z EB0Z EA0C EB0C EA0B EC0B in rad, EX0B in mm; others 0), plus dR (mm, a tool larger by
dR overcuts by dR) if given in --errors, plus Gaussian noise of σ = --noise mm (default 0) drawn
from a ChaCha8 stream seeded by --seed (default 7): the same seed gives the same part.

--machine paper000|paper001|paper002 (default paper000) and --l0: the chain. With another
machine than paper000, or an error outside the eight above, the part is the exact eq. 12 defect
on that chain for any of its ISO 230-1 location errors (`testpiece machine --machine M` lists
them: e.g. EY0C=0.02,EX0C=-0.015 for a C axis off the part origin on the tilting table), and
--effect uses that machine's signatures.

--effect adds unmodelled effects of shared/spec/effects.md, each as ID=VALUE for a one-parameter
effect (backlash_c=1e-4: rad for B and C, mm for X, Y, Z) or ID.PARAMETER=VALUE (tool_taper.g=2e-4,
setup_error.thetaz=1e-4), in the parameter's unit: the deviation gains VALUE times the effect's
signature at the points (paper 000's machine, physical mode, the --branch given), the signature
`testpiece diagnose` fits. Ids: tool_radius, tool_taper, overcut, backlash_x|y|z|b|c,
thermal_drift, setup_error, scale_x|y|z, c_index, pivot_length.
";

/// The design of the 100 built-in points for a mode and branch, with the dR column if asked.
pub fn design_for(mode: &str, branch: &str, tool_radius: bool) -> Result<Design, String> {
    testpiece::simulate::builtin_design(mode, branch, tool_radius).map_err(|e| e.to_string())
}

/// `--effect ID=VALUE,ID.PARAMETER=VALUE`: each effect parameter and its value.
fn parse_effects(text: &str) -> Result<Vec<(Effect, usize, f64)>, String> {
    parse_errors(text)
        .map_err(|e| format!("--effect: {e}"))?
        .into_iter()
        .map(|(key, value)| {
            let (effect, j) =
                Effect::parse_parameter(&key).map_err(|e| format!("--effect: {e}"))?;
            Ok((effect, j, value))
        })
        .collect()
}

/// `--mode` and `--branch` values, checked.
pub fn mode_and_branch(args: &Args) -> Result<(String, String), String> {
    let mode = args.value("mode").unwrap_or("physical").to_string();
    if mode != "physical" && mode != "paper" {
        return Err(format!("--mode `{mode}`: expected physical or paper"));
    }
    let branch = args.value("branch").unwrap_or("signed").to_string();
    if branch != "signed" && branch != "positive" {
        return Err(format!("--branch `{branch}`: expected signed or positive"));
    }
    Ok((mode, branch))
}

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(
        rest,
        &[
            "errors", "noise", "seed", "mode", "branch", "effect", "machine", "l0",
        ],
    )?;
    let errors = args
        .value("errors")
        .ok_or("--errors is required, e.g. --errors EX0B=0.03,EA0B=3e-4")?;
    let noise: f64 = match args.value("noise") {
        Some(t) => t
            .parse()
            .map_err(|_| format!("--noise `{t}`: expected a number of mm, e.g. 0.0015"))?,
        None => 0.0,
    };
    let seed: u64 = match args.value("seed") {
        Some(t) => t
            .parse()
            .map_err(|_| format!("--seed `{t}`: expected a non-negative integer"))?,
        None => 7,
    };
    let (mode, branch) = mode_and_branch(&args)?;
    let linear = args.flag("linear");
    let effects = args.value("effect").map(parse_effects).transpose()?;
    let (machine, l0) = crate::identify::machine_and_l0(&args)?;
    args.reject_unknown("simulate")?;
    if !args.positional.is_empty() {
        return Err(format!(
            "`testpiece simulate` takes no file, found `{}`",
            args.positional.join(" ")
        ));
    }
    let errs = parse_errors(errors).map_err(|e| e.to_string())?;
    if !(l0.is_finite() && l0 > 0.0) {
        return Err(format!("--l0 {l0}: expected a positive length in mm"));
    }
    let full: Vec<String> = testpiece::sensitivity::error_set::full_list(&machine.chain(l0))
        .iter()
        .map(|(e, _)| e.name())
        .collect();
    for (name, _) in &errs {
        if name != "dR" && !full.contains(name) {
            return Err(format!(
                "--errors: unknown error `{name}` on {}; known: {}, dR",
                machine.describe(),
                full.join(", ")
            ));
        }
    }
    // Paper 000 with its eight errors keeps the design-based path (its parts bit for bit).
    let on_chain = machine != testpiece::settings::MachineChoice::Paper000
        || errs
            .iter()
            .any(|(n, _)| n != "dR" && !ISO_LOCATION_ERRORS.contains(&n.as_str()));
    let chain_opts = || -> Result<SensitivityOptions, String> {
        let b = Branch::parse(&branch).ok_or("--branch: expected signed or positive")?;
        let m = testpiece::sensitivity::Mode::parse(&mode).map_err(|e| e.to_string())?;
        Ok(SensitivityOptions::default()
            .with_chain(machine.chain(l0))
            .with_branch(b)
            .with_mode(m))
    };
    let tool_radius = errs.iter().any(|(n, _)| n == "dR");
    let dev = if on_chain {
        if linear {
            return Err("--linear: only on paper000 with its eight errors".to_string());
        }
        testpiece::simulate::simulate_on(&chain_opts()?, &errs, noise, seed)
    } else if linear {
        let design = design_for(&mode, &branch, tool_radius)?;
        simulate_deviation(&design, &errs, noise, seed)
    } else {
        simulate_exact(&mode, &branch, &errs, noise, seed)
    }
    .map_err(|e| e.to_string())?;
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let dev: Vec<f64> = match effects {
        Some(values) => {
            let opts = chain_opts()?;
            let model = part_model_on(&part, &pts, &opts).map_err(|e| e.to_string())?;
            let e = model
                .effect_deviation(&values)
                .map_err(|e| format!("--effect: {e}"))?;
            dev.iter().zip(e).map(|(d, e)| d + e).collect()
        }
        None => dev.to_vec(),
    };
    if pts.len() != dev.len() {
        return Err(format!(
            "internal: {} built-in points but {} design rows",
            pts.len(),
            dev.len()
        ));
    }
    let out = canonical_csv(
        pts.iter().zip(dev.iter().copied()),
        Precision::Shortest,
        None,
    );
    print!("{out}");
    Ok(())
}
