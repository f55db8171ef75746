//! `testpiece simulate` and `testpiece identify` end to end (cli.md), on the reference examples.
#![cfg(not(target_arch = "wasm32"))]

mod identify_common;

use identify_common::*;
mod cli_common;

use cli_common::testpiece;

fn example(name: &str) -> String {
    format!(
        "{}/tests/data/reference/examples/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// `identify --json` on example_clean.csv: the cli.md fields, every key value within 3 std.
#[test]
fn identify_json_example_clean() {
    let (ok, out, err) = testpiece(&["identify", &example("example_clean.csv"), "--json"]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let key = key_truth("example_clean");
    assert_eq!(v["points_used"], 100);
    assert_eq!(v["rank"], 8);
    assert!(v["points_excluded"].as_array().unwrap().is_empty());
    for (name, truth) in &key {
        let p = &v["parameters"][name];
        let z = (p["value"].as_f64().unwrap() - truth) / p["std"].as_f64().unwrap();
        assert!(z.abs() <= 3.0, "{name}: z = {z}");
    }
    assert!(v["groups"]
        .as_array()
        .unwrap()
        .iter()
        .any(|g| g["kind"] == "weak"));
}

/// `identify --tool-radius --json` on example_tool_radius.csv: dR = 0.015 within 3 std.
#[test]
fn identify_json_example_tool_radius() {
    let (ok, out, err) = testpiece(&[
        "identify",
        &example("example_tool_radius.csv"),
        "--tool-radius",
        "--json",
    ]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for (name, truth) in &key_truth("example_tool_radius") {
        let p = &v["parameters"][name];
        let z = (p["value"].as_f64().unwrap() - truth) / p["std"].as_f64().unwrap();
        assert!(z.abs() <= 3.0, "{name}: z = {z}");
    }
}

/// simulate -> identify round trip in paper mode: Table 4's values with a tool 0.02 mm smaller
/// give the simulated range -0.1709..0.2048 mm (table4_paper.csv; the paper measured
/// -0.18..0.21) and are identified back with dR, EA0Z/EA0C and EB0Z/EB0C grouped.
#[test]
fn simulate_table4_and_identify_back() {
    let (ok, csv, err) = testpiece(&[
        "simulate",
        "--mode",
        "paper",
        "--errors",
        "EX0B=0.0294,EA0B=3.2419e-4,dR=-0.02",
    ]);
    assert!(ok, "{err}");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "id,curve,x,y,z,nx,ny,nz,deviation");
    assert_eq!(lines.len(), 101);
    let dev: Vec<f64> = lines[1..]
        .iter()
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect();
    let reference = column("table4_paper.csv", "deviation");
    for (a, b) in dev.iter().zip(&reference) {
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
    }
    let path = std::env::temp_dir().join(format!("identify_cli_table4_{}.csv", std::process::id()));
    std::fs::write(&path, &csv).unwrap();
    let (ok, out, err) = testpiece(&[
        "identify",
        path.to_str().unwrap(),
        "--mode",
        "paper",
        "--tool-radius",
        "--json",
    ]);
    let _ = std::fs::remove_file(&path);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let val = |n: &str| v["parameters"][n]["value"].as_f64().unwrap();
    assert!((val("EX0B") - 0.0294).abs() < 1e-6);
    assert!((val("EA0B") - 3.2419e-4).abs() < 1e-8);
    assert!((val("dR") + 0.02).abs() < 1e-6);
    let groups = v["groups"].as_array().unwrap();
    assert_eq!(
        groups
            .iter()
            .filter(|g| g["kind"] == "not_separable")
            .count(),
        2
    );
}

/// Errors: non-zero exit with a specific message, never a panic.
#[test]
fn cli_errors() {
    let (ok, _, err) = testpiece(&["identify", "/nonexistent/part.csv"]);
    assert!(!ok && err.contains("/nonexistent/part.csv"), "{err}");
    let (ok, _, err) = testpiece(&["simulate", "--errors", "EQ0Z=1"]);
    assert!(!ok && err.contains("unknown error `EQ0Z`"), "{err}");
    let (ok, _, err) = testpiece(&["simulate", "--errors", "EX0B=0.01", "--mode", "fancy"]);
    assert!(!ok && err.contains("--mode `fancy`"), "{err}");
    let (ok, _, err) = testpiece(&["identify", &example("example_clean.csv"), "--export", "xml"]);
    assert!(!ok && err.contains("--export `xml`"), "{err}");
}
