//! Shared helpers of the edge-case tests: CMM files written from the built-in points.
#![allow(dead_code)]

use testpiece::cmm::write::{canonical_csv, Precision};
use testpiece::part::{builtin_points, MeasurementPoint, SShape};

/// A CMM file (`id,curve,x,y,z,nx,ny,nz,deviation`, mm) of `points` with `deviation[i]`, every
/// number written with Rust's shortest round-trip form (no rounding).
pub fn csv_of(points: &[MeasurementPoint], deviation: &[f64]) -> String {
    canonical_csv(
        points.iter().zip(deviation.iter().copied()),
        Precision::Shortest,
        None,
    )
}

/// The 100 built-in points of the ISO S-shape.
pub fn builtin() -> Vec<MeasurementPoint> {
    builtin_points(&SShape::iso())
}

/// A repository file's bytes.
pub fn data(path: &str) -> Vec<u8> {
    let full = format!("{}/tests/data/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read(&full).unwrap_or_else(|e| panic!("{full}: {e}"))
}

/// Typical location errors (rad; mm for EX0B), the size of the examples' README.
pub const TYPICAL: [(&str, f64); 8] = [
    ("EC0Y", 1.2e-4),
    ("EA0Z", -0.8e-4),
    ("EB0Z", 1.5e-4),
    ("EA0C", -1.0e-4),
    ("EB0C", 0.6e-4),
    ("EX0B", 0.02),
    ("EA0B", -1.1e-4),
    ("EC0B", 0.9e-4),
];

/// `TYPICAL` scaled by `k`, as `(name, value)` pairs.
pub fn typical(k: f64) -> Vec<(testpiece::parameter::ParamId, f64)> {
    TYPICAL
        .iter()
        .map(|(n, v)| (n.parse().unwrap(), v * k))
        .collect()
}
