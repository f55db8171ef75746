//! `testpiece forward --machine FILE`: tool tip and tool axis from axis values on stdin.

use std::io::Read;

use testpiece::machine::description::MachineDescription;
use testpiece::machine::direct::tool_point;
use testpiece::machine::{AxisName, Chain};
use testpiece::machine::{AxisValues, MachineErrors};

use crate::common::print_json;

/// tool tip and axis from axis values on stdin through --machine FILE (JSON chain)
///
/// Reads axis values on stdin as CSV with a header naming the machine's axes (e.g. X,Y,Z,B,C;
/// other columns are ignored): X, Y, Z in mm, rotary axes in degrees (or rad if the description
/// says "angle_unit": "rad"). Prints per row `tip_x,tip_y,tip_z,i,j,k`: the tool tip (mm) and
/// unit tool axis in the workpiece frame, through the machine's chain with the errors it lists.
///
/// FILE is a JSON machine description (format in src/machine/description.rs; the machine of the
/// peer data set is tests/data/peer_bc_table.json):
///   {"code": "w C' B' b X Y Z t", "angle_unit": "deg",
///    "offsets": {"B": [x, y, z], ...}, "tool_offset": [0, 0, -120], "errors": {"EX0B": 0.01}}
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the JSON machine description
    #[arg(long, value_name = "FILE")]
    machine: Option<String>,
    /// {machine, rows: [{tip_x, tip_y, tip_z, i, j, k}]}
    #[arg(long)]
    json: bool,
}

/// A machine read from its description: the chain, its errors, the rotary unit's radians.
struct Machine {
    chain: Chain,
    errors: MachineErrors,
    to_rad: f64,
}

pub fn run(a: Args) -> Result<(), String> {
    let file = a
        .machine
        .ok_or("`testpiece forward` needs --machine FILE (a JSON machine description)")?;
    let m = read_machine(&file)?;
    let mut input = String::new();
    std::io::stdin()
        .read_to_string(&mut input)
        .map_err(|e| format!("cannot read stdin: {e}"))?;
    let out = tool_points(&m, &input)?;
    if a.json {
        let rows: Vec<_> = out
            .iter()
            .map(|r| {
                serde_json::json!({"tip_x": r[0], "tip_y": r[1], "tip_z": r[2],
                                   "i": r[3], "j": r[4], "k": r[5]})
            })
            .collect();
        return print_json(&serde_json::json!({"machine": m.chain.code(), "rows": rows}));
    }
    println!("tip_x,tip_y,tip_z,i,j,k");
    for r in out {
        println!("{},{},{},{},{},{}", r[0], r[1], r[2], r[3], r[4], r[5]);
    }
    Ok(())
}

/// The machine of a JSON description file; errors name the file.
fn read_machine(file: &str) -> Result<Machine, String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("cannot read {file}: {e}"))?;
    let desc = MachineDescription::from_json(&text).map_err(|e| format!("{file}: {e}"))?;
    Ok(Machine {
        chain: desc.chain().map_err(|e| format!("{file}: {e}"))?,
        errors: desc.machine_errors().map_err(|e| format!("{file}: {e}"))?,
        to_rad: desc.angle_unit.to_rad(),
    })
}

/// The tool tip and axis `[x, y, z, i, j, k]` of every row of the axis-value CSV.
fn tool_points(m: &Machine, input: &str) -> Result<Vec<[f64; 6]>, String> {
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(input.as_bytes());
    let headers = rdr.headers().map_err(|e| format!("stdin: {e}"))?.clone();
    let columns = axis_columns(&m.chain, &headers)?;
    let mut out = Vec::new();
    for (row, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| format!("stdin row {}: {e}", row + 2))?;
        let mut q = AxisValues::default();
        for &(name, i) in &columns {
            let field = rec.get(i).unwrap_or("");
            let v: f64 = field.parse().map_err(|_| {
                format!("stdin row {}: {name} = `{field}` is not a number", row + 2)
            })?;
            q.set_in_units(name, v, m.to_rad);
        }
        let t = tool_point(&m.chain, &q, 0.0, &m.errors)
            .map_err(|e| format!("row {}: {e}", row + 2))?;
        out.push(t.to_array());
    }
    Ok(out)
}

/// The column of each of the chain's axes in the header.
fn axis_columns(
    chain: &Chain,
    headers: &csv::StringRecord,
) -> Result<Vec<(AxisName, usize)>, String> {
    let mut columns = Vec::new();
    for a in chain.axes() {
        let name = a.name.letter().to_string();
        let i = headers
            .iter()
            .position(|h| h.eq_ignore_ascii_case(&name))
            .ok_or_else(|| {
                format!(
                    "stdin: no column `{name}` for axis {name} of `{}` (header: {})",
                    chain.code(),
                    headers.iter().collect::<Vec<_>>().join(",")
                )
            })?;
        columns.push((a.name, i));
    }
    Ok(columns)
}
