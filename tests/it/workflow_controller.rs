//! Compensation a controller reads (issue 32 item 4), checked from outside the product's model:
//! 1. the SINUMERIK toolholder, CEC and work offset written for the chain with location errors,
//!    evaluated by the implementation written from Siemens' documentation
//!    (`compensation::controller::siemens_kinematics`, no use of the chain), reproduce the
//!    chain's tool tip at the program's axis positions (paper 000's machine path over both
//!    flanks, Z swept over ±100 mm) to `CONTROLLER_POSE_MM`, and its tool direction up to the
//!    spindle tilt at zero angles, which no toolholder parameter holds (the angle between the two
//!    directions equals that tilt to 1e-7 rad, eq. 11's second order (3e-4 rad)²); the same for
//!    paper 001 (type T) and paper 002 (type P);
//! 2. each curve withheld in turn, the part predicted after compensation on it equals what the
//!    exact eq. 12 model of the compensated machine (true − entered errors) cuts there, to
//!    `COMPENSATED_PART_MM`.

use crate::workflow_compensation::{simulated, TRUTH};
use testpiece::compensation::compensation;
use testpiece::compensation::controller::siemens::{toolholder, toolholder_axes};
use testpiece::compensation::controller::siemens_kinematics::tool_pose;
use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::direct::tool_point;
use testpiece::machine::{AxisValues, Branch, Chain, ErrorParam, LocationError, MachineErrors};
use testpiece::parameter::ParamId;
use testpiece::part::{SShape, Surface};
use testpiece::sensitivity::path::machine_path;
use testpiece::sensitivity::Mode;
use testpiece::simulate::simulate_exact;
use testpiece::tolerance::{COMPENSATED_PART_MM, CONTROLLER_POSE_MM};

fn errors(list: &[(&str, f64)]) -> MachineErrors {
    list.iter().fold(MachineErrors::none(), |m, (n, v)| {
        m.with(ErrorParam::Location(LocationError::parse(n).unwrap()), *v)
    })
}

fn angle(a: [f64; 3], b: nalgebra::Vector3<f64>) -> f64 {
    let a = nalgebra::Vector3::from(a);
    a.cross(&b).norm().atan2(a.dot(&b))
}

/// The worst tip distance and the worst |angle − tilt| over `poses`.
fn compare(chain: &Chain, e: &MachineErrors, poses: &[AxisValues]) -> (f64, f64, f64) {
    let (h, d0) = toolholder(chain, e).unwrap();
    let tilt = angle(d0, nalgebra::Vector3::z());
    let (mut tip_worst, mut dir_worst) = (0.0f64, 0.0f64);
    for q in poses {
        let want = tool_point(chain, q, 0.0, e).unwrap();
        let (p, alpha) = toolholder_axes(chain, h.kinematic_type, q);
        let (tip, dir) = tool_pose(&h, p, alpha);
        tip_worst = tip_worst.max((nalgebra::Vector3::from(tip) - want.point).norm());
        dir_worst = dir_worst.max((angle(dir, want.direction.normalize()) - tilt).abs());
    }
    (tip_worst, dir_worst, tilt)
}

#[test]
fn siemens_toolholder_reproduces_the_corrected_chain() {
    // Paper 000 (type M) along its program's machine path, Z offset by ±100 mm.
    let chain = Chain::paper000(PAPER000_L0);
    let part = SShape::iso();
    let us: Vec<f64> = (0..=40).map(|k| k as f64 / 40.0).collect();
    let mut poses = Vec::new();
    for s in Surface::BOTH {
        for p in machine_path(&part, &chain, s, Branch::Signed, &us).unwrap() {
            for dz in [-100.0, 0.0, 100.0] {
                let mut q = p.values;
                q.z += dz;
                poses.push(q);
            }
        }
    }
    // Rotary-axis errors without a spindle tilt: exact to the orthogonality of eq. 11.
    let rotary_only = errors(&[
        ("EX0B", 0.03),
        ("EC0B", 1e-4),
        ("EA0C", -8e-5),
        ("EB0C", 5e-5),
    ]);
    let (tip, dir, tilt) = compare(&chain, &rotary_only, &poses);
    assert!(tilt == 0.0, "no spindle tilt: {tilt}");
    assert!(tip <= CONTROLLER_POSE_MM, "type M tip {tip:e} mm");
    assert!(dir <= 1e-9, "type M direction {dir:e} rad");
    // All of paper 000's minimal set: the squareness goes to CEC, the table tilt to the work
    // offset, EA0Z + EA0B tilt the spindle (no home: the direction differs by that tilt).
    let all = errors(&[
        ("EC0Y", 6e-5),
        ("EA0Z", -7e-5),
        ("EB0Z", 4e-5),
        ("EA0C", -8e-5),
        ("EB0C", 5e-5),
        ("EX0B", 0.03),
        ("EA0B", 3e-4),
        ("EC0B", 1e-4),
    ]);
    let (tip, dir, tilt) = compare(&chain, &all, &poses);
    println!(
        "paper 000, 8 errors: tip within {tip:.2e} mm over {} poses; spindle tilt {tilt:.3e} rad \
         (the direction differs by it to {dir:.1e} rad)",
        poses.len()
    );
    assert!(tip <= CONTROLLER_POSE_MM, "type M tip {tip:e} mm");
    assert!(
        (tilt - (3e-4f64 - 7e-5).hypot(4e-5)).abs() <= 1e-6,
        "tilt {tilt}"
    );
    assert!(dir <= 1e-7, "type M direction beyond the tilt: {dir:e} rad");
    // Paper 001 (type T: B, A head) and paper 002 (type P: B, C table), on a grid.
    let grid = |b: &[f64], other: &[f64], second: char| -> Vec<AxisValues> {
        let mut v = Vec::new();
        for &x in &[-50.0, 40.0] {
            for &bb in b {
                for &o in other {
                    let mut q = AxisValues::xyzbc(x, 20.0, -30.0, bb, 0.0);
                    match second {
                        'A' => q.a = o,
                        _ => q.c = o,
                    }
                    v.push(q);
                }
            }
        }
        v
    };
    let angles = [-0.6, 0.0, 0.4];
    let cases = [
        (
            Chain::paper001(150.0, 100.0),
            errors(&[
                ("EY0B", 0.02),
                ("EC0B", 1e-4),
                ("EX0A", -0.01),
                ("EB0A", 5e-5),
            ]),
            grid(&angles, &angles, 'A'),
        ),
        (
            Chain::paper002(),
            errors(&[
                ("EX0B", 0.02),
                ("EA0B", 1e-4),
                ("EY0C", -0.01),
                ("EA0C", 5e-5),
            ]),
            grid(&angles, &[-2.0, 0.0, 2.5], 'C'),
        ),
    ];
    for (chain, e, poses) in cases {
        let (tip, dir, tilt) = compare(&chain, &e, &poses);
        println!(
            "{}: tip within {tip:.2e} mm, spindle tilt {tilt:.2e} rad",
            chain.code()
        );
        assert!(
            tip <= CONTROLLER_POSE_MM,
            "{}: tip {tip:e} mm",
            chain.code()
        );
        assert!(dir <= 1e-7, "{}: direction {dir:e} rad", chain.code());
    }
}

#[test]
fn withheld_curves_are_predicted_as_the_compensated_machine_cuts_them() {
    let truth = TRUTH;
    let a = simulated(&[]);
    let c = compensation(&a);
    let w = &c.withheld;
    assert_eq!(w.curves.len(), 4, "{:?}", w.skipped);
    let true_errors: Vec<(ParamId, f64)> = truth
        .iter()
        .map(|(n, v)| (n.parse().unwrap(), *v))
        .collect();
    let exact_true = simulate_exact(Mode::Physical, Branch::Signed, &true_errors, 0.0, 0).unwrap();
    let mut worst = 0.0f64;
    for curve in &w.curves {
        assert!(
            curve.entered.iter().any(|n| n == "EX0B"),
            "{}: {:?}",
            curve.curve,
            curve.entered
        );
        // The compensated machine keeps true − entered (the fit without this curve).
        let mut names: Vec<String> = truth.iter().map(|(n, _)| n.to_string()).collect();
        names.extend(
            curve
                .entered
                .iter()
                .filter(|n| !names.contains(n))
                .cloned()
                .collect::<Vec<_>>(),
        );
        let residual: Vec<(ParamId, f64)> = names
            .iter()
            .map(|n| {
                let t = truth.iter().find(|(m, _)| m == n).map_or(0.0, |t| t.1);
                let x = curve
                    .entered
                    .iter()
                    .position(|e| e == n)
                    .map_or(0.0, |j| curve.values[j]);
                (n.parse().unwrap(), t - x)
            })
            .collect();
        let exact_comp = simulate_exact(Mode::Physical, Branch::Signed, &residual, 0.0, 0).unwrap();
        for p in w.points.iter().filter(|p| p.curve == curve.curve) {
            let i = a
                .identification
                .points
                .iter()
                .position(|q| q.id == p.id)
                .unwrap();
            let noise = p.measured - exact_true[i];
            worst = worst.max((exact_comp[i] + noise - p.after).abs());
        }
    }
    println!(
        "withheld curves: RMS {:.2} µm measured -> {:.2} µm predicted after compensation (max \
         {:.2} µm); exact compensated machine within {:.3} µm",
        w.measured.rms * 1e3,
        w.after.rms * 1e3,
        w.after.max_abs * 1e3,
        worst * 1e3
    );
    assert!(worst <= COMPENSATED_PART_MM, "off by {worst:e} mm");
    assert!(w.after.rms < 0.5 * w.measured.rms);
}
