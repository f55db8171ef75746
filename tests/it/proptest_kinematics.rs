//! Property test: the analytic Jacobian of the error model (paper 000 eq. 11-13,
//! `machine::direct::jacobian`) against central finite differences of the exact eq. 12 at
//! RANDOM poses, contact heights and non-zero error vectors, for the three machines (the
//! fixed-pose check is in kinematics_jacobian.rs; round trips direct(inverse) in
//! kinematics_inverse.rs). Every location error and every constant error motion.

use nalgebra::Vector3;
use proptest::prelude::*;
use testpiece::machine::direct::{all_params, jacobian, tool_point};
use testpiece::machine::{AxisValues, Chain, ErrorParam, MachineErrors};
use testpiece::tolerance::FD_REL;

fn machines() -> [Chain; 3] {
    [
        Chain::paper000(499.889),
        Chain::paper002().with_tool_offset(Vector3::new(0.0, 0.0, -120.0)),
        Chain::paper001(200.0, 120.0),
    ]
}

fn is_length(p: &ErrorParam) -> bool {
    let n = p.name();
    n.starts_with("EX") || n.starts_with("EY") || n.starts_with("EZ")
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn jacobian_matches_finite_differences_at_random_poses(
        m in 0usize..3,
        x in -150.0..150.0f64, y in -150.0..150.0f64, z in -100.0..500.0f64,
        a in -1.2..1.2f64, b in -1.2..1.2f64, c in -3.1..3.1f64,
        h in 0.0..30.0f64,
        scale in prop::collection::vec(-1.0..1.0f64, 64),
    ) {
        let chain = &machines()[m];
        let q = AxisValues { x, y, z, a, b, c };
        let params = all_params(chain);
        // A random error vector of machine-like size: 1e-4 rad, 0.01 mm.
        let mut errors = MachineErrors::none();
        for (k, p) in params.iter().enumerate() {
            let size = if is_length(p) { 1e-2 } else { 1e-4 };
            errors = errors.with(*p, size * scale[k % scale.len()]);
        }
        let (jp, jd) = jacobian(chain, &q, h, &errors, &params).unwrap();
        for (k, p) in params.iter().enumerate() {
            let step = if is_length(p) { 1e-4 } else { 1e-6 };
            // with() adds to the value already set: a central difference about `errors`.
            let plus = tool_point(chain, &q, h, &errors.clone().with(*p, step)).unwrap();
            let minus = tool_point(chain, &q, h, &errors.clone().with(*p, -step)).unwrap();
            let fp = (plus.point - minus.point) / (2.0 * step);
            let fd = (plus.direction - minus.direction) / (2.0 * step);
            for r in 0..3 {
                prop_assert!(
                    (jp[(r, k)] - fp[r]).abs() <= FD_REL * (1.0 + fp.norm()),
                    "{} {} point[{}]: analytic {} vs fd {}", chain.code(), p.name(), r, jp[(r, k)], fp[r]
                );
                prop_assert!(
                    (jd[(r, k)] - fd[r]).abs() <= FD_REL * (1.0 + fd.norm()),
                    "{} {} direction[{}]: analytic {} vs fd {}", chain.code(), p.name(), r, jd[(r, k)], fd[r]
                );
            }
        }
    }
}
