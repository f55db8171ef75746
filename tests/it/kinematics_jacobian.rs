//! Error model of paper 000 eq. 11-13: the analytic Jacobian against central finite differences
//! of the exact eq. 12, and against `tests/data/reference/jacobian_samples.csv` (independent
//! implementation, see its README).

use nalgebra::Vector3;
use testpiece::assert_near;
use testpiece::machine::direct::{jacobian, tool_point};
use testpiece::machine::location_errors::minimal_set;
use testpiece::machine::{AxisName, AxisValues, Chain, ErrorMotion, ErrorParam, MachineErrors};
use testpiece::tolerance::FD_REL;

const L0: f64 = 499.889;

fn data(name: &str) -> String {
    format!("{}/tests/data/reference/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn xi_params(chain: &Chain) -> Vec<ErrorParam> {
    minimal_set(chain)
        .free()
        .into_iter()
        .map(ErrorParam::Location)
        .collect()
}

#[test]
fn jacobian_matches_reference_samples() {
    let chain = Chain::paper000(L0);
    let params = xi_params(&chain);
    let names: Vec<String> = params.iter().map(|p| p.name()).collect();
    assert_eq!(
        names,
        ["EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B"]
    );
    let mut rdr = csv::Reader::from_path(data("jacobian_samples.csv")).unwrap();
    let headers = rdr.headers().unwrap().clone();
    let mut rows = 0;
    let mut worst: f64 = 0.0;
    for rec in rdr.records() {
        let rec = rec.unwrap();
        let f = |k: &str| -> f64 {
            let i = headers.iter().position(|h| h == k).unwrap();
            rec[i].parse().unwrap()
        };
        let q = AxisValues::xyzbc(f("X"), f("Y"), f("Z"), f("B"), f("C"));
        let (jp, _) = jacobian(&chain, &q, f("h"), &MachineErrors::none(), &params).unwrap();
        for (r, c) in ["x", "y", "z"].iter().enumerate() {
            for (k, n) in names.iter().enumerate() {
                let want = f(&format!("d{c}_d{n}"));
                let got = jp[(r, k)];
                worst = worst.max((got - want).abs() / (1.0 + want.abs()));
                assert_near!(got, want, 1e-9 * (1.0 + want.abs()));
            }
        }
        rows += 1;
    }
    assert_eq!(rows, 50);
    eprintln!("jacobian_samples.csv: max relative difference {worst:e}");
}

fn check_fd(chain: &Chain, q: &AxisValues, h: f64, errors: &MachineErrors, params: &[ErrorParam]) {
    let (jp, jd) = jacobian(chain, q, h, errors, params).unwrap();
    for (k, p) in params.iter().enumerate() {
        let step = if p.name().starts_with("EX")
            || p.name().starts_with("EY")
            || p.name().starts_with("EZ")
        {
            1e-4
        } else {
            1e-6
        };
        let plus = tool_point(chain, q, h, &errors.clone().with(*p, step)).unwrap();
        let minus = tool_point(chain, q, h, &errors.clone().with(*p, -step)).unwrap();
        let fp = (plus.point - minus.point) / (2.0 * step);
        let fd = (plus.direction - minus.direction) / (2.0 * step);
        for r in 0..3 {
            let scale = 1.0 + fp.norm();
            assert!(
                (jp[(r, k)] - fp[r]).abs() <= FD_REL * scale,
                "{} point[{r}]: analytic {} vs fd {}",
                p.name(),
                jp[(r, k)],
                fp[r]
            );
            assert!(
                (jd[(r, k)] - fd[r]).abs() <= FD_REL * (1.0 + fd.norm()),
                "{} direction[{r}]: analytic {} vs fd {}",
                p.name(),
                jd[(r, k)],
                fd[r]
            );
        }
    }
}

#[test]
fn jacobian_matches_finite_differences_of_exact_eq12() {
    // Every location error and every error motion (constant and linear) of the three machines,
    // at a non-zero error vector (the exact Jacobian, not only eq. 13 at ξ = 0).
    let machines = [
        (
            Chain::paper000(L0),
            AxisValues::xyzbc(-26.9, -21.2, 484.2, 0.2377, 0.0567),
        ),
        (
            Chain::paper002(),
            AxisValues::xyzbc(40.0, -30.0, 120.0, 0.3, -1.1),
        ),
        (
            Chain::paper001(200.0, 120.0),
            AxisValues {
                x: 30.0,
                y: -20.0,
                z: 50.0,
                a: 0.4,
                b: -0.25,
                c: 0.0,
            },
        ),
    ];
    for (chain, q) in machines {
        let mut params = testpiece::machine::direct::all_params(&chain);
        for a in chain.axes() {
            for c in AxisName::ALL {
                params.push(ErrorParam::Motion {
                    component: c,
                    axis: a.name,
                    power: 1,
                });
            }
        }
        let mut errors = MachineErrors::none();
        for (k, p) in params.iter().enumerate() {
            let v = if matches!(p, ErrorParam::Motion { power: 1, .. }) {
                1e-6
            } else {
                1e-4
            };
            errors = errors.with(
                *p,
                v * (1.0 + (k % 5) as f64) * if k % 2 == 0 { 1.0 } else { -1.0 },
            );
        }
        for h in [0.0, 16.0] {
            check_fd(&chain, &q, h, &errors, &params);
        }
    }
}

#[test]
fn paper002_error_motions_are_eq1() {
    // x_t = Rz(C + E_CC)·Ry(B + E_BB)·(x_m + E_XX, y_m + E_YY, z_m + E_ZZ): first-order agreement.
    let chain = Chain::paper002();
    let q = AxisValues::xyzbc(40.0, -30.0, 120.0, 0.3, -1.1);
    let (exx, eyy, ezz, ebb, ecc) = (0.01, -0.02, 0.015, 2e-5, -3e-5);
    let e = MachineErrors::none()
        .with_motion(&ErrorMotion::constant(AxisName::X, AxisName::X, exx))
        .with_motion(&ErrorMotion::constant(AxisName::Y, AxisName::Y, eyy))
        .with_motion(&ErrorMotion::constant(AxisName::Z, AxisName::Z, ezz))
        .with_motion(&ErrorMotion::constant(AxisName::B, AxisName::B, ebb))
        .with_motion(&ErrorMotion::constant(AxisName::C, AxisName::C, ecc));
    let got = tool_point(&chain, &q, 0.0, &e).unwrap().point;
    let rz = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), q.c + ecc);
    let ry = nalgebra::Rotation3::from_axis_angle(&Vector3::y_axis(), q.b + ebb);
    let want = rz * ry * Vector3::new(q.x + exx, q.y + eyy, q.z + ezz);
    // second-order terms: |ε|²·|p| ≈ 1e-9·150
    assert!((got - want).norm() < 1e-6, "{got} vs {want}");
}

#[test]
fn tool_direction_deviation_is_eq_s3_and_first_order_in_the_jacobian() {
    // Paper 004 eq. S3: ΔV = w(ξ) − w(0). Tilts of the B axis line (EA0B, EC0B) tilt the tool;
    // position errors (EX0B) and a pure positioning error of X (EXX) leave it unchanged.
    use testpiece::machine::direct::deviation;
    let chain = Chain::paper000(L0);
    let q = AxisValues::xyzbc(10.0, -20.0, 480.0, 0.3, 0.8);
    let tilt = MachineErrors::none().with(ErrorParam::parse("EA0B").unwrap(), 2e-4);
    let (dp, dv) = deviation(&chain, &q, 0.0, &tilt).unwrap();
    let (jp, jd) = jacobian(
        &chain,
        &q,
        0.0,
        &MachineErrors::none(),
        &[ErrorParam::parse("EA0B").unwrap()],
    )
    .unwrap();
    // Second-order remainder: |ξ|² = 4e-8.
    assert!(
        (dv - jd.column(0) * 2e-4).norm() < 1e-7 && dv.norm() > 1e-4,
        "{dv}"
    );
    // Position: |ξ|²·L0 = 2e-5 mm.
    assert!((dp - jp.column(0) * 2e-4).norm() < 5e-5);
    for p in ["EX0B", "EXX"] {
        let e = MachineErrors::none().with(ErrorParam::parse(p).unwrap(), 0.01);
        let (_, dv) = deviation(&chain, &q, 0.0, &e).unwrap();
        assert!(dv.norm() < 1e-15, "{p}: {dv}");
    }
}
