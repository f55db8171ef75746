//! Servo following error columns (`servo_lag_<axis>.l`, `servo_common.L2`) against the converged
//! per-unit signatures of tests/data/reference/servo_signatures.csv (physical mode, signed B,
//! L0 = 499.889; the reference README's tolerance: 1e-6 of each column's largest value).

use testpiece::machine::AxisName;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::servo::servo_signatures;
use testpiece::sensitivity::{axis_values, SensitivityOptions};

use crate::validate_physics::servo_column as column;

fn worst(got: &[f64], want: &[f64]) -> f64 {
    let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    got.iter()
        .zip(want)
        .map(|(g, w)| (g - w).abs() / scale)
        .fold(0.0, f64::max)
}

#[test]
fn servo_signatures_match_reference() {
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let opts = SensitivityOptions::default();
    let q = axis_values(&part, &pts, &opts).unwrap();
    let cols = servo_signatures(&part, &pts, &q, &opts).unwrap();
    for (axis, name) in [
        (AxisName::X, "servo_lag_x.l"),
        (AxisName::Y, "servo_lag_y.l"),
        (AxisName::Z, "servo_lag_z.l"),
        (AxisName::B, "servo_lag_b.l"),
        (AxisName::C, "servo_lag_c.l"),
    ] {
        let got = &cols.lag.iter().find(|(a, _)| *a == axis).unwrap().1;
        let w = worst(got, &column(name));
        eprintln!("{name}: max difference {w:e} of the column's largest value");
        assert!(w < 1e-6, "{name}: {w:e}");
    }
    let w = worst(&cols.common, &column("servo_common.L2"));
    eprintln!("servo_common.L2: max difference {w:e} of the column's largest value");
    assert!(w < 1e-6, "servo_common.L2: {w:e}");
    // The identity of the reference README: the whole tool moving along its path leaves the part
    // unchanged, Σ_i servo_lag_i ≈ 0 (within 0.009 mm/mm; the columns reach 2.66).
    for i in 0..pts.len() {
        let sum: f64 = cols.lag.iter().map(|(_, c)| c[i]).sum();
        assert!(sum.abs() < 0.009, "point {}: Σ = {sum}", i + 1);
    }
}
