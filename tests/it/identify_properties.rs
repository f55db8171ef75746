//! Properties of the identification: exact recovery of noiseless vectors, defined results on
//! rank-deficient designs, weights, input validation.
#![allow(clippy::needless_range_loop)] // index loops read like the maths here

use crate::identify_common::*;
use nalgebra::DMatrix;
use proptest::prelude::*;
use testpiece::assert_near;
use testpiece::identify::*;

fn no_nan(id: &Identification) {
    let json = serde_json::to_string(id).unwrap();
    assert!(!json.contains("NaN"));
    for p in &id.parameters.0 {
        assert!(p.value.is_finite(), "{} = {}", p.name(), p.value);
        if let Some(s) = p.std {
            assert!(s.is_finite() && s >= 0.0);
        }
    }
    assert!(id.residual.rms.is_finite());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Noiseless A·x on the physical design (full rank, condition 8.4) is recovered to 1e-9
    /// (mm for EX0B, rad for the angles: far below any machine error).
    #[test]
    fn noiseless_physical_recovered(x in xi_strategy()) {
        let d = design("physical");
        let obs = Observations::plain(d.predict(&x));
        let id = identify(&d, &obs, &IdentifyOptions::default()).unwrap();
        for (j, p) in id.parameters.0.iter().enumerate() {
            prop_assert!((p.value - x[j]).abs() < 1e-9, "{}: {} vs {}", p.name(), p.value, x[j]);
        }
        prop_assert!(id.residual.max_abs < 1e-12);
    }

    /// Paper mode: the estimator is a projection. Re-identifying the deviations of an
    /// identified vector gives it back to 1e-9; and a vector with the group parameters at 0
    /// (Table 4's case) is recovered to 1e-9 with an exact fit.
    #[test]
    fn noiseless_paper_recovered(x in xi_strategy()) {
        let d = design("paper");
        let id = identify(&d, &Observations::plain(d.predict(&x)), &IdentifyOptions::default()).unwrap();
        let x1 = id.values();
        let id2 = identify(&d, &Observations::plain(d.predict(&x1)), &IdentifyOptions::default()).unwrap();
        for j in 0..8 {
            prop_assert!((id2.values()[j] - x1[j]).abs() < 1e-9, "{}", id.names()[j]);
        }
        prop_assert!(id2.residual.max_abs < 1e-12);
        let mut x0 = x.clone();
        for j in 1..5 {
            x0[j] = 0.0;
        }
        let id0 = identify(&d, &Observations::plain(d.predict(&x0)), &IdentifyOptions::default()).unwrap();
        for j in 0..8 {
            prop_assert!((id0.values()[j] - x0[j]).abs() < 1e-9, "{}", id.names()[j]);
        }
        prop_assert!(id0.residual.max_abs < 1e-12);
    }
}

/// Fewer points than parameters: rank = number of points, every direction beyond is named,
/// nothing is NaN, the points are fitted exactly.
#[test]
fn fewer_points_than_parameters() {
    let full = design("physical");
    let a = full.matrix().rows(0, 5).into_owned();
    let d = Design::try_new(full.parameters().to_vec(), a).unwrap();
    let x = [1e-4, -2e-4, 1e-4, 0.5e-4, -1e-4, 0.01, 2e-4, -1e-4];
    let obs = Observations::plain(d.predict(&x));
    let id = identify(&d, &obs, &IdentifyOptions::default()).unwrap();
    no_nan(&id);
    assert_eq!(id.rank, 5, "5 generic rows");
    assert!(id.rank_used <= 5);
    // Every direction not solved is named in a not-separable group.
    let named: usize = id
        .groups
        .iter()
        .filter(|g| g.kind == GroupKind::NotSeparable)
        .map(|g| g.directions.len())
        .sum();
    assert_eq!(named, 8 - id.rank_used);
    // Fitted exactly when all 5 directions are kept; otherwise the dropped (condition index
    // >= 30) directions leave a residual no larger than the data.
    let ymax = obs.deviation.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(id.residual.max_abs <= ymax);
    if id.rank_used == 5 {
        assert!(id.residual.max_abs < 1e-12);
    }
    if id.dof == 0 {
        assert!(id.sigma.is_none(), "no dof, no a priori sigma: no std");
    }
    assert!(id
        .notes
        .iter()
        .any(|n| n.contains("only 5 points for 8 parameters")));
}

/// Two identical columns and a zero column: the duplicate pair is a group whose estimable
/// combination is their sum; the zero column is reported as not determined at all (value 0).
#[test]
fn collinear_and_zero_columns() {
    let full = design("physical");
    let mut a = full.matrix().clone();
    let c0 = a.column(0).into_owned();
    a.column_mut(1).copy_from(&c0); // EA0Z column := EC0Y column
    a.column_mut(2).fill(0.0); // EB0Z unseen
    let d = Design::try_new(full.parameters().to_vec(), a).unwrap();
    let x = [1e-4, 2e-4, 3e-4, -1e-4, 1e-4, 0.01, 2e-4, -1e-4];
    let obs = Observations::plain(d.predict(&x));
    let id = identify(&d, &obs, &IdentifyOptions::default()).unwrap();
    no_nan(&id);
    assert_eq!(id.rank, 6);
    assert_eq!(id.rank_used, 6);
    assert!(id.residual.max_abs < 1e-12);
    let zero = id
        .groups
        .iter()
        .find(|g| g.parameters == ["EB0Z"])
        .expect("zero column group");
    assert!(zero.estimable.is_empty());
    assert!(zero.explanation.contains("at all"));
    assert_eq!(id.value("EB0Z"), Some(0.0));
    let dup = id
        .groups
        .iter()
        .find(|g| g.parameters == ["EC0Y", "EA0Z"])
        .expect("duplicate group");
    let names = d.names();
    let e = &dup.estimable[0];
    // Estimable: EC0Y + EA0Z (identical columns), value 3e-4.
    assert_near!(e.combination.apply(&names, &x), 3e-4, 1e-18);
    assert_near!(e.value, 3e-4, 1e-12);
    for t in &e.combination.terms {
        assert_near!(t.coefficient, 1.0, 1e-9);
    }
    // The other parameters are still recovered exactly.
    for j in 3..8 {
        assert_near!(id.values()[j], x[j], 1e-9);
    }
}

/// An all-zero design and a single point: defined answers, no NaN, no panic.
#[test]
fn degenerate_designs() {
    let d = Design::try_new(
        vec![
            Parameter::parse("EX0B").unwrap(),
            Parameter::parse("EA0B").unwrap(),
        ],
        DMatrix::zeros(4, 2),
    )
    .unwrap();
    let id = identify(
        &d,
        &Observations::plain(vec![0.01, -0.02, 0.0, 0.03]),
        &IdentifyOptions::default(),
    )
    .unwrap();
    no_nan(&id);
    assert_eq!(id.rank, 0);
    assert_eq!(id.values(), vec![0.0, 0.0]);
    assert!(!id.condition.is_finite());

    let full = design("physical").with_tool_radius().unwrap();
    let a = full.matrix().rows(10, 1).into_owned();
    let d1 = Design::try_new(full.parameters().to_vec(), a).unwrap();
    let id1 = identify(
        &d1,
        &Observations::plain(vec![0.005]),
        &IdentifyOptions::default(),
    )
    .unwrap();
    no_nan(&id1);
    assert_eq!(id1.rank, 1);
    assert!(id1.residual.max_abs < 1e-15);
}

/// Weight 0 excludes a point (listed), and a gross error on it changes nothing.
#[test]
fn zero_weight_excludes_point() {
    let d = design("physical");
    let x = [1e-4, -1e-4, 2e-4, 0.0, 1e-4, 0.02, -2e-4, 1e-4];
    let mut y = d.predict(&x);
    y[17] += 1.0;
    let mut w = vec![1.0; 100];
    w[17] = 0.0;
    let obs = Observations::plain(y).with_weights(w);
    let id = identify(&d, &obs, &IdentifyOptions::default()).unwrap();
    assert_eq!(id.points_used, 99);
    assert_eq!(id.points_excluded.len(), 1);
    assert_eq!(id.points_excluded[0].id, "18");
    for j in 0..8 {
        assert_near!(id.values()[j], x[j], 1e-9);
    }
    assert!(!id.points[17].used);
}

/// Scaling all weights by a constant changes neither the estimate nor the a posteriori std.
#[test]
fn weights_are_relative() {
    let d = design("physical");
    let obs = observations("examples/example_clean.csv", "deviation");
    let w: Vec<f64> = (0..100).map(|i| 1.0 + (i % 3) as f64).collect();
    let a = identify(
        &d,
        &obs.clone().with_weights(w.clone()),
        &IdentifyOptions::default(),
    )
    .unwrap();
    let b = identify(
        &d,
        &obs.with_weights(w.iter().map(|v| v * 7.0).collect()),
        &IdentifyOptions::default(),
    )
    .unwrap();
    for (p, q) in a.parameters.0.iter().zip(&b.parameters.0) {
        assert_near!(p.value, q.value, 1e-12 * p.value.abs().max(1e-9));
        assert_near!(p.std.unwrap(), q.std.unwrap(), 1e-9 * p.std.unwrap());
    }
}

/// Bad input gives the specific error with the offending value, never a panic.
#[test]
fn input_errors() {
    let d = design("physical");
    let mut y = vec![0.0; 100];
    y[3] = f64::NAN;
    let e = identify(&d, &Observations::plain(y), &IdentifyOptions::default()).unwrap_err();
    assert!(
        matches!(e, IdentifyError::NonFiniteDeviation { ref id, .. } if id == "4"),
        "{e}"
    );
    let e = identify(
        &d,
        &Observations::plain(vec![0.0; 99]),
        &IdentifyOptions::default(),
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "deviations: 99 values for 100 design rows");
    let e = identify(
        &d,
        &Observations::plain(vec![0.0; 100]).with_weights(vec![0.0; 100]),
        &IdentifyOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(
        e,
        IdentifyError::NoPoints {
            total: 100,
            excluded: 100
        }
    ));
    let e = identify(
        &d,
        &Observations::plain(vec![0.0; 100]),
        &IdentifyOptions::default().with_condition_index_limit(0.5),
    )
    .unwrap_err();
    assert!(e.to_string().contains("0.5"), "{e}");
    let e = Design::from_column_major(&["EX0B", "EX0B"], 1, &[1.0, 2.0]).unwrap_err();
    assert!(matches!(e, IdentifyError::DuplicateName { .. }));
    let e = Design::from_column_major(&["EX0B"], 2, &[1.0, f64::INFINITY]).unwrap_err();
    assert!(e.to_string().contains("inf"), "{e}");
    let e = Design::from_column_major(&["EX0B"], 3, &[1.0, 2.0]).unwrap_err();
    assert!(matches!(
        e,
        IdentifyError::DesignShape {
            rows: 3,
            cols: 1,
            found: 2
        }
    ));
}

/// Residual statistics against their closed forms (paper 001 eq. 15-17).
#[test]
fn residual_statistics_closed_form() {
    let s = ResidualStats::of(
        &[0.01, -0.02, 0.001, 0.004],
        &[0.011, -0.018, 0.0, 0.004],
        0.003,
    );
    assert_near!(s.mad, (0.001 + 0.002 + 0.001 + 0.0) / 4.0, 1e-15);
    assert_near!(s.rmse, ((1e-6 + 4e-6 + 1e-6) / 4.0f64).sqrt(), 1e-15);
    assert_near!(s.rms, s.rmse, 0.0);
    assert_near!(s.max_abs, 0.002, 1e-15);
    // 0.001 is below the 0.003 floor: 3 points enter MAPE.
    assert_eq!(s.mape_points, 3);
    assert_near!(s.mape.unwrap(), 100.0 * (0.1 + 0.1 + 0.0) / 3.0, 1e-9);
}
