//! `testpiece identify FILE --compensation`: the correction in the controller's terms (issue 19,
//! step 3), printed after the identification; with `--json` the field `compensation`.

use testpiece::compensation::Compensation;
use testpiece::machine::axis_lines::KinematicDescription;

fn vec3(v: [f64; 3]) -> String {
    format!("({:.6}, {:.6}, {:.6})", v[0], v[1], v[2])
}

fn description(title: &str, d: &KinematicDescription) {
    println!("{title} ({}):", d.code);
    for a in &d.axes {
        match a.point {
            Some(p) => println!(
                "  {} rotary: point {} mm, direction {}",
                a.axis,
                vec3(p),
                vec3(a.direction)
            ),
            None => println!("  {} linear: direction {}", a.axis, vec3(a.direction)),
        }
    }
    println!("  tool tip at the reference pose {} mm", vec3(d.tool_tip));
    for o in &d.offsets {
        println!("  offset {} -> {}: {} mm", o.from, o.to, vec3(o.vector));
    }
}

/// The text report.
pub fn print(c: &Compensation) {
    println!("Compensation in the controller's terms ({}):", c.machine);
    description("before (nominal, as the controller holds it)", &c.before);
    description("after (with the identified location errors)", &c.after);
    for ch in &c.changes {
        match ch.point_shift {
            Some(s) => println!(
                "  {} moved by {} mm, turned by {:.3e} rad",
                ch.axis,
                vec3(s),
                ch.tilt
            ),
            None => println!("  {} turned by {:.3e} rad", ch.axis, ch.tilt),
        }
    }
    println!("  tool tip moved by {} mm", vec3(c.tool_tip_shift));
    println!(
        "predicted part after compensation: rms {:.4} mm (was {:.4}), max |d| {:.4} mm (was {:.4})",
        c.part.after.rms, c.part.before.rms, c.part.after.max_abs, c.part.before.max_abs
    );
    for n in &c.notes {
        println!("note: {n}");
    }
}
