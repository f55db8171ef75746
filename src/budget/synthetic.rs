//! Synthetic tool paths for examples and tests: the ideal flank path of eq. 2 sampled at a
//! fixed step (a CAM program like TP1S1 of paper 000 §4.1: "distance between points: 0.5 mm",
//! tangent to the top curve), its controller trace by inverse kinematics (eq. 10), and writers
//! of the two file formats that [`super::cl`] and [`super::trace`] read.

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
            path.tips.push([p.tip.x, p.tip.y, p.tip.z]);
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

/// A CL file in CSV (`x,y,z,i,j,k`, full precision), with a comment line `# {comment}`.
pub fn write_cl_csv(path: &ToolPath, comment: &str) -> String {
    let mut s = format!("# {comment}\nx,y,z,i,j,k\n");
    for (t, a) in path.tips.iter().zip(&path.axes) {
        let _ = writeln!(s, "{},{},{},{},{},{}", t[0], t[1], t[2], a[0], a[1], a[2]);
    }
    s
}

/// A CL file in APT (`GOTO/x,y,z,i,j,k` with PARTNO, UNITS, MULTAX, CUTTER, FEDRAT, FINI).
pub fn write_apt(path: &ToolPath, partno: &str) -> String {
    let mut s = format!("PARTNO/{partno}\nUNITS/MM\nMULTAX\n");
    if let Some(d) = path.cutter_diameter {
        let _ = writeln!(s, "CUTTER/{d}");
    }
    s += "FEDRAT/1000.0,MMPM\n";
    for (t, a) in path.tips.iter().zip(&path.axes) {
        let _ = writeln!(
            s,
            "GOTO/{},{},{},{},{},{}",
            t[0], t[1], t[2], a[0], a[1], a[2]
        );
    }
    s += "FINI\n";
    s
}

/// A trace file: `time,<axes>` (s; mm and the machine's angle unit), one row per sample every
/// `period` s, with a comment line `# {comment}`.
pub fn write_trace_csv(
    rows: &[AxisValues],
    machine: &TraceMachine,
    period: f64,
    comment: &str,
) -> String {
    let axes: Vec<_> = machine.chain.axes().map(|a| a.name).collect();
    let head: Vec<String> = axes.iter().map(|a| a.letter().to_string()).collect();
    let mut s = format!("# {comment}\ntime,{}\n", head.join(","));
    let per_rad = 1.0 / machine.angle_unit.to_rad();
    for (k, q) in rows.iter().enumerate() {
        let _ = write!(s, "{}", k as f64 * period);
        for a in &axes {
            let v = q.get(*a);
            let v = if a.kind() == AxisKind::Rotary {
                v * per_rad
            } else {
                v
            };
            let _ = write!(s, ",{v}");
        }
        s.push('\n');
    }
    s
}
