//! `testpiece machine [--machine M] [--l0 MM] [--branch signed|positive] [--json]`: the location
//! errors a machine is identified with, derived from what the part sees, and its conventions.

use testpiece::effects::catalogue::{machine_effects, EffectStatus};
use testpiece::effects::prepared::Prepared;
use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::Branch;
use testpiece::part::SShape;
use testpiece::sensitivity::error_set::{ErrorSet, ErrorStatus, VISIBLE_FRACTION};
use testpiece::sensitivity::SensitivityOptions;
use testpiece::settings::MachineChoice;

use crate::common::{branch, machine, mm, positive_l0, print_json, to_json};

/// the location errors a machine is identified with (derived from what the part sees), the ones left out and why, and its coordinate convention [--machine M]
///
/// The set is derived, not listed: from every ISO 230-1 location error of the chain's axes (for
/// a linear axis its zero offset and two squareness angles; for a rotary axis the two positions
/// of its line across it, its two tilts and its angular zero), the columns of the machined defect
/// at the part's 100 built-in points (physical mode, per 1e-4 rad or 0.01 mm) are taken in a
/// fixed order (paper 000 Table 3's convention first, then rotary-line positions, tilts,
/// squareness, zero offsets) and one is kept when at least 1/30 of its RMS is left after the
/// errors kept before it (condition index 30, the identification's limit of separability).
/// Angular zeros are never kept: the C index next to the part is the effect c_index (a_index on
/// the A-B head); the others are fixed by the reference pose.
///
/// Statuses: kept (identified); absorbed (the part cannot tell it from the kept ones: `looks like`
/// gives one unit of it in their terms); invisible (no deviation on a flank-milled wall); index.
///
/// Sets on the built-in design (signed branch):
///   paper000 (B head / C table)     EC0Y EA0Z EB0Z EA0C EB0C EX0B EA0B EC0B  (paper 000 Table 3)
///   paper002 (B-C tilting table)    EC0Y EA0Z EB0Z EA0C EX0B EC0B EY0C EZ0B
///   paper001 (A-B head)             EC0Y EA0Z EB0Z EA0B EC0B EZ0A EB0A EC0A EA0Y
///
/// The machine's own effects (effects.md): each candidate is offered, invisible (its signature is
/// exactly zero there, e.g. backlash_z, scale_z and thermal_drift on the tilting table, whose Z is
/// the tool axis) or left out (the machine lacks its axis or pivot, or it is one of the machine's
/// location errors under another name: c_index on the tilting table is -0.976 EC0B on the part).
///
/// Prints CSV `name,unit,status,rms_um,unabsorbed_um,looks_like,reason` (µm of deviation RMS per
/// typical size), then the conventions and the effects as `# ` lines; --json prints the whole set
/// with `effects` [{effect, status, reason}].
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the chain: paper000 (B head / C table), paper001 (A-B head), paper002 (B-C tilting table)
    #[arg(long, value_name = "paper000|paper001|paper002", default_value = "paper000", value_parser = machine)]
    machine: MachineChoice,
    /// the pivot-to-tip length (mm)
    #[arg(long, value_name = "MM", default_value_t = PAPER000_L0, value_parser = mm, allow_negative_numbers = true)]
    l0: f64,
    /// the B-axis branch of the inverse kinematics
    #[arg(long, value_name = "signed|positive", default_value = "signed", value_parser = branch)]
    branch: Branch,
    /// the whole set as JSON, with `effects`, `machine` and `description`
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), String> {
    let chain = a.machine.chain(positive_l0(a.l0)?);
    let opts = SensitivityOptions::default()
        .with_chain(chain)
        .with_branch(a.branch);
    let prepared = Prepared::new(SShape::iso(), opts).map_err(|e| e.to_string())?;
    let set = prepared.error_set();
    let effects = machine_effects(&prepared);
    if a.json {
        let mut v = to_json(set)?;
        v["effects"] = to_json(&effects)?;
        v["machine"] = to_json(&a.machine)?;
        v["description"] = serde_json::json!(a.machine.describe());
        return print_json(&v);
    }
    print_rows(set);
    print_notes(a.machine, set, &effects);
    Ok(())
}

/// `name,unit,status,rms_um,unabsorbed_um,looks_like,reason`, one row per location error.
fn print_rows(set: &ErrorSet) {
    println!("name,unit,status,rms_um,unabsorbed_um,looks_like,reason");
    for r in &set.rows {
        let status = match r.status {
            ErrorStatus::Kept => "kept",
            ErrorStatus::Absorbed => "absorbed",
            ErrorStatus::Invisible => "invisible",
            ErrorStatus::Index => "index",
        };
        let looks = r.looks_like.as_ref().map_or("", |l| l.text.as_str());
        println!(
            "{},{},{},{:.4},{:.4},\"{}\",\"{}\"",
            r.name,
            r.unit,
            status,
            r.rms * 1e3,
            r.unabsorbed * 1e3,
            looks,
            r.reason.replace('"', "'")
        );
    }
}

/// The `# ` lines: the count kept, the conventions, the machine's effects.
fn print_notes(machine: MachineChoice, set: &ErrorSet, effects: &[EffectStatus]) {
    println!(
        "# {}: {} kept of {}, kept when >= {:.1} % of a column is left",
        machine.describe(),
        set.kept.len(),
        set.rows.len(),
        100.0 * VISIBLE_FRACTION
    );
    for c in &set.conventions {
        println!("# {c}");
    }
    for e in effects {
        match e.status {
            "offered" => println!("# effect {}: offered", e.effect),
            s => println!("# effect {}: {s}: {}", e.effect, e.reason),
        }
    }
}
