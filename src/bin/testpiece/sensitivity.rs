//! `testpiece sensitivity [--mode physical|paper] [--branch signed|positive] [--json]`

use crate::args::Args;
use testpiece::machine::Branch;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::{sensitivity_matrix, Mode, SensitivityOptions};

const HELP: &str = "\
testpiece sensitivity [--mode physical|paper] [--branch signed|positive] [--json]

Figure 19 of paper 000: the machined defect (mm, + = material left) at the 100 built-in points
per unit of each of the 8 location errors of the B-head / C-table machine (L0 = 499.889 mm):
CSV `id,curve,EC0Y,EA0Z,EB0Z,EA0C,EB0C,EX0B,EA0B,EC0B` (mm per rad; mm per mm for EX0B).

  --mode physical  (default) tool-axis point at the contact height, normal N(u,v), reference at
                   the part origin (0,0,L0,0,0)
  --mode paper     tool tip, normal N(u,1), reference at (0,0,0,0,0): eq. 14 as printed
  --branch signed  (default) C modulo pi unwrapped, B signed (eq. 9); `positive`: B >= 0
";

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(rest, &["mode", "branch"])?;
    let mode = match args.value("mode") {
        Some(m) => Mode::parse(m).map_err(|e| e.to_string())?,
        None => Mode::Physical,
    };
    let branch = match args.value("branch") {
        Some(b) => Branch::parse(b)
            .ok_or_else(|| format!("`{b}` is not a branch (expected `signed` or `positive`)"))?,
        None => Branch::Signed,
    };
    let json = args.flag("json");
    args.reject_unknown("sensitivity")?;
    let part = SShape::iso();
    let points = builtin_points(&part);
    let opts = SensitivityOptions::default()
        .with_mode(mode)
        .with_branch(branch);
    let m = sensitivity_matrix(&part, &points, &opts).map_err(|e| e.to_string())?;
    if json {
        let rows: Vec<_> = (0..m.ids.len())
            .map(|i| {
                let mut o = serde_json::Map::new();
                o.insert("id".into(), m.ids[i].into());
                o.insert("curve".into(), m.curves[i].clone().into());
                for (k, p) in m.params.iter().enumerate() {
                    o.insert(p.clone(), m.values[(i, k)].into());
                }
                serde_json::Value::Object(o)
            })
            .collect();
        let doc = serde_json::json!({
            "mode": mode.name(),
            "branch": match branch { Branch::Signed => "signed", Branch::Positive => "positive" },
            "params": m.params,
            "points": rows,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&doc).map_err(|e| e.to_string())?
        );
    } else {
        println!("id,curve,{}", m.params.join(","));
        for i in 0..m.ids.len() {
            let vals: Vec<String> = (0..m.params.len())
                .map(|k| m.values[(i, k)].to_string())
                .collect();
            println!("{},{},{}", m.ids[i], m.curves[i], vals.join(","));
        }
    }
    Ok(())
}
