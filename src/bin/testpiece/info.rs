//! `testpiece info [--json]`

use crate::args::Args;

const HELP: &str = "\
testpiece info [--json]

Prints the lengths of the four measurement curves of the built-in ISO 10791-7 S-shape
(A_Z11, A_Z25, B_Z11, B_Z25) as CSV `curve,z,length` (mm), or as JSON with --json.
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &[])?;
    let json = args.flag("json");
    args.reject_unknown("info")?;
    let s = testpiece::summary::part_summary();
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&s).map_err(|e| e.to_string())?
        );
    } else {
        println!("curve,z,length");
        for c in &s.curves {
            println!("{},{},{}", c.curve, c.z, c.length);
        }
    }
    Ok(())
}
