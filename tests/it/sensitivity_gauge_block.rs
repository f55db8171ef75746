//! Gauge-block check of paper 000 eq. 14-15 (spec s-shape.md): a probe (L0 = 533.889 mm, B = 0)
//! measures the same table point at C = 0, 90, 180, 270°. With the probed point on the C axis
//! plane x = 0 at the B-axis height (X = 0, Z = L0), the model of eq. 12 gives
//! `y(C180) − y(C0) = −2·L0·EA0B` and `y(C270) − y(C90) = 2·EX0B` for any error vector; applied to
//! the paper's readings they give EA0B = −3.549e-4 rad (the paper prints +3.549e-4) and
//! EX0B = +0.003 mm.

use nalgebra::Vector3;
use testpiece::assert_near;
use testpiece::machine::direct::{jacobian, tool_point};
use testpiece::machine::inverse::inverse;
use testpiece::machine::location_errors::minimal_set;
use testpiece::machine::{Branch, Chain, ErrorParam, MachineErrors};

const L0_PROBE: f64 = 533.889;

fn probe_y(chain: &Chain, errors: &MachineErrors, c_deg: f64) -> f64 {
    // The gauge face point in table coordinates; the machine puts the nominal tip on it.
    let p = Vector3::new(0.0, -328.0, 0.0);
    let q = inverse(chain, &p, &Vector3::z(), Branch::Signed, c_deg.to_radians()).unwrap();
    assert_near!(q.c, c_deg.to_radians(), 1e-15);
    assert_near!(q.b, 0.0, 1e-15);
    // Displacement of the real tip in table coordinates (exact eq. 12).
    tool_point(chain, &q, 0.0, errors).unwrap().point.y - p.y
}

#[test]
fn eq15_holds_for_any_error_vector() {
    let chain = Chain::paper000(L0_PROBE);
    let params: Vec<ErrorParam> = minimal_set(&chain)
        .free()
        .into_iter()
        .map(ErrorParam::Location)
        .collect();
    // A deterministic spread of errors (rad; EX0B in mm), all 8 non-zero.
    let xi = [
        1.1e-4, -2.3e-4, 0.7e-4, 1.9e-4, -1.4e-4, 0.021, 3.2e-4, -0.8e-4,
    ];
    let e = MachineErrors::from_pairs(&params, &xi);
    let (ea0b, ex0b) = (xi[6], xi[5]);
    let y = |c| probe_y(&chain, &e, c);
    // Exact eq. 12: second-order terms are |ξ|²·L0 ≈ 5e-5 mm at most here.
    assert_near!(y(180.0) - y(0.0), -2.0 * L0_PROBE * ea0b, 1e-4);
    assert_near!(y(270.0) - y(90.0), 2.0 * ex0b, 1e-4);
    // Linear eq. 14: exact relations.
    let jy = |c: f64| {
        let q = inverse(
            &chain,
            &Vector3::new(0.0, -328.0, 0.0),
            &Vector3::z(),
            Branch::Signed,
            c.to_radians(),
        )
        .unwrap();
        let (j, _) = jacobian(&chain, &q, 0.0, &MachineErrors::none(), &params).unwrap();
        (0..8).map(|k| j[(1, k)] * xi[k]).sum::<f64>()
    };
    assert_near!(jy(180.0) - jy(0.0), -2.0 * L0_PROBE * ea0b, 1e-12);
    assert_near!(jy(270.0) - jy(90.0), 2.0 * ex0b, 1e-12);
}

#[test]
fn paper_readings_give_negative_ea0b() {
    // Paper 000 eq. 14 readings (mm), fitted with the model: y_C = y_true + ∂y/∂(EA0B, EX0B)·(EA0B, EX0B)
    // at the four probing poses (least squares, 4 equations, 3 unknowns).
    let chain = Chain::paper000(L0_PROBE);
    let params = [
        ErrorParam::parse("EA0B").unwrap(),
        ErrorParam::parse("EX0B").unwrap(),
    ];
    let readings = [
        (0.0, -328.005),
        (90.0, -327.821),
        (180.0, -327.626),
        (270.0, -327.815),
    ];
    let mut a = nalgebra::DMatrix::zeros(4, 3);
    let mut b = nalgebra::DVector::zeros(4);
    for (r, (c, y)) in readings.iter().enumerate() {
        let q = inverse(
            &chain,
            &Vector3::new(0.0, -328.0, 0.0),
            &Vector3::z(),
            Branch::Signed,
            f64::to_radians(*c),
        )
        .unwrap();
        let (j, _) = jacobian(&chain, &q, 0.0, &MachineErrors::none(), &params).unwrap();
        a[(r, 0)] = 1.0;
        a[(r, 1)] = j[(1, 0)];
        a[(r, 2)] = j[(1, 1)];
        b[r] = *y;
    }
    let x = a.clone().svd(true, true).solve(&b, 1e-12).unwrap();
    assert_near!(x[1], -3.549e-4, 5e-8); // the paper prints +3.549e-4
    assert_near!(x[2], 0.003, 1e-9);
}
