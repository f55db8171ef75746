//! Runs the `testpiece` binary built for the tests (the CLI end-to-end tests share it).
#![allow(dead_code)]

use std::process::Command;

/// `testpiece ARGS`: (success, stdout, stderr).
pub fn testpiece(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_testpiece"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// `testpiece ARGS` that must succeed: its stdout (the stderr is the failure message).
pub fn testpiece_ok(args: &[&str]) -> String {
    let (ok, stdout, stderr) = testpiece(args);
    assert!(ok, "testpiece {args:?} failed: {stderr}");
    stdout
}
