//! Native side of the native/wasm parity (issue 9) and determinism for a given seed.
//!
//! - `tests/data/parity/broken_messages.json`: the reader's message for every file of
//!   tests/data/cmm/broken (read_and_match, default options); tests/wasm_node/cmm_broken.rs
//!   feeds each file through the wasm export `analyse` and expects the same message.
//! - `tests/data/parity/analysis_examples.json`: `analysis::analyse` of the three examples (the
//!   page's default settings), every double at full precision; tests/wasm_node/parity.rs
//!   recomputes them in wasm and compares to 1e-12 relative.
//! - `tests/data/parity/analysis_paper002.json`: the backlash example on paper 002's tilting
//!   table (rank 6 of 8: not-separable parameters), compared the same way.
//!
//! Rewrite both files after a deliberate change of the results with
//! `TESTPIECE_WRITE_PARITY=1 cargo test --test it edge_parity::`; otherwise this test fails when
//! the native results no longer match them (so the wasm comparison is always against the
//! current native numbers).

use std::collections::BTreeMap;
use std::path::PathBuf;
use testpiece::machine::Branch;
use testpiece::parameter::ParamId;
use testpiece::sensitivity::Mode;

use crate::parity_common::*;
use serde_json::Value;
use testpiece::analysis::{analyse_once, AnalysisOptions};
use testpiece::cmm::{read_and_match, ReadOptions};
use testpiece::identify::monte_carlo::{monte_carlo, MonteCarloOptions, Noise};
use testpiece::identify::{identify, IdentifyOptions, Observations};
use testpiece::settings::MachineChoice;
use testpiece::simulate::{builtin_design, simulate_deviation, simulate_exact};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn write_mode() -> bool {
    std::env::var("TESTPIECE_WRITE_PARITY").is_ok_and(|v| v == "1")
}

/// Writes `value` (write mode) or checks the committed file against it.
fn check_or_write(name: &str, value: &Value) {
    let path = root().join("tests/data/parity").join(name);
    if write_mode() {
        std::fs::write(&path, serde_json::to_string(value).unwrap() + "\n").unwrap();
        return;
    }
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let committed: Value = serde_json::from_str(&text).unwrap();
    // 1e-15: serde_json parses decimals to within an ulp (no float_roundtrip feature).
    let diff = compare(&committed, value, 1e-15);
    assert!(
        diff.is_empty(),
        "{name} differs from the native results (rewrite with TESTPIECE_WRITE_PARITY=1 if intended): {:?}",
        &diff[..diff.len().min(10)]
    );
}

fn broken_files() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(root().join("tests/data/cmm/broken"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    v.sort();
    v
}

#[test]
fn broken_file_messages() {
    let mut m = BTreeMap::new();
    for name in broken_files() {
        let bytes = std::fs::read(root().join("tests/data/cmm/broken").join(&name)).unwrap();
        let e = read_and_match(&bytes, &name, &ReadOptions::default())
            .expect_err(&format!("{name} is read without error"));
        m.insert(name, e.to_string());
    }
    check_or_write("broken_messages.json", &serde_json::to_value(&m).unwrap());
    // The wasm test lists the files by name (include_bytes! needs literals): all of them.
    let wasm = std::fs::read_to_string(root().join("tests/wasm_node/cmm_broken.rs")).unwrap();
    for name in broken_files() {
        assert!(
            wasm.contains(&format!("\"{name}\"")),
            "tests/wasm_node/cmm_broken.rs does not list {name}"
        );
    }
}

fn examples_value() -> Value {
    let mut m = serde_json::Map::new();
    for name in EXAMPLES {
        let bytes = std::fs::read(root().join("tests/data/reference/examples").join(name)).unwrap();
        let a = analyse_once(&bytes, name, &AnalysisOptions::default()).unwrap();
        m.insert(name.to_string(), analysis_value(&a));
    }
    Value::Object(m)
}

#[test]
fn analysis_of_the_examples() {
    check_or_write("analysis_examples.json", &examples_value());
}

/// The backlash example on paper 002's tilting table. Its set is derived from what the part sees
/// (`sensitivity::error_set`): the eight errors EC0Y, EA0Z, EB0Z, EA0C, EX0B, EC0B, EY0C, EZ0B,
/// all separable (before issue 20 it was paper 000's eight, of rank 6, two fixed by the
/// minimum-norm rule); wasm must give the same values (tests/wasm_node/parity.rs).
#[test]
fn analysis_on_the_tilting_table() {
    let name = "example_backlash_c.csv";
    let bytes = std::fs::read(root().join("tests/data/reference/examples").join(name)).unwrap();
    let opts = AnalysisOptions {
        machine: MachineChoice::Paper002,
        ..AnalysisOptions::default()
    };
    let a = analyse_once(&bytes, name, &opts).unwrap();
    let names = a.design.names();
    assert_eq!(
        names,
        ["EC0Y", "EA0Z", "EB0Z", "EA0C", "EX0B", "EC0B", "EY0C", "EZ0B"]
    );
    assert!(
        a.identification
            .parameters
            .0
            .iter()
            .all(|p| p.std.is_some()),
        "every error of the tilting table's set is separable on this part"
    );
    check_or_write("analysis_paper002.json", &analysis_value(&a));
}

/// A 600-point scan with structure: the grouped covariance and the low-rank whitener
/// (`gap::structure`, `identify::correlated::Whitener::LowRank`); wasm compares with this
/// (tests/wasm_node/parity.rs).
#[test]
fn a_structured_scan_of_600_points() {
    let a = analyse_once(
        structured_scan().as_bytes(),
        "scan.csv",
        &AnalysisOptions::default(),
    )
    .unwrap();
    check_or_write("structured_scan.json", &structured_summary(&a));
}

/// The same input gives bit-identical results, run after run: the analysis (no hidden
/// randomness), simulated parts and Monte Carlo for a given seed (ChaCha8, seeded); another
/// seed gives other numbers.
#[test]
fn deterministic_for_a_given_seed() {
    let bytes =
        std::fs::read(root().join("tests/data/reference/examples/example_backlash_c.csv")).unwrap();
    let a =
        serde_json::to_string(&analyse_once(&bytes, "b.csv", &AnalysisOptions::default()).unwrap())
            .unwrap();
    let b =
        serde_json::to_string(&analyse_once(&bytes, "b.csv", &AnalysisOptions::default()).unwrap())
            .unwrap();
    assert_eq!(a, b);

    let errors: Vec<(ParamId, f64)> = vec![
        ("EX0B".parse().unwrap(), 0.02),
        ("EA0B".parse().unwrap(), 1e-4),
    ];
    let d = builtin_design(Mode::Physical, Branch::Signed, false).unwrap();
    let y1 = simulate_deviation(&d, &errors, 0.0015, 42).unwrap();
    assert_eq!(y1, simulate_deviation(&d, &errors, 0.0015, 42).unwrap());
    assert_ne!(y1, simulate_deviation(&d, &errors, 0.0015, 43).unwrap());
    let e1 = simulate_exact(Mode::Physical, Branch::Signed, &errors, 0.0015, 42).unwrap();
    assert_eq!(
        e1,
        simulate_exact(Mode::Physical, Branch::Signed, &errors, 0.0015, 42).unwrap()
    );

    let obs = Observations::plain(y1);
    let truth = d.vector_from(&errors).unwrap();
    let run = |seed| {
        let r = monte_carlo(
            &d,
            &obs,
            &truth,
            &Noise::Gaussian { sigma: 0.0015 },
            &MonteCarloOptions::default().with_runs(20).with_seed(seed),
            &IdentifyOptions::default(),
        )
        .unwrap();
        serde_json::to_string(&r).unwrap()
    };
    assert_eq!(run(7), run(7));
    assert_ne!(run(7), run(8));
    let id = identify(&d, &obs, &IdentifyOptions::default()).unwrap();
    assert_eq!(
        serde_json::to_string(&id).unwrap(),
        serde_json::to_string(&identify(&d, &obs, &IdentifyOptions::default()).unwrap()).unwrap()
    );
}
