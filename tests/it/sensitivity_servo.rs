//! Servo following error columns (`servo_lag_<axis>.l`, `servo_common.L2`) against the converged
//! per-unit signatures of tests/data/reference/servo_signatures.csv (physical mode, signed B,
//! L0 = 499.889; the reference README's tolerance: 1e-6 of each column's largest value).

use testpiece::machine::AxisName;
use testpiece::part::{builtin_points, SShape, Surface};
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

/// A dense scan's servo rates from the table of the paths (`RateTable`, nodes 1/2600 apart in
/// `u`) against each point's own finite differences, at 3,000 `u` on each surface of paper
/// 000's machine: the first rates within 1e-7, the second within 1e-6, of each axis's largest
/// over the path (measured 1.0e-8 and 7.1e-8; the points near a knot, the vertical zone's ends
/// among them, are solved at the point). The first-order formulas themselves are 5 % from servos
/// simulated in time (`FIRST_ORDER_REL`).
#[test]
fn the_rate_table_is_the_points_own_rates() {
    use testpiece::numerics::parallel::Threads;
    use testpiece::sensitivity::servo::{path_rates, PathRates, RateTable};
    let part = SShape::iso();
    let opts = SensitivityOptions::default();
    let table = RateTable::new(&part, &opts, Threads::new(2)).unwrap();
    let axes: Vec<AxisName> = opts.chain.axes().map(|a| a.name).collect();
    for surface in Surface::BOTH {
        let us: Vec<f64> = (0..3000).map(|i| (i as f64 + 0.37) / 3000.0).collect();
        let exact = path_rates(&part, surface, &us, &opts).unwrap();
        let got = table.rates(&part, surface, &us, &opts, &axes).unwrap();
        for &a in &axes {
            let big = |f: &dyn Fn(&PathRates) -> f64| {
                exact.iter().map(|r| f(r).abs()).fold(0.0, f64::max)
            };
            let (m1, m2) = (big(&|r| r.first.get(a)), big(&|r| r.second.get(a)));
            let mut worst = (0.0f64, 0.0f64);
            for (e, g) in exact.iter().zip(&got) {
                worst.0 = worst.0.max((e.first.get(a) - g.first.get(a)).abs() / m1);
                worst.1 = worst.1.max((e.second.get(a) - g.second.get(a)).abs() / m2);
            }
            assert!(
                worst.0 < 1e-7 && worst.1 < 1e-6,
                "{surface:?} {a:?}: {worst:?}"
            );
        }
    }
}
