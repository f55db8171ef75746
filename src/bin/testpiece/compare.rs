//! `testpiece compare A B`: the differences of two parts' identified parameters.

use testpiece::analysis::{analyse, AnalysisOptions, Session};
use testpiece::compare::{compare, parameters_of, Comparison, Flag};

use crate::common::{file_name, mm, print_json, read, ModeBranch};

/// differences of two parts' parameters with σ_d = √(σa²+σb²), flagged at 2 and 3 σ
///
/// Identifies the machine from each of two measured parts (before / after compensation, two
/// machines, two dates) and prints, per parameter, d = B - A with σ_d = √(σ_A² + σ_B²) (independent
/// parts) and z = d/σ_d. Flags: different (|z| >= 3), suspect (2 <= |z| < 3), consistent, and
/// undetermined when a side has no std (not separable). CSV: name,unit,a,a_std,b,b_std,diff,std,z,flag
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the first measured part (any CMM export)
    a: String,
    /// the second measured part
    b: String,
    #[command(flatten)]
    model: ModeBranch,
    /// also fit the tool-radius error dR (mm)
    #[arg(long)]
    tool_radius: bool,
    /// a priori σ of the deviations (mm)
    #[arg(long, value_name = "MM", value_parser = mm, allow_negative_numbers = true)]
    sigma: Option<f64>,
    /// {a, b, differences: [...], different, suspect, summary}
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), String> {
    let settings = AnalysisOptions {
        mode: a.model.mode,
        branch: a.model.branch,
        tool_radius: a.tool_radius,
        noise_sigma: a.sigma,
        ..AnalysisOptions::default()
    };
    // The two parts share their settings: prepared once.
    let session = Session::new(&settings).map_err(|e| format!("{}: {e}", a.a))?;
    let run_one = |f: &str| -> Result<_, String> {
        let name = file_name(f);
        let part =
            analyse(&session, &read(f)?, &name, &settings).map_err(|e| format!("{f}: {e}"))?;
        Ok((name, parameters_of(&part.identification)))
    };
    let (na, pa) = run_one(&a.a)?;
    let (nb, pb) = run_one(&a.b)?;
    let c = compare(&na, &pa, &nb, &pb).map_err(|e| e.to_string())?;
    if a.json {
        return print_json(&c);
    }
    print_csv(&c);
    eprintln!("{}", c.summary);
    Ok(())
}

/// `name,unit,a,a_std,b,b_std,diff,std,z,flag`, one row per parameter.
fn print_csv(c: &Comparison) {
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
}
