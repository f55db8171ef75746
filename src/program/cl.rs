//! The CL file of a program: APT cutter-location data (ANSI/ISO 3592 records as CAM systems
//! write them) in the part frame, the tool tip and unit tool axis per position:
//!
//! ```text
//! PARTNO/…   UNITS/MM   MULTAX   CUTTER/20   LOADTL/1   SPINDL/6000,CLW   COOLNT/FLOOD
//! RAPID                  (before each positioning GOTO: retract, rotary axes, X Y, down)
//! GOTO/x,y,z,i,j,k
//! FEDRAT/1000.0,MMPM     (the move along the tool axis into the pass, the pass, out of it)
//! GOTO/x,y,z,i,j,k …
//! COOLNT/OFF   SPINDL/OFF   FINI
//! ```
//!
//! The positions of the pass are the exact path (full precision, read back by `budget --cl`);
//! the positioning moves are those of [`super::motion`] through the nominal direct kinematics
//! (no GOTO at feed between two passes: surface A's last cut is followed by its retract along
//! the axis, then rapids).

use std::fmt::Write;

use super::motion::StepKind;
use super::Program;
use crate::machine::direct::nominal;
use crate::toolpath::TOOL_RADIUS;

fn goto(s: &mut String, tip: [f64; 3], axis: [f64; 3]) {
    let _ = writeln!(
        s,
        "GOTO/{},{},{},{},{},{}",
        tip[0], tip[1], tip[2], axis[0], axis[1], axis[2]
    );
}

/// The CL text of `p`.
pub fn write_cl(p: &Program) -> String {
    let mut s: String = p.header().lines().map(|l| format!("$$ {l}\n")).collect();
    let o = &p.settings;
    let _ = write!(
        s,
        "PARTNO/TESTPIECE S-SHAPE FINISHING FLANK PASS\nUNITS/MM\nMULTAX\nCUTTER/{}\n\
         LOADTL/{}\nSPINDL/{:.0},CLW\nCOOLNT/FLOOD\n",
        2.0 * TOOL_RADIUS,
        o.tool,
        o.spindle
    );
    let chain = o.chain();
    let mut positions = p.passes.iter().flat_map(|x| x.positions.iter());
    let mut feeding = false;
    for st in &p.motion.steps {
        match st.kind {
            StepKind::Home => {}
            StepKind::Rapid => {
                s.push_str("RAPID\n");
                feeding = false;
                let t = nominal(&chain, &st.q, 0.0);
                goto(&mut s, t.point.into(), t.direction.into());
            }
            StepKind::Approach | StepKind::Exit | StepKind::Cut => {
                if !feeding {
                    let _ = writeln!(s, "FEDRAT/{:.1},MMPM", o.feed);
                    feeding = true;
                }
                if st.kind == StepKind::Exit {
                    let t = nominal(&chain, &st.q, 0.0);
                    goto(&mut s, t.point.into(), t.direction.into());
                } else if let Some(q) = positions.next() {
                    goto(&mut s, q.tip, q.axis);
                }
            }
        }
    }
    s.push_str("COOLNT/OFF\nSPINDL/OFF\nFINI\n");
    s
}
