//! Levenberg-Marquardt refinement with an exact model: run only where the linearisation error
//! matters, recover a non-linear truth, keep unresolved combinations fixed.
//!
//! The exact model here is a closed-form stand-in with a known Jacobian,
//! `f(x) = A x + κ (A x)²` (element-wise), whose Jacobian `(1 + 2κ A x) ⊙ A` is checked against
//! central finite differences below.
#![allow(clippy::needless_range_loop)] // index loops read like the maths here

use crate::identify_common::*;
use nalgebra::DMatrix;
use testpiece::assert_near;
use testpiece::identify::refine::*;
use testpiece::identify::*;
use testpiece::tolerance::FD_REL;

fn model(d: &Design, kappa: f64) -> impl Fn(&[f64]) -> ModelOutput + '_ {
    move |x: &[f64]| {
        let ax = d.predict(x);
        let f: Vec<f64> = ax.iter().map(|v| v + kappa * v * v).collect();
        let a = d.matrix();
        let j = DMatrix::from_fn(a.nrows(), a.ncols(), |i, c| {
            (1.0 + 2.0 * kappa * ax[i]) * a[(i, c)]
        });
        Ok((f, j))
    }
}

/// The test model's Jacobian against central finite differences (STYLE rule 8).
#[test]
fn test_model_jacobian_matches_finite_differences() {
    let d = design("physical");
    let m = model(&d, 2.0);
    let x = [1e-4, -2e-4, 1e-4, 0.5e-4, -1e-4, 0.02, 2e-4, -1e-4];
    let (_, j) = m(&x).unwrap();
    for c in 0..8 {
        let h = if c == 5 { 1e-5 } else { 1e-7 };
        let (mut xp, mut xm) = (x, x);
        xp[c] += h;
        xm[c] -= h;
        let (fp, _) = m(&xp).unwrap();
        let (fm, _) = m(&xm).unwrap();
        let colmax = (0..100).map(|i| j[(i, c)].abs()).fold(0.0, f64::max);
        for i in 0..100 {
            assert_near!((fp[i] - fm[i]) / (2.0 * h), j[(i, c)], FD_REL * colmax);
        }
    }
}

/// Exact model = linear model + 1e-9 of curvature: the linearisation error is far below 0.1 σ,
/// so LM is skipped and the linear answer is returned with the reason.
#[test]
fn skipped_when_linearisation_error_is_small() {
    let d = design("physical");
    let obs = observations("examples/example_clean.csv", "deviation");
    let opts = IdentifyOptions::default();
    let lin = identify(&d, &obs, &opts).unwrap();
    let r = refine(
        &d,
        &obs,
        &lin,
        model(&d, 1e-9),
        &RefineOptions::default(),
        &opts,
    )
    .unwrap();
    assert!(!r.performed);
    assert!(r.reason.starts_with("skipped"), "{}", r.reason);
    assert_eq!(r.values, lin.values());
    assert_eq!(r.rank, 8);
}

/// A machine's location errors (`truth`, the design's order) and the part the exact model with
/// κ = 2 /mm makes of them, noiseless.
fn curved_part(d: &Design) -> ([f64; 8], Observations) {
    let truth = [
        7.5e-5, 2.4e-4, 1.7e-4, -1.6e-4, -1.2e-4, 0.0178, -2.97e-4, 1.9e-4,
    ];
    let (y, _) = model(d, 2.0)(&truth).unwrap();
    (truth, Observations::plain(y))
}

/// κ = 2 /mm: deviations of ±0.15 mm get ±45 µm of curvature. The linear fit is biased; LM
/// recovers the truth from noiseless data to 1e-9 and reports success.
#[test]
fn recovers_non_linear_truth() {
    let d = design("physical");
    let (truth, obs) = curved_part(&d);
    let opts = IdentifyOptions::default();
    let lin = identify(&d, &obs, &opts).unwrap();
    let bias = (lin.value("EA0B").unwrap() - truth[6]).abs();
    assert!(bias > 1e-7, "linear fit should be biased: {bias}");
    let r = refine(
        &d,
        &obs,
        &lin,
        model(&d, 2.0),
        &RefineOptions::default(),
        &opts,
    )
    .unwrap();
    assert!(r.performed && r.success, "{} / {}", r.reason, r.termination);
    assert!(r.evaluations > 0);
    for j in 0..8 {
        assert_near!(r.values[j], truth[j], 1e-9);
    }
    assert!(r.residual_rms < 1e-12);
    assert_eq!(r.rank, 8);
    assert!(r.condition.is_finite());
}

/// The refinement of a fit from the factored problem its identification kept
/// (`identify_factored`, `refine_factored`) is the refinement that factorises it again: the same
/// identification and the same report, value for value (κ = 2 /mm as above, LM run).
#[test]
fn the_kept_factorisation_refines_as_a_new_one() {
    let d = design("physical");
    let (_, obs) = curved_part(&d);
    let opts = IdentifyOptions::default();
    let lin = identify(&d, &obs, &opts).unwrap();
    let (kept, factored) = identify_factored(&d, &obs, &opts).unwrap();
    assert_eq!(kept.values(), lin.values());
    assert_eq!(kept.parameters, lin.parameters);
    let ropts = RefineOptions::default();
    let again = refine(&d, &obs, &lin, model(&d, 2.0), &ropts, &opts).unwrap();
    let from_kept =
        refine_factored(&d, &obs, &kept, &factored, model(&d, 2.0), &ropts, &opts).unwrap();
    assert!(again.performed);
    assert_eq!(from_kept.values, again.values);
    assert_eq!(from_kept.std, again.std);
    assert_eq!(from_kept.covariance, again.covariance);
    assert_eq!(from_kept.evaluations, again.evaluations);
    assert_eq!(from_kept.residual_rms, again.residual_rms);
}

/// Paper mode: LM works only in the solved subspace, so the unresolved combinations stay as the
/// linear solution fixed them; a truth with the group parameters at 0 is recovered.
#[test]
fn keeps_unresolved_directions_fixed() {
    let d = design("paper").with_tool_radius().unwrap();
    let truth = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0294, 3.2419e-4, 0.0, -0.02];
    let (y, _) = model(&d, 1.0)(&truth).unwrap();
    let obs = Observations::plain(y);
    let opts = IdentifyOptions::default();
    let lin = identify(&d, &obs, &opts).unwrap();
    assert_eq!(lin.rank_used, 7);
    let r = refine(
        &d,
        &obs,
        &lin,
        model(&d, 1.0),
        &RefineOptions::default().forced(),
        &opts,
    )
    .unwrap();
    assert!(r.success, "{}", r.termination);
    for j in 0..9 {
        assert_near!(r.values[j], truth[j], 1e-9);
    }
    assert_eq!(r.rank, 7);
}

/// A failing or mis-shaped model is an error with its message.
#[test]
fn model_errors_are_reported() {
    let d = design("physical");
    let obs = Observations::plain(vec![0.0; 100]);
    let opts = IdentifyOptions::default();
    let lin = identify(&d, &obs, &opts).unwrap();
    let e = refine(
        &d,
        &obs,
        &lin,
        |_: &[f64]| {
            Err(ModelError::Sensitivity(
                testpiece::sensitivity::SensitivityError::BadPoint { id: 7, u: 1.5 },
            ))
        },
        &RefineOptions::default(),
        &opts,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "exact model: point 7: u = 1.5 is outside [0, 1]"
    );
    let short = |_: &[f64]| Ok((vec![0.0; 3], DMatrix::zeros(3, 8)));
    let e = refine(&d, &obs, &lin, short, &RefineOptions::default(), &opts).unwrap_err();
    assert!(e.to_string().contains("3 deviations"), "{e}");
}
