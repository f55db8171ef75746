//! Shared by the pooled-identification tests: one machine and its simulated parts.
#![allow(dead_code)]

use testpiece::cmm::write::{canonical_csv, Precision};
use testpiece::machine::Branch;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::Mode;
use testpiece::simulate::simulate_exact;

/// The machine of example_clean.key.json (`xi_true`, rad; EX0B mm).
pub const TRUTH: [(&str, f64); 8] = [
    ("EC0Y", 7.505727996280019e-05),
    ("EA0Z", 0.00023832828058174528),
    ("EB0Z", 0.0001654114141471161),
    ("EA0C", -0.00016487568600564488),
    ("EB0C", -0.00011990022905326473),
    ("EX0B", 0.01782416572512277),
    ("EA0B", -0.00029684081726065513),
    ("EC0B", 0.00019273705102965973),
];
/// σ of the simulated CMM noise (mm).
pub const NOISE: f64 = 0.0015;

/// A canonical CSV part (`id,curve,x,y,z,nx,ny,nz,deviation`, shortest round-trip numbers):
/// exact eq. 12 for `errors` at the 100 built-in points plus N(0, NOISE²) noise with `seed`.
pub fn part_csv(errors: &[(String, f64)], seed: u64) -> String {
    let errors: Vec<(testpiece::parameter::ParamId, f64)> = errors
        .iter()
        .map(|(n, v)| (n.parse().unwrap(), *v))
        .collect();
    let dev = simulate_exact(Mode::Physical, Branch::Signed, &errors, NOISE, seed).unwrap();
    let points = builtin_points(&SShape::iso());
    canonical_csv(points.iter().zip(dev), Precision::Shortest, None)
}
