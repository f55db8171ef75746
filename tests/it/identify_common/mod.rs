//! Readers for the reference vectors used by the identification tests (tests/data/reference/,
//! produced by the independent implementation described in its README.md).
#![allow(dead_code)]

use std::collections::BTreeMap;

use testpiece::identify::{Design, Observations};

pub fn reference(path: &str) -> String {
    let full = format!("{}/tests/data/reference/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"))
}

/// A CSV as (header, rows of text fields).
pub fn csv(path: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let text = reference(path);
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(|s| s.trim().to_string())
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|s| s.trim().to_string()).collect())
        .collect();
    (header, rows)
}

/// Column of a CSV by name, as numbers.
pub fn column(path: &str, name: &str) -> Vec<f64> {
    let (h, rows) = csv(path);
    let j = h
        .iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("{path}: no column {name}"));
    rows.iter().map(|r| r[j].parse().unwrap()).collect()
}

/// The 100 x 8 design of `sensitivity_<mode>.csv` (mode = physical | paper).
pub fn design(mode: &str) -> Design {
    let path = format!("sensitivity_{mode}.csv");
    let (h, rows) = csv(&path);
    let names: Vec<&str> = h[2..].iter().map(String::as_str).collect();
    let n = rows.len();
    let mut data = Vec::with_capacity(n * names.len());
    for j in 0..names.len() {
        for r in &rows {
            data.push(r[j + 2].parse::<f64>().unwrap());
        }
    }
    Design::from_column_major(&names, n, &data).unwrap()
}

/// Observations (id, curve, deviation column) of a reference CSV.
pub fn observations(path: &str, deviation_column: &str) -> Observations {
    let (h, rows) = csv(path);
    let jd = h.iter().position(|c| c == deviation_column).unwrap();
    Observations::new(
        rows.iter().map(|r| r[0].clone()).collect(),
        rows.iter().map(|r| r[1].clone()).collect(),
        rows.iter().map(|r| r[jd].parse().unwrap()).collect(),
    )
}

/// `xi_true` of an example's key file, plus the effect parameters.
pub fn key_truth(example: &str) -> BTreeMap<String, f64> {
    let v: serde_json::Value =
        serde_json::from_str(&reference(&format!("examples/{example}.key.json"))).unwrap();
    let mut out = BTreeMap::new();
    for (k, x) in v["xi_true"].as_object().unwrap() {
        out.insert(k.clone(), x.as_f64().unwrap());
    }
    if let Some(p) = v["effect"]["params"].as_object() {
        for (k, x) in p {
            out.insert(k.clone(), x.as_f64().unwrap());
        }
    }
    out
}

/// Typical-size random error vectors of paper 000's eight location errors, in the design's order
/// (±3e-4 rad, ±0.03 mm for EX0B, as the examples' README).
pub fn xi_strategy() -> impl proptest::strategy::Strategy<Value = Vec<f64>> {
    use proptest::prelude::*;
    prop::collection::vec(-1.0f64..1.0, 8).prop_map(|u| {
        u.iter()
            .enumerate()
            .map(|(j, v)| if j == 5 { 0.03 * v } else { 3e-4 * v })
            .collect()
    })
}

/// `(name, value)` pairs as tests write them, read into parameter ids (the text that comes in).
pub fn ids<S: AsRef<str>>(named: &[(S, f64)]) -> Vec<(testpiece::parameter::ParamId, f64)> {
    named
        .iter()
        .map(|(n, v)| (n.as_ref().parse().unwrap(), *v))
        .collect()
}
