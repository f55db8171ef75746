//! Native/wasm parity data (tests/data/parity/), shared by the native test `edge_parity.rs`
//! and the wasm test `wasm_node/parity.rs` (included there with `#[path]`).
//!
//! Approach: the native build writes its results with full precision (serde_json writes the
//! shortest decimal that round-trips each f64, so the file holds the exact native doubles) to
//! `tests/data/parity/*.json` (`TESTPIECE_WRITE_PARITY=1 cargo test --test edge_parity`); the
//! native test checks the committed file still equals what the native build computes, and the
//! wasm test recomputes the same results under Node and compares them with [`compare`].
#![allow(dead_code)]

use serde_json::Value;

/// Relative tolerance of numbers between native and wasm (issue 9).
pub const PARITY_REL: f64 = 1e-12;

/// The three example files of the page (tests/data/reference/examples/).
pub const EXAMPLES: [&str; 3] = [
    "example_clean.csv",
    "example_tool_radius.csv",
    "example_backlash_c.csv",
];

/// The serialised `Analysis` compared between native and wasm: everything but `file` (the
/// reader's echo of the rows; its numbers, the matched `u, v`, foot and normal, are in
/// `points`), to keep the committed file small.
pub fn analysis_value(a: &testpiece::analysis::Analysis) -> Value {
    let mut v = serde_json::to_value(a).expect("an analysis serialises");
    if let Value::Object(m) = &mut v {
        m.remove("file");
    }
    v
}

/// Differences between two JSON trees: numbers beyond `rel` relative (`|a-b| <= rel·max(|a|,|b|)`),
/// any other value not equal, keys or lengths that differ. Empty when they agree.
pub fn compare(a: &Value, b: &Value, rel: f64) -> Vec<String> {
    let mut out = Vec::new();
    walk(a, b, rel, "$", &mut out);
    out
}

fn walk(a: &Value, b: &Value, rel: f64, path: &str, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (
                x.as_f64().unwrap_or(f64::NAN),
                y.as_f64().unwrap_or(f64::NAN),
            );
            let within = (x - y).abs() <= rel * x.abs().max(y.abs());
            if !within {
                out.push(format!("{path}: {x:e} vs {y:e}"));
            }
        }
        (Value::Array(x), Value::Array(y)) => {
            if x.len() != y.len() {
                out.push(format!("{path}: {} vs {} items", x.len(), y.len()));
                return;
            }
            for (k, (p, q)) in x.iter().zip(y).enumerate() {
                walk(p, q, rel, &format!("{path}[{k}]"), out);
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            for (k, p) in x {
                match y.get(k) {
                    Some(q) => walk(p, q, rel, &format!("{path}.{k}"), out),
                    None => out.push(format!("{path}.{k}: missing on the right")),
                }
            }
            for k in y.keys().filter(|k| !x.contains_key(*k)) {
                out.push(format!("{path}.{k}: missing on the left"));
            }
        }
        _ => {
            if a != b {
                out.push(format!("{path}: {a} vs {b}"));
            }
        }
    }
}
