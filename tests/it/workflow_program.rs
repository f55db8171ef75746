//! The part program (issue 19, step 2) read back by the product itself:
//! - `testpiece budget FILE --cl <the CL of testpiece program>` shows a CAM term within the
//!   program's chord tolerance at every point;
//! - the G-code of every dialect replayed as an NC trace (the budget's trace reader, through the
//!   nominal direct kinematics of the same chain) gives the CL's tool tips within the program's
//!   rounding bound, for the three machines and both B branches.

use crate::cli_common::testpiece_ok;
use testpiece::budget::synthetic::write_trace_csv;
use testpiece::budget::{read_trace, TraceMachine};
use testpiece::machine::description::AngleUnit;
use testpiece::machine::Branch;
use testpiece::program::{program, read_program, Dialect, ProgramOptions};
use testpiece::settings::MachineChoice;
use testpiece::tolerance::GCODE_REPLAY_MM as REPLAY_MM;

fn budget_cam(cl: &str, tolerance: f64) -> (f64, f64) {
    let dir = std::env::temp_dir().join(format!(
        "testpiece-program-{}-{tolerance}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("program.apt");
    std::fs::write(&path, cl).unwrap();
    let root = env!("CARGO_MANIFEST_DIR");
    let measured = format!("{root}/tests/data/budget/example_measured.csv");
    let v: serde_json::Value = serde_json::from_str(&testpiece_ok(&[
        "budget",
        &measured,
        "--cl",
        path.to_str().unwrap(),
        "--json",
    ]))
    .unwrap();
    std::fs::remove_dir_all(&dir).ok();
    (
        v["summary"]["cam"]["min"].as_f64().unwrap(),
        v["summary"]["cam"]["max"].as_f64().unwrap(),
    )
}

/// The CL of `testpiece program` (1 µm, then 5 µm) read by `testpiece budget --cl`: the CAM
/// term (CAM path minus the exact envelope, paper 000 §4.1) lies within ± the tolerance at all
/// 100 points, and the header says what the program is and is not.
#[test]
fn budget_reads_the_cl_with_a_cam_term_within_the_tolerance() {
    for tol in [0.001, 0.005] {
        let cl = testpiece_ok(&["program", "--tolerance", &tol.to_string()]);
        for needed in [
            "ROUGHING NOT INCLUDED",
            "machine: B head / C table",
            "L0 = 499.889 mm",
            "tool: flat end mill, diameter 20 mm",
            "branch: signed",
            &format!("chord tolerance: {tol} mm"),
            "testpiece 0.",
        ] {
            assert!(cl.contains(needed), "CL header lacks `{needed}`");
        }
        let (lo, hi) = budget_cam(&cl, tol);
        assert!(
            lo >= -tol && hi <= tol,
            "CAM term {lo:e}..{hi:e} mm outside ±{tol} mm"
        );
        println!(
            "tolerance {tol} mm: CAM term {:.3}..{:.3} µm",
            lo * 1e3,
            hi * 1e3
        );
    }
}

/// `testpiece program --format gcode` in every dialect, read back block by block
/// ([`read_program`]), its feed blocks of the passes written as a trace CSV and replayed by the
/// budget's trace reader (TCP: the tips read directly): the tips equal the program's CL tips
/// within the program's rounding bound (its words' decimals, `Program::rounding_bound`); the
/// interval errors of every pass are within the tolerance.
#[test]
fn gcode_replayed_as_a_trace_gives_the_cl_tips() {
    for (machine, flag) in [
        (MachineChoice::Paper000, "paper000"),
        (MachineChoice::Paper001, "paper001"),
        (MachineChoice::Paper002, "paper002"),
    ] {
        for (branch, b) in [(Branch::Signed, "signed"), (Branch::Positive, "positive")] {
            let opts = ProgramOptions {
                machine,
                branch,
                ..ProgramOptions::default()
            };
            let p = program(&opts).unwrap();
            for pass in &p.passes {
                assert!(
                    pass.max_interval_error <= opts.tolerance,
                    "{flag} {b}: {}",
                    pass.max_interval_error
                );
                assert!(
                    pass.max_scallop <= opts.tolerance * (1.0 + 1e-9),
                    "{flag} {b}: {}",
                    pass.max_scallop
                );
            }
            for (dialect, tcp) in [
                ("iso", false),
                ("fanuc", false),
                ("linuxcnc", false),
                ("sinumerik", false),
                ("heidenhain", false),
                ("fanuc", true),
                ("sinumerik", true),
                ("heidenhain", true),
            ] {
                if b == "positive" && dialect != "iso" {
                    continue; // the branch changes the values, not the writer
                }
                let mut args = vec![
                    "program",
                    "--format",
                    "gcode",
                    "--machine",
                    flag,
                    "--branch",
                    b,
                    "--dialect",
                    dialect,
                ];
                if tcp {
                    args.push("--tcp");
                }
                let text = testpiece_ok(&args);
                assert!(text.contains("ROUGHING NOT INCLUDED"), "{flag} {dialect}");
                let d = Dialect::parse(dialect).unwrap();
                let p = program(&ProgramOptions {
                    dialect: d,
                    tcp,
                    ..opts.clone()
                })
                .unwrap();
                let chain = opts.chain();
                let blocks = read_program(&text, d, &chain).unwrap();
                // The pass's positions: every feed block but the exits (a feed block followed
                // by a rapid).
                let rows: Vec<_> = blocks
                    .iter()
                    .enumerate()
                    .filter(|(k, x)| !x.rapid && blocks.get(k + 1).is_some_and(|n| !n.rapid))
                    .map(|(_, x)| x.words)
                    .collect();
                let cl = p.tool_path("program");
                assert_eq!(rows.len(), cl.len(), "{flag} {b} {dialect}");
                let tips: Vec<[f64; 3]> = if tcp {
                    rows.iter().map(|q| [q.x, q.y, q.z]).collect()
                } else {
                    let machine = TraceMachine {
                        name: flag.to_string(),
                        chain: chain.clone(),
                        angle_unit: AngleUnit::Deg,
                    };
                    let trace_csv =
                        write_trace_csv(&rows, &machine, 0.008, "replayed G-code", None);
                    read_trace(trace_csv.as_bytes(), "replay.csv", &machine)
                        .unwrap()
                        .tips
                };
                let mut worst = 0.0f64;
                for (t, c) in tips.iter().zip(&cl.tips) {
                    let d = ((t[0] - c[0]).powi(2) + (t[1] - c[1]).powi(2) + (t[2] - c[2]).powi(2))
                        .sqrt();
                    worst = worst.max(d);
                }
                let bound = p.rounding_bound() + REPLAY_MM;
                assert!(
                    worst <= bound,
                    "{flag} {b} {dialect} tcp {tcp}: replayed tips {worst:e} mm from the CL, bound {bound:e}"
                );
                println!(
                    "{flag} {b} {dialect} tcp {tcp}: {} blocks, replayed tips within {worst:.2e} mm (bound {bound:.2e})",
                    rows.len()
                );
            }
        }
    }
}
