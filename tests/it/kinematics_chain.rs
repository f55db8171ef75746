//! Kinematic chains as data: structural codes, nominal kinematics of paper 000 eq. 9, and the
//! minimal location-error sets of paper 000 Table 3 derived from the chain.

use nalgebra::{DMatrix, Vector3};
use testpiece::assert_near;
use testpiece::machine::direct::{jacobian, nominal};
use testpiece::machine::location_errors::minimal_set;
use testpiece::machine::{
    AxisValues, Chain, ErrorParam, LocationError, LocationStatus, MachineErrors,
};

const L0: f64 = 499.889;

#[test]
fn paper000_nominal_is_eq9() {
    // x = X cosC + Y sinC - L0 cosC sinB, y = -X sinC + Y cosC + L0 sinB sinC, z = Z - L0 cosB,
    // w = (sinB cosC, -sinB sinC, cosB).
    let chain = Chain::paper000(L0);
    let (x, y, z, b, c) = (12.0, -34.0, 480.0, 0.31, -1.2);
    let p = nominal(&chain, &AxisValues::xyzbc(x, y, z, b, c), 0.0);
    assert_near!(
        p.point.x,
        x * c.cos() + y * c.sin() - L0 * c.cos() * b.sin(),
        1e-12
    );
    assert_near!(
        p.point.y,
        -x * c.sin() + y * c.cos() + L0 * b.sin() * c.sin(),
        1e-12
    );
    assert_near!(p.point.z, z - L0 * b.cos(), 1e-12);
    let w = Vector3::new(b.sin() * c.cos(), -b.sin() * c.sin(), b.cos());
    assert_near!((p.direction - w).norm(), 0.0, 1e-15);
}

#[test]
fn minimal_sets_of_the_three_machines() {
    let names = |c: &Chain| minimal_set(c).names();
    // Paper 000 Table 3, in the order of its ξ.
    assert_eq!(
        names(&Chain::paper000(L0)),
        ["EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B"]
    );
    // B-C tilting table (paper 002): the same 8 names; here C rides on B.
    assert_eq!(
        names(&Chain::paper002()),
        ["EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B"]
    );
    // XFYZBA head (paper 001): origin on the B line; A keeps its offset along z.
    assert_eq!(
        names(&Chain::paper001(200.0, 120.0)),
        ["EC0Y", "EA0Z", "EB0Z", "EA0B", "EC0B", "EZ0A", "EB0A", "EC0A"]
    );
    // Table 3's zeros and dashes for paper 000.
    let t = minimal_set(&Chain::paper000(L0));
    let st = |s: &str| t.status(LocationError::parse(s).unwrap()).unwrap();
    for s in [
        "EX0X", "EB0X", "EC0X", "EY0Y", "EA0Y", "EZ0Z", "EX0C", "EY0C", "EC0C", "EZ0B", "EB0B",
    ] {
        assert_eq!(st(s), LocationStatus::Zero, "{s}");
    }
    for s in [
        "EY0X", "EZ0X", "EA0X", "EX0Y", "EZ0Y", "EB0Y", "EX0Z", "EY0Z", "EC0Z", "EZ0C", "EY0B",
    ] {
        assert_eq!(st(s), LocationStatus::Meaningless, "{s}");
    }
}

/// Rank of a matrix by SVD with a relative threshold.
fn rank(m: &DMatrix<f64>) -> usize {
    let sv = m.clone().svd(false, false).singular_values;
    let max = sv.max();
    sv.iter().filter(|s| **s > 1e-9 * max).count()
}

#[test]
fn minimal_sets_are_independent_on_tool_pose() {
    // Stack the 6-row Jacobian (tool point, tool direction scaled by 100 mm) over varied poses:
    // the minimal set must have full column rank.
    let machines = [
        Chain::paper000(L0),
        Chain::paper002().with_tool_offset(Vector3::new(0.0, 0.0, -120.0)),
        Chain::paper001(200.0, 120.0),
    ];
    for chain in machines {
        let params: Vec<ErrorParam> = minimal_set(&chain)
            .free()
            .into_iter()
            .map(ErrorParam::Location)
            .collect();
        let mut rows = Vec::new();
        for k in 0..12 {
            let t = k as f64;
            let q = AxisValues {
                x: 50.0 * (0.7 * t).sin(),
                y: 40.0 * (1.3 * t).cos(),
                z: 300.0 + 30.0 * (0.5 * t).sin(),
                a: 0.6 * (0.9 * t).sin(),
                b: 0.5 * (1.7 * t).cos(),
                c: 2.0 * (0.4 * t).sin(),
            };
            let (jp, jd) = jacobian(&chain, &q, 0.0, &MachineErrors::none(), &params).unwrap();
            for r in 0..3 {
                rows.push(jp.row(r).iter().copied().collect::<Vec<_>>());
                rows.push(jd.row(r).iter().map(|v| 100.0 * v).collect::<Vec<_>>());
            }
        }
        let m = DMatrix::from_fn(rows.len(), params.len(), |i, j| rows[i][j]);
        assert_eq!(rank(&m), params.len(), "{}", chain.code());
    }
}

#[test]
fn rigid_nominal_equals_error_model_at_zero() {
    // `nominal` (plain rigid motions) and `tool_point` with no errors (eq. 12, 4×4) agree.
    use testpiece::machine::direct::tool_point;
    let chains = [
        Chain::paper000(L0),
        Chain::paper001(200.0, 120.0),
        Chain::paper002()
            .with_offset(
                testpiece::machine::AxisName::B,
                Vector3::new(0.033, 0.033, -139.192),
            )
            .unwrap()
            .with_tool_offset(Vector3::new(0.0, 0.0, -120.0)),
    ];
    for c in chains {
        let q = AxisValues {
            x: 12.0,
            y: -7.0,
            z: 250.0,
            a: 0.3,
            b: -0.4,
            c: 2.2,
        };
        let a = nominal(&c, &q, 16.0);
        let b = tool_point(&c, &q, 16.0, &MachineErrors::none()).unwrap();
        assert!((a.point - b.point).norm() < 1e-12 && (a.direction - b.direction).norm() < 1e-15);
    }
}
