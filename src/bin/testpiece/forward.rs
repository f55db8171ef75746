//! `testpiece forward --machine FILE`: tool tip and tool axis from axis values on stdin.

use std::io::Read;

use crate::args::Args;
use testpiece::machine::description::MachineDescription;
use testpiece::machine::direct::tool_point;
use testpiece::machine::AxisValues;

const HELP: &str = "\
testpiece forward --machine FILE [--json]

Reads axis values on stdin as CSV with a header naming the machine's axes (e.g. X,Y,Z,B,C;
other columns are ignored): X, Y, Z in mm, rotary axes in degrees (or rad if the description
says \"angle_unit\": \"rad\"). Prints per row `tip_x,tip_y,tip_z,i,j,k`: the tool tip (mm) and
unit tool axis in the workpiece frame, through the machine's chain with the errors it lists.

FILE is a JSON machine description (format in src/machine/description.rs; the machine of the
peer data set is tests/data/peer_bc_table.json):
  {\"code\": \"w C' B' b X Y Z t\", \"angle_unit\": \"deg\",
   \"offsets\": {\"B\": [x, y, z], ...}, \"tool_offset\": [0, 0, -120], \"errors\": {\"EX0B\": 0.01}}
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["machine"])?;
    let file = args
        .value("machine")
        .ok_or("`testpiece forward` needs --machine FILE (a JSON machine description)")?
        .to_string();
    let json = args.flag("json");
    args.reject_unknown("forward")?;
    let text = std::fs::read_to_string(&file).map_err(|e| format!("cannot read {file}: {e}"))?;
    let desc = MachineDescription::from_json(&text).map_err(|e| format!("{file}: {e}"))?;
    let chain = desc.chain().map_err(|e| format!("{file}: {e}"))?;
    let errors = desc.machine_errors().map_err(|e| format!("{file}: {e}"))?;
    let to_rad = desc.angle_unit.to_rad();

    let mut input = String::new();
    std::io::stdin()
        .read_to_string(&mut input)
        .map_err(|e| format!("cannot read stdin: {e}"))?;
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(input.as_bytes());
    let headers = rdr.headers().map_err(|e| format!("stdin: {e}"))?.clone();
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
    let mut out = Vec::new();
    for (row, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| format!("stdin row {}: {e}", row + 2))?;
        let mut q = AxisValues::default();
        for &(name, i) in &columns {
            let field = rec.get(i).unwrap_or("");
            let v: f64 = field.parse().map_err(|_| {
                format!("stdin row {}: {name} = `{field}` is not a number", row + 2)
            })?;
            q.set_in_units(name, v, to_rad);
        }
        let t =
            tool_point(&chain, &q, 0.0, &errors).map_err(|e| format!("row {}: {e}", row + 2))?;
        out.push(t.to_array());
    }
    if json {
        let rows: Vec<_> = out
            .iter()
            .map(|r| {
                serde_json::json!({"tip_x": r[0], "tip_y": r[1], "tip_z": r[2],
                                   "i": r[3], "j": r[4], "k": r[5]})
            })
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(
                &serde_json::json!({"machine": chain.code(), "rows": rows})
            )
            .map_err(|e| e.to_string())?
        );
    } else {
        println!("tip_x,tip_y,tip_z,i,j,k");
        for r in out {
            println!("{},{},{},{},{},{}", r[0], r[1], r[2], r[3], r[4], r[5]);
        }
    }
    Ok(())
}
