//! Property test: the whole analysis recovers random location-error vectors from noiseless
//! simulated parts (issue 9). A random vector of machine-like size (±3e-4 rad, ±0.03 mm for
//! EX0B) → the exact eq. 12 deviations at the 100 built-in points (`simulate_exact`, σ = 0) →
//! a CMM file (positions, normals, deviations at full precision) → `analysis::analyse` (reader,
//! projection, design, identification, exact-model refinement). Physical mode: every parameter
//! is identified and recovered; paper mode (rank 6): the estimable combinations are recovered and
//! the other parameters within the truncation bias described in the test. (Noiseless linear data: tests/it/identify_properties.rs.)

use crate::edge_common::*;
use crate::identify_common::xi_strategy;
use proptest::prelude::*;
use testpiece::analysis::{analyse_once, AnalysisOptions};
use testpiece::final_fit::correct::EffectsChoice;
use testpiece::identify::Status;
use testpiece::sensitivity::Mode;
use testpiece::simulate::simulate_exact;

const NAMES: [&str; 8] = [
    "EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B",
];

proptest! {
    // Each case is a full analysis with LM on the exact model (~1 s in the debug build).
    #![proptest_config(ProptestConfig::with_cases(6))]
    #[test]
    fn noiseless_simulated_parts_are_recovered(x in xi_strategy()) {
      for paper in [false, true] {
        let mode = if paper { Mode::Paper } else { Mode::Physical };
        let errors: Vec<(testpiece::parameter::ParamId, f64)> =
            NAMES.iter().zip(&x).map(|(n, v)| (n.parse().unwrap(), *v)).collect();
        let y = simulate_exact(mode, testpiece::machine::Branch::Signed, &errors, 0.0, 0).unwrap();
        let text = csv_of(&builtin(), &y);
        // The baseline identification (`--effects none`): a noiseless part is no test of the
        // gap diagnosis (σ ≈ 0 makes the exact model's second-order terms "structure"), and
        // the property checked here is the least-squares recovery of the location errors.
        let opts = AnalysisOptions {
            mode,
            effects: EffectsChoice::None,
            ..Default::default()
        };
        let a = analyse_once(text.as_bytes(), "sim.csv", &opts).unwrap();
        let id = &a.identification;
        let names = id.names();
        let values = id.values();
        // Tolerance, in typical magnitudes (1e-4 rad, 0.01 mm: paper 000 Figure 19's units).
        // Physical mode (full rank, LM on the exact model down to its xtol): 1e-5 of the
        // typical size. Paper mode (rank 6): the two squareness directions `EB0C + 0.99 EB0Z`
        // and `EA0C + 0.96 EA0Z` are nearly, not exactly, null (condition index 323 and 147);
        // the product fixes them by the minimum-norm convention within the not-separable set
        // (parameters with ≥ 10 % of their unit vector in the unresolved subspace). The truth's
        // component along such a direction `v` is then missing from the solution, and so is its
        // share `v_j` on the parameters outside the set: a truncation bias proportional to the
        // size of the squareness errors. Measured over 30 random vectors (PROPTEST_CASES=30):
        // bias / (largest component of the vector, typical units) at most 0.243 (EX0B), 0.058
        // (EC0Y), 0.050 (EC0B), 0.035 (EA0B). Bound asserted: 0.3 of the vector's size plus the
        // 1e-3 of the exact model's second-order terms. (A known limit of paper mode, reported in
        // the issue-9 note: these parameters are listed as identified although a part of their
        // value is the convention's.) The estimable combinations carry no truncation bias:
        // 3e-5 in both modes.
        let typical = |j: usize| if j == 5 { 0.01 } else { 1e-4 };
        let size = (0..8).map(|j| x[j].abs() / typical(j)).fold(0.0, f64::max);
        let k = if paper { 1e-3 + 0.3 * size } else { 1e-5 };
        for (j, p) in id.parameters.0.iter().enumerate() {
            prop_assert_eq!(&p.name(), NAMES[j]);
            if p.status != Status::NotSeparable {
                let bias = (p.value - x[j]).abs() / typical(j);
                prop_assert!(bias < k, "{} {}: {} vs {}", mode.name(), p.name(), p.value, x[j]);
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
                prop_assert!((got - want).abs() < 1e-3 * 0.03, "{}: {} vs {}", mode.name(), got, want);
            }
        }
      }
    }
}
