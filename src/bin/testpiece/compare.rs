//! `testpiece compare A B`: the differences of two parts' identified parameters.

use crate::args::Args;
use testpiece::analysis::{analyse, AnalysisOptions};
use testpiece::compare::{compare, parameters_of, Flag};
use testpiece::machine::Branch;
use testpiece::sensitivity::Mode;

const HELP: &str = "\
testpiece compare A B [--mode physical|paper] [--branch signed|positive] [--tool-radius]
                      [--sigma MM] [--json]

Identifies the machine from each of two measured parts (before / after compensation, two
machines, two dates) and prints, per parameter, d = B - A with σ_d = √(σ_A² + σ_B²) (independent
parts) and z = d/σ_d. Flags: different (|z| >= 3), suspect (2 <= |z| < 3), consistent, and
undetermined when a side has no std (not separable). CSV: name,unit,a,a_std,b,b_std,diff,std,z,flag
--json {a, b, differences: [...], different, suspect, summary}
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["mode", "branch", "sigma"])?;
    let (mode, branch) = crate::simulate::mode_and_branch(&args)?;
    let json = args.flag("json");
    let sigma = match args.value("sigma") {
        Some(t) => Some(
            t.parse::<f64>()
                .map_err(|_| format!("--sigma `{t}`: expected a number of mm"))?,
        ),
        None => None,
    };
    let settings = AnalysisOptions {
        mode: Mode::parse(&mode).map_err(|e| e.to_string())?,
        branch: Branch::parse(&branch).unwrap_or_default(),
        tool_radius: args.flag("tool-radius"),
        noise_sigma: sigma,
        ..AnalysisOptions::default()
    };
    args.reject_unknown("compare")?;
    let [fa, fb] = args.positional.as_slice() else {
        return Err("`testpiece compare` needs two files A B (see --help)".to_string());
    };
    let run_one = |f: &String| -> Result<_, String> {
        let bytes = std::fs::read(f).map_err(|e| format!("{f}: {e}"))?;
        let name = crate::identify::file_name(f);
        let a = analyse(&bytes, &name, &settings).map_err(|e| format!("{f}: {e}"))?;
        Ok((name, parameters_of(&a.identification)))
    };
    let (na, pa) = run_one(fa)?;
    let (nb, pb) = run_one(fb)?;
    let c = compare(&na, &pa, &nb, &pb).map_err(|e| e.to_string())?;
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&c).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    let o = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:e}"));
    println!("name,unit,a,a_std,b,b_std,diff,std,z,flag");
    for d in &c.differences {
        let flag = match d.flag {
            Flag::Consistent => "consistent",
            Flag::Suspect => "suspect",
            Flag::Different => "different",
            Flag::Undetermined => "undetermined",
        };
        println!(
            "{},{},{},{},{},{},{},{},{},{flag}",
            d.name,
            d.unit,
            o(d.a),
            o(d.a_std),
            o(d.b),
            o(d.b_std),
            o(d.diff),
            o(d.std),
            d.z.map_or(String::new(), |z| format!("{z:.3}"))
        );
    }
    eprintln!("{}", c.summary);
    Ok(())
}
