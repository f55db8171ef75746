//! `testpiece sensitivity [--mode physical|paper] [--branch signed|positive] [--json]`

use testpiece::machine::Branch;
use testpiece::parameter::ParamId;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::error_set::error_set;
use testpiece::sensitivity::{
    axis_values, sensitivity_matrix, Mode, SensitivityMatrix, SensitivityOptions,
};

use crate::common::{branch, branch_name, mode, print_json};

/// Figure-19 defect per unit of each of the 8 location errors [--mode] [--branch]
///
/// Figure 19 of paper 000: the machined defect (mm, + = material left) at the 100 built-in points
/// per unit of each of the 8 location errors of the B-head / C-table machine (L0 = 499.889 mm):
/// CSV `id,curve,EC0Y,EA0Z,EB0Z,EA0C,EB0C,EX0B,EA0B,EC0B` (mm per rad; mm per mm for EX0B).
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// physical (default): tool-axis point at the contact height, normal N(u,v), reference at
    /// the part origin (0,0,L0,0,0); paper: tool tip, normal N(u,1), reference at (0,0,0,0,0):
    /// eq. 14 as printed
    #[arg(long, value_name = "physical|paper", default_value = "physical", value_parser = mode, verbatim_doc_comment)]
    mode: Mode,
    /// signed (default): C modulo pi unwrapped, B signed (eq. 9); positive: B >= 0
    #[arg(long, value_name = "signed|positive", default_value = "signed", value_parser = branch)]
    branch: Branch,
    /// the matrix as JSON: {mode, branch, params, points: [{id, curve, EC0Y, ...}]}
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), String> {
    let part = SShape::iso();
    let points = builtin_points(&part);
    let opts = SensitivityOptions::default()
        .with_mode(a.mode)
        .with_branch(a.branch);
    let m = error_set(&opts.chain, opts.branch)
        .and_then(|set| {
            let q = axis_values(&part, &points, &opts)?;
            sensitivity_matrix(&part, &points, &q, &opts, &set.params())
        })
        .map_err(|e| e.to_string())?;
    if a.json {
        print_json(&json(&m, a.mode, a.branch))
    } else {
        print_csv(&m);
        Ok(())
    }
}

/// `{mode, branch, params, parameters: [{kind, name, unit}], points: [{id, curve, <param>:
/// value, ...}]}`.
fn json(m: &SensitivityMatrix, mode: Mode, branch: Branch) -> serde_json::Value {
    let names = m.names();
    let rows: Vec<_> = (0..m.ids.len())
        .map(|i| {
            let mut o = serde_json::Map::new();
            o.insert("id".into(), m.ids[i].into());
            o.insert("curve".into(), m.curves[i].clone().into());
            for (k, p) in names.iter().enumerate() {
                o.insert(p.clone(), m.values[(i, k)].into());
            }
            serde_json::Value::Object(o)
        })
        .collect();
    let parameters: Vec<ParamId> = m.errors.iter().map(|e| ParamId::Machine(*e)).collect();
    serde_json::json!({
        "mode": mode.name(),
        "branch": branch_name(branch),
        "params": names,
        "parameters": parameters,
        "points": rows,
    })
}

/// `id,curve,<param>,...`, one row per point.
fn print_csv(m: &SensitivityMatrix) {
    println!("id,curve,{}", m.names().join(","));
    for i in 0..m.ids.len() {
        let vals: Vec<String> = (0..m.errors.len())
            .map(|k| m.values[(i, k)].to_string())
            .collect();
        println!("{},{},{}", m.ids[i], m.curves[i], vals.join(","));
    }
}
