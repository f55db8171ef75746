//! The budget of a simulated part adds up point by point to the simulated measurement (issue 10,
//! done-when: within 1e-6 mm), every source is the one put in, and an offset CL path shifts the
//! budget by its offset.
//!
//! The simulated part: the ideal flank path (eq. 2) at 0.5 mm as the CL file; its controller
//! trace by inverse kinematics (eq. 10) with a deterministic following error on X and C; the
//! measured deviation = the trace's discrete deviation (§4.1 method) + the linear machined
//! defect of known location errors (eq. 14) − dR (§3.2), written as a canonical CMM file.

use testpiece::analysis::{AnalysisOptions, Session};
use testpiece::budget::synthetic::{
    flank_path, flank_path_with_allowance, trace_of, write_cl_csv, write_trace_csv,
};
use testpiece::budget::{
    error_budget, path_deviation, read_cl, read_trace, BudgetOptions, TraceMachine,
};
use testpiece::machine::{AxisName, Branch};
use testpiece::parameter::ParamId;
use testpiece::part::{builtin_points, MeasurementPoint, SShape};
use testpiece::sensitivity::Mode;
use testpiece::simulate::{builtin_design, simulate_deviation};
use testpiece::toolpath::TOOL_RADIUS;

fn cmm_file(pts: &[MeasurementPoint], dev: &[f64]) -> String {
    let mut s = String::from("id,curve,x,y,z,nx,ny,nz,deviation\n");
    for (p, d) in pts.iter().zip(dev) {
        s += &format!(
            "{},{},{},{},{},{},{},{},{}\n",
            p.id, p.curve, p.point.x, p.point.y, p.point.z, p.normal.x, p.normal.y, p.normal.z, d
        );
    }
    s
}

fn options(tool_radius: bool) -> BudgetOptions {
    BudgetOptions::default().with_analysis(AnalysisOptions {
        tool_radius,
        refine: false,
        ..AnalysisOptions::default()
    })
}

#[test]
fn the_budget_adds_up_to_the_simulated_measurement() {
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let machine = TraceMachine::default();
    let cl_text = write_cl_csv(&flank_path(&part, 0.5, "cl"), "eq. 2 at 0.5 mm");
    let cl = read_cl(cl_text.as_bytes(), "cl.csv").unwrap();
    let mut rows = trace_of(&cl, &machine, Branch::Signed).unwrap();
    for (k, q) in rows.iter_mut().enumerate() {
        // following error: 3 µm on X and 0.002° on C, slowly varying
        let s = (k as f64 / 40.0).sin();
        q.set(AxisName::X, q.get(AxisName::X) + 0.003 * s);
        q.set(AxisName::C, q.get(AxisName::C) + 0.002f64.to_radians() * s);
    }
    let tr_text = write_trace_csv(&rows, &machine, 0.008, "following error", None);
    let trace = read_trace(tr_text.as_bytes(), "trace.csv", &machine).unwrap();
    let d_trace: Vec<f64> = path_deviation(&trace, &pts, TOOL_RADIUS)
        .unwrap()
        .iter()
        .map(|h| h.deviation)
        .collect();
    let errors: Vec<(ParamId, f64)> = [
        ("EX0B", 0.012),
        ("EA0B", 1.5e-4),
        ("EC0Y", -4e-5),
        ("dR", 0.008),
    ]
    .iter()
    .map(|(n, v)| (n.parse().unwrap(), *v))
    .collect();
    let design = builtin_design(Mode::Physical, Branch::Signed, true).unwrap();
    let defect = simulate_deviation(&design, &errors, 0.0, 0).unwrap();
    let measured: Vec<f64> = d_trace.iter().zip(&defect).map(|(a, b)| a + b).collect();
    let cmm = cmm_file(&pts, &measured);
    let opts = options(true);
    let session = Session::new(&opts.analysis).unwrap();
    let b = error_budget(
        &session,
        cmm.as_bytes(),
        "sim.csv",
        &cl,
        Some(&trace),
        &opts,
    )
    .unwrap();
    assert_eq!(b.points.len(), 100);
    let (mut sum_err, mut res, mut mach) = (0.0f64, 0.0f64, 0.0f64);
    for (i, p) in b.points.iter().enumerate() {
        let sum = p.design + p.cam + p.nc + p.machine + p.tool + p.residual;
        sum_err = sum_err.max((sum - measured[i]).abs());
        res = res.max(p.residual.abs());
        // machine + tool = the simulated defect (the identification recovers it: no noise)
        mach = mach.max((p.machine + p.tool - defect[i]).abs());
        // design + cam + nc = the trace's deviation
        assert!(
            (p.design + p.cam + p.nc - d_trace[i]).abs() < 1e-9,
            "point {}",
            p.id
        );
        assert!(p.cmm > 0.003 && p.cmm < 0.006, "MPE band {}", p.cmm);
    }
    let dr = b
        .parameters
        .iter()
        .find(|p| p.id.name() == "dR")
        .unwrap()
        .value;
    println!(
        "sum check: max |design+cam+nc+machine+tool+residual - simulated| = {sum_err:.3e} mm; max |residual| = {res:.3e} mm; max |machine+tool - simulated defect| = {mach:.3e} mm; dR = {dr:.6} mm; NC term {:.4}..{:.4} mm, CAM {:.4}..{:.4} mm",
        b.summary.nc.min, b.summary.nc.max, b.summary.cam.min, b.summary.cam.max
    );
    assert!(sum_err <= 1e-6, "{sum_err}");
    assert!(b.sum_check <= 1e-12);
    assert!(res <= 1e-6, "{res}");
    assert!(mach <= 1e-6, "{mach}");
    assert!((dr - 0.008).abs() < 1e-6);
    assert!(
        b.summary.nc.max - b.summary.nc.min > 1e-3,
        "the following error shows"
    );
    assert!(b.notes[0].contains("NC trace trace.csv"));
    assert!(b.verdict.is_some());
}

#[test]
fn an_offset_path_shifts_the_budget_by_its_offset() {
    // A stock allowance δ on the CL path (every tip moved δ along N(u,1)) leaves δ more material:
    // the CAM term shifts by δ (to within the cosine between N(u,1) and the envelope's contact
    // normal), the design term not at all; and when the measured part carries the same shift,
    // machine, tool and residual do not move.
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let delta = 0.01;
    let cl0 = flank_path(&part, 0.5, "cl0");
    let cl1 = flank_path_with_allowance(&part, 0.5, delta, "cl1");
    let design = builtin_design(Mode::Physical, Branch::Signed, false).unwrap();
    let defect = simulate_deviation(&design, &[("EA0B".parse().unwrap(), 1e-4)], 0.0, 0).unwrap();
    let h0 = path_deviation(&cl0, &pts, TOOL_RADIUS).unwrap();
    let d0: Vec<f64> = h0.iter().map(|h| h.deviation).collect();
    // First order: the cylinder moved by v = δ·N(u,1) ⊥ its axis moves the entry of the line
    // P + tN by (v·n_M)/(N·n_M), n_M the tool's radial normal at the entry point.
    let expected: Vec<f64> = pts
        .iter()
        .zip(&h0)
        .map(|(p, h)| {
            let v3 = |a: [f64; 3]| nalgebra::Vector3::new(a[0], a[1], a[2]);
            let (e, w) = (v3(cl0.tips[h.index]), v3(cl0.axes[h.index]));
            let v = v3(cl1.tips[h.index]) - e;
            let m = p.point + p.normal * h.deviation;
            let r = (m - e) - w * (m - e).dot(&w);
            v.dot(&r) / p.normal.dot(&r)
        })
        .collect();
    let d1: Vec<f64> = path_deviation(&cl1, &pts, TOOL_RADIUS)
        .unwrap()
        .iter()
        .map(|h| h.deviation)
        .collect();
    let m0: Vec<f64> = d0.iter().zip(&defect).map(|(a, b)| a + b).collect();
    let m1: Vec<f64> = d1.iter().zip(&defect).map(|(a, b)| a + b).collect();
    // One session for the three budgets (the same settings).
    let session = Session::new(&options(false).analysis).unwrap();
    let b0 = error_budget(
        &session,
        cmm_file(&pts, &m0).as_bytes(),
        "m0.csv",
        &cl0,
        None,
        &options(false),
    )
    .unwrap();
    let b1 = error_budget(
        &session,
        cmm_file(&pts, &m0).as_bytes(),
        "m0.csv",
        &cl1,
        None,
        &options(false),
    )
    .unwrap();
    let b2 = error_budget(
        &session,
        cmm_file(&pts, &m1).as_bytes(),
        "m1.csv",
        &cl1,
        None,
        &options(false),
    )
    .unwrap();
    let (mut worst, mut cosine): (f64, f64) = (0.0, 0.0);
    for (((p0, p1), p2), x) in b0
        .points
        .iter()
        .zip(&b1.points)
        .zip(&b2.points)
        .zip(&expected)
    {
        assert_eq!(p0.design, p1.design);
        worst = worst.max((p1.cam - p0.cam - x).abs());
        cosine = cosine.max((p1.cam - p0.cam - delta).abs());
        // same measurement, shifted path: the shift goes into machine + tool + residual (the
        // final identification may fit it as a tool-radius effect, which is the tool's term)
        let moved = (p1.machine + p1.tool + p1.residual) - (p0.machine + p0.tool + p0.residual);
        assert!((moved + (p1.cam - p0.cam)).abs() < 1e-12);
        // shifted measurement too: nothing but the CAM term moves
        assert!((p2.machine - p0.machine).abs() < 1e-9 && (p2.residual - p0.residual).abs() < 1e-9);
    }
    println!("offset {delta} mm: max |CAM shift - first-order shift| = {worst:.3e} mm; max |CAM shift - offset| = {cosine:.3e} mm (N(u,1) vs the point's normal)");
    assert!(worst <= 1e-7, "{worst}");
    assert!(cosine <= 5e-3 * delta, "{cosine}");
}
