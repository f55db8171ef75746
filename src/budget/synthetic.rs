//! Synthetic tool paths for examples and tests: the ideal flank path of eq. 2 sampled at a
//! fixed step (a CAM program like TP1S1 of paper 000 §4.1: "distance between points: 0.5 mm",
//! tangent to the top curve), its controller trace by inverse kinematics (eq. 10), and writers
//! of the two file formats that [`super::cl`] and [`super::trace`] read.

use crate::sensitivity::Mode;
use std::fmt::Write;

use super::trace::TraceMachine;
use super::ToolPath;
use crate::machine::inverse::inverse;
use crate::machine::{AxisKind, AxisValues, Branch, MachineError};
use crate::part::{SShape, Surface};
use crate::toolpath::tool_pose;

/// Intervals of the table used to place the samples at equal tip distance.
const TABLE: usize = 20_000;

/// The tool positions of eq. 2 on surface A then surface B, the tip advancing `step` mm
/// between positions (the last one at `u = 1`). `step` must be positive.
pub fn flank_path(part: &SShape, step: f64, name: &str) -> ToolPath {
    flank_path_with_allowance(part, step, 0.0, name)
}

/// [`flank_path`] for a stock allowance `allowance` (mm): every tip moved by `allowance·N(u,1)`
/// (the tool axis `R(u)` is ⊥ `N(u,1)`, so the tool's flank moves `allowance` away from the part
/// along its contact normal: + leaves material).
pub fn flank_path_with_allowance(part: &SShape, step: f64, allowance: f64, name: &str) -> ToolPath {
    let mut path = ToolPath {
        name: name.to_string(),
        format: format!("eq. 2 flank path sampled every {step} mm"),
        tips: Vec::new(),
        axes: Vec::new(),
        lines: Vec::new(),
        times: None,
        cutter_diameter: Some(2.0 * crate::toolpath::TOOL_RADIUS),
        notes: Vec::new(),
    };
    for s in Surface::BOTH {
        for u in equal_steps(part, s, step) {
            let p = tool_pose(part, s, u);
            let tip = p.tip + part.frame_at(s, u, 1.0).n * allowance;
            path.tips.push([tip.x, tip.y, tip.z]);
            path.axes.push([p.axis.x, p.axis.y, p.axis.z]);
        }
    }
    path.lines = (1..=path.tips.len()).collect();
    path
}

/// Path parameters at which the tip of surface `s`'s flank path is `step` mm apart.
pub fn equal_steps(part: &SShape, s: Surface, step: f64) -> Vec<f64> {
    let step = if step.is_finite() && step > 0.0 {
        step
    } else {
        0.5
    };
    let tip = |u: f64| tool_pose(part, s, u).tip;
    let mut cum = vec![0.0; TABLE + 1];
    let mut prev = tip(0.0);
    for k in 1..=TABLE {
        let p = tip(k as f64 / TABLE as f64);
        cum[k] = cum[k - 1] + (p - prev).norm();
        prev = p;
    }
    let total = cum[TABLE];
    let mut us = Vec::new();
    let mut k = 0;
    let mut target = 0.0;
    while target < total {
        while cum[k + 1] < target {
            k += 1;
        }
        let f = (target - cum[k]) / (cum[k + 1] - cum[k]).max(1e-300);
        us.push((k as f64 + f) / TABLE as f64);
        target += step;
    }
    us.push(1.0);
    us
}

/// Axis values of every position of `path` by inverse kinematics (eq. 10 for paper 000's
/// machine), the outer rotary angle kept near the previous one along the path.
pub fn trace_of(
    path: &ToolPath,
    machine: &TraceMachine,
    branch: Branch,
) -> Result<Vec<AxisValues>, MachineError> {
    let v = |a: &[f64; 3]| nalgebra::Vector3::new(a[0], a[1], a[2]);
    let outer = crate::machine::inverse::RotaryPair::of(&machine.chain)?.outer;
    let mut prev = 0.0;
    path.tips
        .iter()
        .zip(&path.axes)
        .map(|(t, a)| {
            let q = inverse(&machine.chain, &v(t), &v(a), branch, prev)?;
            prev = q.get(outer);
            Ok(q)
        })
        .collect()
}

/// A number in full precision (`None`) or with `decimals` decimals.
fn num(v: f64, decimals: Option<usize>) -> String {
    match decimals {
        Some(d) => format!("{v:.d$}"),
        None => format!("{v}"),
    }
}

/// Six numbers joined by commas.
fn six(t: &[f64; 3], a: &[f64; 3], d: Option<usize>) -> String {
    [t[0], t[1], t[2], a[0], a[1], a[2]]
        .iter()
        .map(|v| num(*v, d))
        .collect::<Vec<_>>()
        .join(",")
}

/// A CL file in CSV (`x,y,z,i,j,k`, full precision), with a comment line `# {comment}`.
pub fn write_cl_csv(path: &ToolPath, comment: &str) -> String {
    let mut s = format!("# {comment}\nx,y,z,i,j,k\n");
    for (t, a) in path.tips.iter().zip(&path.axes) {
        let _ = writeln!(s, "{}", six(t, a, None));
    }
    s
}

/// A CL file in APT (`GOTO/x,y,z,i,j,k` with PARTNO, UNITS, MULTAX, CUTTER, FEDRAT, FINI), full
/// precision or `decimals` decimals.
pub fn write_apt(path: &ToolPath, partno: &str, decimals: Option<usize>) -> String {
    let mut s = format!("PARTNO/{partno}\nUNITS/MM\nMULTAX\n");
    if let Some(d) = path.cutter_diameter {
        let _ = writeln!(s, "CUTTER/{d}");
    }
    s += "FEDRAT/1000.0,MMPM\n";
    for (t, a) in path.tips.iter().zip(&path.axes) {
        let _ = writeln!(s, "GOTO/{}", six(t, a, decimals));
    }
    s += "FINI\n";
    s
}

/// A trace file: `time,<axes>` (s; mm and the machine's angle unit), one row per sample every
/// `period` s, with a comment line `# {comment}`; full precision or `decimals` decimals.
pub fn write_trace_csv(
    rows: &[AxisValues],
    machine: &TraceMachine,
    period: f64,
    comment: &str,
    decimals: Option<usize>,
) -> String {
    let axes = machine.axis_names();
    let head: Vec<String> = axes.iter().map(|a| a.letter().to_string()).collect();
    let mut s = format!("# {comment}\ntime,{}\n", head.join(","));
    let per_rad = 1.0 / machine.angle_unit.to_rad();
    for (k, q) in rows.iter().enumerate() {
        let _ = write!(s, "{}", num(k as f64 * period, Some(3)));
        for a in &axes {
            let v = q.get(*a);
            let v = if a.kind() == AxisKind::Rotary {
                v * per_rad
            } else {
                v
            };
            let _ = write!(s, ",{}", num(v, decimals));
        }
        s.push('\n');
    }
    s
}

/// The three example files of `tests/data/budget/` (README there), generated: the CAM path of
/// eq. 2 every 1 mm as APT; its NC trace on paper 000's machine with a following error of 4 µm
/// on X and 0.003° on C; and the measured part = the trace's deviation + machine defect
/// (EX0B = 0.01 mm, EA0B = 1.2e-4 rad) + a 5 µm oversize tool + CMM noise σ = 1 µm (seed 10).
/// `(file name, content)`; tests/it/budget_examples.rs checks the files on disk are exactly these.
pub fn example_files() -> Result<Vec<(&'static str, String)>, super::BudgetError> {
    use crate::cmm::write::{canonical_csv, Precision};
    use crate::machine::{AxisName, ErrorParam, LocationError};
    use crate::parameter::ParamId;
    use crate::part::builtin_points;
    use crate::simulate::{builtin_design, simulate_deviation};
    use crate::toolpath::TOOL_RADIUS;
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let machine = TraceMachine::default();
    let cl = flank_path(&part, 1.0, "example_cl.apt");
    let apt = write_apt(
        &cl,
        "S-SHAPE EQ2 FLANK PATH EVERY 1 MM (testpiece synthetic example)",
        Some(6),
    );
    let mut rows = trace_of(&cl, &machine, Branch::Signed)?;
    for (k, q) in rows.iter_mut().enumerate() {
        let s = (k as f64 / 25.0).sin();
        q.set(AxisName::X, q.get(AxisName::X) + 0.004 * s);
        q.set(AxisName::C, q.get(AxisName::C) + 0.003f64.to_radians() * s);
    }
    let trace_text = write_trace_csv(
        &rows,
        &machine,
        0.008,
        "testpiece synthetic NC trace of example_cl.apt on paper 000's machine (L0 = 499.889 mm), X Y Z mm, B C degrees, following error 4 um on X and 0.003 deg on C",
        Some(6),
    );
    let trace = super::read_trace(trace_text.as_bytes(), "example_trace.csv", &machine)?;
    let d_trace: Vec<f64> = super::path_deviation(&trace, &pts, TOOL_RADIUS)?
        .iter()
        .map(|h| h.deviation)
        .collect();
    let design = builtin_design(Mode::Physical, Branch::Signed, true)?;
    let (ex0b, ea0b) = (
        LocationError::new(AxisName::X, AxisName::B),
        LocationError::new(AxisName::A, AxisName::B),
    );
    let errors = vec![
        (ParamId::Machine(ErrorParam::Location(ex0b)), 0.01),
        (ParamId::Machine(ErrorParam::Location(ea0b)), 1.2e-4),
        (ParamId::ToolRadius, 0.005),
    ];
    let defect = simulate_deviation(&design, &errors, 0.001, 10)?;
    let measured: Vec<f64> = d_trace.iter().zip(&defect).map(|(a, b)| a + b).collect();
    let cmm = canonical_csv(
        pts.iter().zip(measured),
        Precision::Decimals(6),
        Some("testpiece synthetic measured part for the budget example: deviation = NC trace deviation (example_trace.csv) + machine defect EX0B = 0.01 mm, EA0B = 1.2e-4 rad + dR = 0.005 mm + noise 1 um"),
    );
    Ok(vec![
        ("example_cl.apt", apt),
        ("example_trace.csv", trace_text),
        ("example_measured.csv", cmm),
    ])
}
