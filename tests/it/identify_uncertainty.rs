//! Uncertainty: Monte Carlo with seeded CMM noise against the linear propagation, the MPE to σ
//! conversion (paper 000 §6), a priori covariance.
#![allow(clippy::needless_range_loop)] // index loops read like the maths here

use crate::identify_common::*;
use testpiece::assert_near;
use testpiece::identify::monte_carlo::*;
use testpiece::identify::*;

/// MPE_E = ±(3 + L/75) µm and R0 = 3 µm (paper 000 §6): σ = max(MPE/√3, R0/1.693).
#[test]
fn mpe_to_sigma() {
    let m = CmmMpe::paper000();
    assert_near!(m.mpe_mm(0.0), 0.003, 1e-15);
    assert_near!(m.mpe_mm(150.0), 0.005, 1e-15);
    // At L = 0 the repeatability dominates: 3/1.693 = 1.772 µm > 3/√3 = 1.732 µm.
    assert_near!(m.sigma_mm(0.0), 0.003 / 1.693, 1e-15);
    assert_near!(m.sigma_mm(150.0), 0.005 / 3f64.sqrt(), 1e-15);
    assert!(CmmMpe::try_new(-1.0, 75.0, 3.0).is_err());
    assert!(CmmMpe::try_new(3.0, 0.0, 3.0).is_err());
}

/// Distances of the 100 built-in points from the part origin (points.csv).
fn lengths() -> Vec<f64> {
    let (x, y, z) = (
        column("points.csv", "x"),
        column("points.csv", "y"),
        column("points.csv", "z"),
    );
    (0..x.len())
        .map(|i| (x[i] * x[i] + y[i] * y[i] + z[i] * z[i]).sqrt())
        .collect()
}

/// With the paper's CMM on the physical design, the Monte Carlo std of every parameter agrees
/// with the linear propagation within 6 % (2000 runs: the sampling error of a std is
/// 1/√(2·2000) = 1.6 %, so 6 % is about 4 of those), and the means are unbiased.
#[test]
fn monte_carlo_matches_propagation_physical() {
    let d = design("physical");
    let obs = observations("examples/example_clean.csv", "deviation");
    let key = key_truth("example_clean");
    let truth: Vec<f64> = d.names().iter().map(|n| key[n]).collect();
    let noise = Noise::from_mpe(&CmmMpe::paper000(), &lengths());
    let mc = MonteCarloOptions::default().with_runs(2000).with_seed(11);
    let r = monte_carlo(&d, &obs, &truth, &noise, &mc, &IdentifyOptions::default()).unwrap();
    assert!(r.sigma_min >= 0.003 / 1.693 - 1e-15 && r.sigma_max <= 0.0045);
    for p in &r.parameters {
        let ratio = p.std_mc / p.std_predicted;
        assert!(
            (ratio - 1.0).abs() < 0.06,
            "{}: MC std {} vs predicted {}",
            p.name,
            p.std_mc,
            p.std_predicted
        );
        let se = p.std_predicted / (2000f64).sqrt();
        assert!(
            (p.mean - p.truth).abs() < 4.0 * se,
            "{}: mean {} truth {}",
            p.name,
            p.mean,
            p.truth
        );
    }
    // Same seed, same numbers (ChaCha8 stream).
    let r2 = monte_carlo(&d, &obs, &truth, &noise, &mc, &IdentifyOptions::default()).unwrap();
    assert_eq!(r, r2);
}

/// Paper mode: the estimable combinations of the not-separable groups have MC std equal to the
/// propagated one (within 6 %), and the MC mean of each is its true value.
#[test]
fn monte_carlo_paper_combinations() {
    let d = design("paper");
    let obs = Observations::plain(vec![0.0; 100]);
    let truth = [1e-5, -2e-4, 1e-4, 2e-4, -1e-4, 0.0294, 3.2419e-4, 0.0];
    let noise = Noise::Gaussian { sigma: 0.0015 };
    let mc = MonteCarloOptions::default().with_runs(2000).with_seed(3);
    let r = monte_carlo(&d, &obs, &truth, &noise, &mc, &IdentifyOptions::default()).unwrap();
    assert_eq!(r.combinations.len(), 2);
    for c in &r.combinations {
        assert!(
            (c.std_mc / c.std_predicted - 1.0).abs() < 0.06,
            "{}: {} vs {}",
            c.name,
            c.std_mc,
            c.std_predicted
        );
    }
}

/// Weights 1/σ_i² with an a priori σ of 1 give the propagated std exactly.
#[test]
fn a_priori_covariance_equals_propagation() {
    let d = design("physical");
    let noise_sig: Vec<f64> = lengths()
        .iter()
        .map(|&l| CmmMpe::paper000().sigma_mm(l))
        .collect();
    let w: Vec<f64> = noise_sig.iter().map(|s| 1.0 / (s * s)).collect();
    let obs = observations("examples/example_clean.csv", "deviation").with_weights(w);
    let opts = IdentifyOptions::default().with_sigma(1.0);
    let id = identify(&d, &obs, &opts).unwrap();
    assert_eq!(id.sigma_source, "a_priori");
    let truth = id.values();
    let mc = MonteCarloOptions::default().with_runs(2);
    let r = monte_carlo(
        &d,
        &obs,
        &truth,
        &Noise::PerPoint { sigma: noise_sig },
        &mc,
        &opts,
    )
    .unwrap();
    for (p, m) in id.parameters.0.iter().zip(&r.parameters) {
        assert_near!(p.std.unwrap(), m.std_predicted, 1e-9 * m.std_predicted);
    }
}

/// Bad Monte Carlo input is an error, not a panic.
#[test]
fn monte_carlo_errors() {
    let d = design("physical");
    let obs = Observations::plain(vec![0.0; 100]);
    let o = IdentifyOptions::default();
    let mc = MonteCarloOptions::default().with_runs(10);
    let fails =
        |truth: &[f64], noise: Noise| monte_carlo(&d, &obs, truth, &noise, &mc, &o).is_err();
    assert!(fails(&[0.0; 3], Noise::Gaussian { sigma: 0.001 }));
    assert!(fails(&[0.0; 8], Noise::Gaussian { sigma: f64::NAN }));
    assert!(fails(
        &[0.0; 8],
        Noise::PerPoint {
            sigma: vec![0.001; 5]
        }
    ));
    assert!(monte_carlo(
        &d,
        &obs,
        &[0.0; 8],
        &Noise::Gaussian { sigma: 0.001 },
        &mc.with_runs(1),
        &o
    )
    .is_err());
}
