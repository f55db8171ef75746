//! Inverse kinematics (paper 000 eq. 9): direct(inverse(pose)) = pose to 1e-9 mm over random
//! poses away from singularities, for the three machines and both branches.

use nalgebra::Vector3;
use proptest::prelude::*;
use testpiece::machine::direct::nominal;
use testpiece::machine::inverse::inverse;
use testpiece::machine::{Branch, Chain};
use testpiece::tolerance::KINEMATICS_MM;

fn machines() -> Vec<Chain> {
    vec![
        Chain::paper000(499.889),
        Chain::paper002().with_tool_offset(Vector3::new(0.0, 0.0, -120.0)),
        Chain::paper001(200.0, 120.0),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn direct_of_inverse_is_identity(
        m in 0usize..3,
        x in -200.0..200.0f64, y in -200.0..200.0f64, z in -100.0..100.0f64,
        tilt in 0.05..1.4f64, tilt_sign in prop::bool::ANY, turn in -3.1..3.1f64,
        prev in -6.0..6.0f64, positive in prop::bool::ANY,
    ) {
        let chain = &machines()[m];
        // A pose: tool tip and direction (the direction from a tilted axis turned about z).
        let w = Vector3::new(tilt.sin() * turn.cos(), tilt.sin() * turn.sin(), tilt.cos());
        let w = if tilt_sign { w } else { Vector3::new(-w.x, w.y, w.z) };
        // paper001's head tilts about y then x: its reachable set is every direction, as for the
        // others; away from singularities means w not parallel to the outer axis.
        let tip = Vector3::new(x, y, z);
        let branch = if positive { Branch::Positive } else { Branch::Signed };
        let q = inverse(chain, &tip, &w, branch, prev).unwrap();
        let p = nominal(chain, &q, 0.0);
        prop_assert!((p.point - tip).norm() <= KINEMATICS_MM, "{:?}: {} vs {}", q, p.point, tip);
        prop_assert!((p.direction - w).norm() <= 1e-12, "{:?}: {} vs {}", q, p.direction, w);
        // And the other way: inverse(direct(q)) reproduces the same pose (not necessarily q).
        let q2 = inverse(chain, &p.point, &p.direction, branch, prev).unwrap();
        let p2 = nominal(chain, &q2, 0.0);
        prop_assert!((p2.point - tip).norm() <= KINEMATICS_MM);
        if positive && m < 2 {
            let pair = testpiece::machine::inverse::RotaryPair::of(chain).unwrap();
            prop_assert!(q.get(pair.inner) >= 0.0);
        }
    }
}

#[test]
fn signed_branch_is_paper000_eq9() {
    // C = atan(-j/i) modulo π nearest the previous C, B = atan2(i cosC - j sinC, k).
    let chain = Chain::paper000(499.889);
    let w = Vector3::new(-0.2, 0.1, 0.9).normalize();
    let q = inverse(
        &chain,
        &Vector3::new(1.0, 2.0, 3.0),
        &w,
        Branch::Signed,
        0.0,
    )
    .unwrap();
    let c = (-w.y / w.x).atan();
    let b = (w.x * c.cos() - w.y * c.sin()).atan2(w.z);
    assert!((q.c - c).abs() < 1e-14 && (q.b - b).abs() < 1e-14, "{q:?}");
    assert!(q.b < 0.0);
    let qp = inverse(
        &chain,
        &Vector3::new(1.0, 2.0, 3.0),
        &w,
        Branch::Positive,
        0.0,
    )
    .unwrap();
    assert!(
        (qp.c - (-w.y).atan2(w.x)).abs() < 1e-14 && qp.b > 0.0,
        "{qp:?}"
    );
}

#[test]
fn outer_angle_is_exact_next_to_the_singularity() {
    // Next to the S-shape's vertical zone the horizontal part of the axis is ~1e-40: C must still
    // be atan(-j/i) (eq. 9), not the arbitrary value of an exactly vertical axis.
    let chain = Chain::paper000(499.889);
    for (i, j) in [(-3e-40, 12e-40), (4e-45, -8e-45)] {
        let w = Vector3::new(i, j, 1.0);
        let q = inverse(&chain, &Vector3::zeros(), &w, Branch::Signed, 1.0).unwrap();
        let c = (-j / i).atan();
        let c = c + std::f64::consts::PI * ((1.0 - c) / std::f64::consts::PI).round();
        assert!((q.c - c).abs() < 1e-15, "{} vs {c}", q.c);
        assert!(q.b.abs() < 1e-38);
    }
}
