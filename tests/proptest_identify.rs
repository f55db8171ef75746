//! Property test: the whole analysis recovers random location-error vectors from noiseless
//! simulated parts (issue 9). A random vector of machine-like size (±3e-4 rad, ±0.03 mm for
//! EX0B) → the exact eq. 12 deviations at the 100 built-in points (`simulate_exact`, σ = 0) →
//! a CMM file (positions, normals, deviations at full precision) → `analysis::analyse` (reader,
//! projection, design, identification, exact-model refinement). Physical mode: every parameter
//! is identified and recovered. Paper mode (rank 6 of 8): the separable parameters are
//! recovered and every estimable combination of a not-separable group has the value of the same
//! combination of the truth. (Noiseless linear data: tests/identify_properties.rs.)
#![cfg(not(target_arch = "wasm32"))]

mod edge_common;

use edge_common::*;
use proptest::prelude::*;
use testpiece::analysis::{analyse, AnalysisOptions};
use testpiece::identify::Status;
use testpiece::sensitivity::Mode;
use testpiece::simulate::simulate_exact;

const NAMES: [&str; 8] = [
    "EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B",
];

fn xi_strategy() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-1.0f64..1.0, 8).prop_map(|u| {
        u.iter()
            .enumerate()
            .map(|(j, v)| if j == 5 { 0.03 * v } else { 3e-4 * v })
            .collect()
    })
}

proptest! {
    // Each case is a full analysis with LM on the exact model (~1 s in the debug build).
    #![proptest_config(ProptestConfig::with_cases(6))]
    #[test]
    fn noiseless_simulated_parts_are_recovered(x in xi_strategy(), paper in any::<bool>()) {
        let mode = if paper { "paper" } else { "physical" };
        let errors: Vec<(String, f64)> =
            NAMES.iter().zip(&x).map(|(n, v)| (n.to_string(), *v)).collect();
        let y = simulate_exact(mode, "signed", &errors, 0.0, 0).unwrap();
        let text = csv_of(&builtin(), &y);
        let opts = AnalysisOptions {
            mode: if paper { Mode::Paper } else { Mode::Physical },
            ..Default::default()
        };
        let a = analyse(text.as_bytes(), "sim.csv", &opts).unwrap();
        let id = &a.identification;
        let names = id.names();
        let values = id.values();
        // Tolerance: 1e-6 of the vector's size (rad; mm for EX0B 1e-6 x 0.03/3e-4 larger):
        // LM on the exact model stops at its xtol, far below any machine error.
        let tol = |j: usize| if j == 5 { 1e-7 } else { 1e-9 };
        for (j, p) in id.parameters.0.iter().enumerate() {
            prop_assert_eq!(&p.name, NAMES[j]);
            if p.status != Status::NotSeparable {
                prop_assert!((p.value - x[j]).abs() < tol(j), "{} {}: {} vs {}", mode, p.name, p.value, x[j]);
            }
        }
        if paper {
            prop_assert!(id.rank_used < 8);
        } else {
            prop_assert!(id.parameters.0.iter().all(|p| p.status != Status::NotSeparable));
        }
        for g in &id.groups {
            for e in &g.estimable {
                let want = e.combination.apply(&names, &x);
                let got = e.combination.apply(&names, &values);
                prop_assert!((got - want).abs() < 1e-9, "{}: {} vs {}", mode, got, want);
            }
        }
    }
}
