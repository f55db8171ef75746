//! The stages of an analysis (issue 31 item 3, progress): reported in order to the caller's sink
//! without changing any result, written by the CLI on a terminal's stderr only: piped, `diagnose`
//! and `identify` write nothing there and their stdout is byte for byte the silent analysis's.

use std::process::Command;

use testpiece::analysis::{
    analyse_parts, analyse_parts_with, AnalysisOptions, Progress, Session, Stage,
};

use crate::cli_common::testpiece;

const CLEAN: &str = include_str!("../data/reference/examples/example_clean.csv");

fn example(name: &str) -> String {
    format!(
        "{}/tests/data/reference/examples/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// Every stage once, in order, and the analysis the same to the byte as without a sink.
#[test]
fn the_stages_are_reported_in_order_and_change_nothing() {
    let opts = AnalysisOptions::default();
    let session = Session::new(&opts).unwrap();
    let files = [(CLEAN.as_bytes(), "example_clean.csv")];
    let mut seen: Vec<Progress> = Vec::new();
    let (with, _) = analyse_parts_with(&session, &files, &opts, &mut |p| seen.push(p)).unwrap();
    let (without, _) = analyse_parts(&Session::new(&opts).unwrap(), &files, &opts).unwrap();
    assert_eq!(
        seen.iter().map(|p| p.stage).collect::<Vec<_>>(),
        Stage::ALL.to_vec()
    );
    assert_eq!(
        serde_json::to_string(&with).unwrap(),
        serde_json::to_string(&without).unwrap()
    );
}

/// Piped: nothing on stderr, no carriage return or escape in the output.
#[test]
fn piped_the_cli_writes_no_stage() {
    for cmd in ["diagnose", "identify"] {
        for json in [false, true] {
            let mut args = vec![cmd, "example_backlash_c.csv"];
            let file = example("example_backlash_c.csv");
            args[1] = &file;
            if json {
                args.push("--json");
            }
            let (ok, out, err) = testpiece(&args);
            assert!(ok, "{args:?}: {err}");
            assert_eq!(err, "", "{args:?}: stderr");
            assert!(!out.contains('\r') && !out.contains('\x1b'), "{args:?}");
        }
    }
}

/// On a terminal (a pseudo-terminal from `script`, when the system has it): the stage line is
/// written, then cleared.
#[test]
fn on_a_terminal_the_cli_shows_the_stages() {
    let bin = env!("CARGO_BIN_EXE_testpiece");
    let file = example("example_clean.csv");
    // stdout to /dev/null, stderr on the pseudo-terminal that `script` records
    let inner = format!("'{bin}' diagnose '{file}' --json > /dev/null");
    let Ok(out) = Command::new("script")
        .args(["-qec", &inner, "/dev/null"])
        .output()
    else {
        return; // no `script`: nothing to check here
    };
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    for k in 1..=6 {
        assert!(text.contains(&format!("stage {k} of 6")), "{text:?}");
    }
    assert!(text.ends_with("\r\x1b[K"), "the line is cleared: {text:?}");
}
