//! Native/wasm parity data (tests/data/parity/), shared by the native test `it/edge_parity.rs`
//! and the wasm test `wasm_node/parity.rs` (both include it with `#[path]`).
//!
//! Approach: the native build writes its results with full precision (serde_json writes the
//! shortest decimal that round-trips each f64, so the file holds the exact native doubles) to
//! `tests/data/parity/*.json` (`TESTPIECE_WRITE_PARITY=1 cargo test --test it edge_parity::`); the
//! native test checks the committed file still equals what the native build computes, and the
//! wasm test recomputes the same results under Node and compares them with [`compare`].
#![allow(dead_code)]

use serde_json::Value;

/// Relative tolerance of the results between native and wasm (issue 9): the design, the
/// matched points, the identified parameters (values, std, covariance, singular values,
/// condition, groups), the refined values and std, the verdict ([`STRICT`]).
pub const PARITY_REL: f64 = 1e-12;

/// The parts of the serialised `Analysis` held to [`PARITY_REL`] (JSON pointers).
pub const STRICT: [&str; 17] = [
    "/baseline/design",
    "/baseline/identification/parameters",
    "/baseline/refinement/values",
    "/correction/effects_included",
    "/design",
    "/points",
    "/settings",
    "/version",
    "/identification/parameters",
    "/identification/singular_values",
    "/identification/condition",
    "/identification/covariance",
    "/identification/groups",
    "/refinement/values",
    "/refinement/std",
    "/refinement/covariance",
    "/diagnosis/report/verdict",
];

/// Tolerance of a final answer refined by Levenberg-Marquardt on a generalised least squares
/// (basis `structure`, `gap::correct`): REML's golden section on the structure's amplitude stops
/// on its own tolerance and LM on its cost tolerance (`Converged { ftol }`), where the values are
/// flat to about 1e-8 relative, and the ulp differences of sin/cos between glibc and the wasm
/// libm can change the number of iterations (12 vs 13). Measured: at most 5e-8 relative (EB0C on
/// paper 002's tilting table, the backlash example, with the white σ of the smooth-basis
/// residual); 1.9e-7 since issue 29 (the same part, white σ from the ruling pairs: the
/// refinement's covariance [1][7], formed by cancellation, and the shift of EA0C 1.4e-7). The
/// baseline of the same part stays within [`PARITY_REL`].
pub const LM_FTOL_REL: f64 = 3e-7;

/// Tolerance of everything else, relative, with an absolute floor of [`LOOSE_ABS`]:
/// statistics formed by cancellation (residuals ≈ 1e-5 mm of deviations ≈ 1e-2 mm,
/// linearisation error, shrink, F, χ² p-values) carry the ≤ 1-ulp differences of sin, cos,
/// atan2 between glibc (native) and Rust's libm port (wasm32), amplified ~1e3; measured at most
/// 2.2e-10 relative (absolute ≤ 2e-12). Since issue 30 the servo candidates' columns are central
/// differences of the inverse kinematics in `u` (step 2.5e-4, the second difference divided by
/// its square: `sensitivity::servo`), which amplify the same ulp differences further: measured
/// 1.3e-9 relative on a candidate's statistics (the clean example's `cv_shrink`).
pub const LOOSE_REL: f64 = 5e-9;
pub const LOOSE_ABS: f64 = 1e-15;

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

/// Largest relative difference `|a-b| / max(|a|,|b|)` over the numbers of two JSON trees of the
/// same shape (values of other kinds and shapes are left to [`compare`]).
pub fn max_rel(a: &Value, b: &Value) -> f64 {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap_or(0.0), y.as_f64().unwrap_or(0.0));
            let m = x.abs().max(y.abs());
            if m == 0.0 {
                0.0
            } else {
                (x - y).abs() / m
            }
        }
        (Value::Array(x), Value::Array(y)) => x
            .iter()
            .zip(y)
            .map(|(p, q)| max_rel(p, q))
            .fold(0.0, f64::max),
        (Value::Object(x), Value::Object(y)) => x
            .iter()
            .filter_map(|(k, p)| y.get(k).map(|q| max_rel(p, q)))
            .fold(0.0, f64::max),
        _ => 0.0,
    }
}

/// Differences between two JSON trees: numbers beyond `rel` relative (`|a-b| <= rel·max(|a|,|b|)`),
/// any other value not equal, keys or lengths that differ. Empty when they agree.
pub fn compare(a: &Value, b: &Value, rel: f64) -> Vec<String> {
    compare_abs(a, b, rel, 0.0)
}

/// Differences between two covariance matrices (arrays of rows) beyond `rel` of the scale of
/// each entry, `|a_ij − b_ij| <= rel·√(a_ii·a_jj)`: an entry near zero is formed by cancellation
/// of terms of that scale (since issue 29 the covariance holds the model spread's second moment,
/// `Σ_c w_c d_c d_cᵀ`, differences of fits), so its own magnitude is no measure of its error.
pub fn compare_covariance(a: &Value, b: &Value, rel: f64) -> Vec<String> {
    let m = |v: &Value| -> Option<Vec<Vec<f64>>> {
        v.as_array()?
            .iter()
            .map(|r| r.as_array()?.iter().map(Value::as_f64).collect())
            .collect()
    };
    let (Some(x), Some(y)) = (m(a), m(b)) else {
        return compare(a, b, rel);
    };
    if x.len() != y.len() || x.iter().zip(&y).any(|(p, q)| p.len() != q.len()) {
        return compare(a, b, rel);
    }
    let mut out = Vec::new();
    for i in 0..x.len() {
        for j in 0..x[i].len().min(x.len()) {
            let scale = (x[i][i].abs() * x[j][j].abs()).sqrt();
            if (x[i][j] - y[i][j]).abs() > rel * scale {
                out.push(format!(
                    "$[{i}][{j}]: {:e} vs {:e} (scale {scale:e})",
                    x[i][j], y[i][j]
                ));
            }
        }
    }
    out
}

/// [`compare`] with an absolute floor: `|a-b| <= rel·max(|a|,|b|) + abs`.
pub fn compare_abs(a: &Value, b: &Value, rel: f64, abs: f64) -> Vec<String> {
    let mut out = Vec::new();
    walk(a, b, rel, abs, "$", &mut out);
    out
}

fn walk(a: &Value, b: &Value, rel: f64, abs: f64, path: &str, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (
                x.as_f64().unwrap_or(f64::NAN),
                y.as_f64().unwrap_or(f64::NAN),
            );
            let within = (x - y).abs() <= rel * x.abs().max(y.abs()) + abs;
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
                walk(p, q, rel, abs, &format!("{path}[{k}]"), out);
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            for (k, p) in x {
                match y.get(k) {
                    Some(q) => walk(p, q, rel, abs, &format!("{path}.{k}"), out),
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

/// A 600-point scan with a 10 µm wave along u (2 surfaces × 60 rulings × 5 heights, 1.5 µm
/// noise, seed 5): `unexplained`, so its final answer is the GLS with the structure taken on
/// groups along the path (above 400 points: `gap::structure::CovarianceForm::Grouped`).
pub fn structured_scan() -> String {
    use testpiece::cmm::write::{canonical_csv, Precision};
    use testpiece::part::{Curve, MeasurementPoint, SShape};
    let part = SShape::iso();
    let mut rng = testpiece::numerics::random::Sampler::new(5);
    let mut pts = Vec::new();
    let mut id = 1;
    for (low, high) in [(Curve::AZ11, Curve::AZ25), (Curve::BZ11, Curve::BZ25)] {
        for i in 0..60 {
            let u = 0.05 + 0.9 * i as f64 / 59.0;
            for k in 0..5 {
                let z = 6.0 + 6.0 * k as f64;
                let c = if z < 18.0 { low } else { high };
                pts.push(MeasurementPoint::at(&part, id, c, u, z / 30.0));
                id += 1;
            }
        }
    }
    let rows: Vec<_> = pts
        .iter()
        .map(|p| (p, 0.010 * (22.0 * p.u).sin() + 0.0015 * rng.normal()))
        .collect();
    canonical_csv(rows, Precision::Decimals(5), None)
}

/// What the parity of [`structured_scan`] compares: the structure's estimate and the final
/// parameters (a whole 600-point analysis would be a megabyte of snapshot).
pub fn structured_summary(a: &testpiece::analysis::Analysis) -> Value {
    serde_json::json!({
        "basis": a.correction.basis,
        "structure": a.correction.structure,
        "parameters": a.identification.parameters,
        "residual": a.identification.residual,
    })
}
