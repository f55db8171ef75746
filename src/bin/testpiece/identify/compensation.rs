//! `testpiece identify FILE --compensation`: the correction in the controller's terms (issue 19,
//! step 3), printed after the identification; with `--json` the field `compensation`.

use testpiece::compensation::Compensation;
use testpiece::machine::axis_lines::KinematicDescription;

fn vec3(v: [f64; 3]) -> String {
    format!("({:.6}, {:.6}, {:.6})", v[0], v[1], v[2])
}

fn std3(v: [f64; 3]) -> String {
    format!("± ({:.1e}, {:.1e}, {:.1e})", v[0], v[1], v[2])
}

/// The description; with `std` (same shape) each vector followed by its std.
fn description(title: &str, d: &KinematicDescription, std: Option<&KinematicDescription>) {
    let s = |f: &dyn Fn(&KinematicDescription) -> [f64; 3]| {
        std.map_or(String::new(), |x| format!(" {}", std3(f(x))))
    };
    println!("{title} ({}):", d.code);
    for (k, a) in d.axes.iter().enumerate() {
        let dir = s(&|x| x.axes[k].direction);
        match a.point {
            Some(p) => println!(
                "  {} rotary: point {} mm{}, direction {}{dir}",
                a.axis,
                vec3(p),
                s(&|x| x.axes[k].point.unwrap_or([f64::NAN; 3])),
                vec3(a.direction)
            ),
            None => println!("  {} linear: direction {}{dir}", a.axis, vec3(a.direction)),
        }
    }
    println!(
        "  tool tip at the reference pose {} mm{}",
        vec3(d.tool_tip),
        s(&|x| x.tool_tip)
    );
    for (k, o) in d.offsets.iter().enumerate() {
        println!(
            "  offset {} -> {}: {} mm{}",
            o.from,
            o.to,
            vec3(o.vector),
            s(&|x| x.offsets[k].vector)
        );
    }
}

/// The text report.
pub fn print(c: &Compensation) {
    println!("Compensation in the controller's terms ({}):", c.machine);
    println!("entered (separable, |value| >= 2 std):");
    for e in &c.entered {
        println!(
            "  {} = {:.4e} ± {:.1e} {}",
            e.name,
            e.value,
            e.std.unwrap_or(f64::NAN),
            e.unit
        );
    }
    description(
        "before (nominal, as the controller holds it)",
        &c.before,
        None,
    );
    description(
        "after (with the entered location errors; std propagated)",
        &c.after,
        Some(&c.after_std),
    );
    println!("  covariance: {}", c.covariance);
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
    let w = &c.withheld;
    for k in &w.curves {
        println!(
            "withheld {} ({} points; fit of the other curves enters {}): rms {:.4} mm -> {:.4} \
             mm predicted, max |d| {:.4} mm",
            k.curve,
            k.points,
            k.entered.join(" "),
            k.measured.rms,
            k.after.rms,
            k.after.max_abs
        );
    }
    for k in &w.skipped {
        println!("withheld: {k}");
    }
    if let Some(ctl) = &c.controller {
        println!(
            "{} (kinematic type {:?}):",
            ctl.controller, ctl.kinematic_type
        );
        for p in &ctl.parameters {
            println!(
                "  {:<36} {:>14.6e} ± {:.1e} {}  ({})",
                p.name, p.value, p.std, p.unit, p.meaning
            );
        }
    }
    for n in &c.notes {
        println!("note: {n}");
    }
}
