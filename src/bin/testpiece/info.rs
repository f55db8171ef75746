//! `testpiece info [--json]`

use crate::common::print_json;

/// lengths of the four measurement curves of the built-in S-shape (mm)
///
/// Prints the lengths of the four measurement curves of the built-in ISO 10791-7 S-shape
/// (A_Z11, A_Z25, B_Z11, B_Z25) as CSV `curve,z,length` (mm), or as JSON with --json.
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the lengths as JSON
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), String> {
    let s = testpiece::summary::part_summary();
    if a.json {
        return print_json(&s);
    }
    println!("curve,z,length");
    for c in &s.curves {
        println!("{},{},{}", c.curve, c.z, c.length);
    }
    Ok(())
}
