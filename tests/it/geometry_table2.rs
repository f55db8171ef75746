//! Paper 000 Table 2 (program TP6C2): the control points of the measurement curves at Z11 and
//! Z25, printed to 3 decimals. They are `(1-v)·P0_i + v·P1_i` with `v = 11/30` and `25/30`, an
//! independent check of the control points of s-shape.md and of the ruled-surface model
//! (a B-spline is linear in its control points, so `S(·, v)` is the spline of these points).
//!
//! Transcribed from `shared/papers/000_*.txt`. Surface A is fully legible; the OCR of the B block
//! is garbled, so only its legible first 14 rows are used. One printed value is a typo (s-shape.md):
//! A, 6th row, YH at Z25 is printed 46; the exact value is 48. Row 12 prints XH = 104.334 where
//! the exact value is 104.3333…, so the tolerance is 1e-3 (printed precision plus one rounding).

use nalgebra::Vector3;
use testpiece::assert_near;
use testpiece::part::{SShape, Surface};

/// (X, Y) at Z11 and (XH, YH) at Z25, surface A, rows 1-16.
const A_TABLE_2: [(f64, f64, f64, f64); 16] = [
    (-134.8, -95.5, -132.0, -95.5),
    (-131.067, -41.0, -127.333, -41.0),
    (-135.433, 23.0, -132.167, 23.0),
    (-117.267, 83.7, -116.333, 79.5),
    (-49.733, 81.433, -50.667, 78.167),
    (-21.9, 53.6, -20.5, 46.0), // YH printed 46: typo, exact 48
    (-11.0, 10.0, -11.0, 10.0),
    (-9.0, 2.0, -9.0, 2.0),
    (-7.0, -6.0, -7.0, -6.0),
    (-5.0, -14.0, -5.0, -14.0),
    (3.0, -46.0, 3.0, -46.0),
    (34.533, -85.067, 32.667, -81.333),
    (108.067, -82.9, 104.334, -81.5),
    (117.9, -13.0, 116.5, -13.0),
    (115.067, 43.0, 111.333, 43.0),
    (118.8, 99.5, 116.0, 99.5),
];

/// Surface B, rows 1-14 (legible part of the OCR).
const B_TABLE_2: [(f64, f64, f64, f64); 14] = [
    (-124.8, -95.5, -122.0, -95.5),
    (-121.433, -29.0, -118.167, -29.0),
    (-125.433, 30.0, -122.167, 30.0),
    (-107.633, 73.067, -107.167, 69.333),
    (-62.0, 71.433, -62.0, 68.167),
    (-32.267, 53.067, -31.333, 49.333),
    (-22.0, 12.0, -22.0, 12.0),
    (-20.0, 4.0, -20.0, 4.0),
    (-18.0, -4.0, -18.0, -4.0),
    (-16.0, -12.0, -16.0, -12.0),
    (-7.0, -48.0, -7.0, -48.0),
    (28.533, -92.433, 26.667, -89.167),
    (98.167, -94.8, 95.833, -92.0),
    (130.9, -44.533, 129.5, -42.667),
];

const PRINTED_MM: f64 = 1e-3;

fn interpolated(part: &SShape, s: Surface, i: usize, z: f64) -> Vector3<f64> {
    let [c0, c1] = part.curves(s);
    let v = z / 30.0;
    c0.control_points()[i] * (1.0 - v) + c1.control_points()[i] * v
}

#[test]
fn table_2_matches_the_interpolated_control_points() {
    let part = SShape::iso();
    let mut typos = Vec::new();
    for (s, rows) in [(Surface::A, &A_TABLE_2[..]), (Surface::B, &B_TABLE_2[..])] {
        for (i, &(x11, y11, x25, y25)) in rows.iter().enumerate() {
            let p11 = interpolated(&part, s, i, 11.0);
            let p25 = interpolated(&part, s, i, 25.0);
            assert_near!(p11.x, x11, PRINTED_MM);
            assert_near!(p11.y, y11, PRINTED_MM);
            assert_near!(p11.z, 11.0, 1e-12);
            assert_near!(p25.x, x25, PRINTED_MM);
            assert_near!(p25.z, 25.0, 1e-12);
            if (p25.y - y25).abs() > PRINTED_MM {
                typos.push((s, i + 1, y25, p25.y));
            } else {
                assert_near!(p25.y, y25, PRINTED_MM);
            }
        }
    }
    // exactly the one known typo: A, row 6, YH printed 46, exact 48
    assert_eq!(typos.len(), 1, "{typos:?}");
    let (s, row, printed, exact) = typos[0];
    assert_eq!((s, row, printed), (Surface::A, 6, 46.0));
    assert_near!(exact, 48.0, 1e-12);
}

#[test]
fn the_z_curves_are_the_splines_of_the_interpolated_points() {
    // S(u, v) equals the B-spline with control points (1-v)P0 + vP1 (linearity in the points).
    let part = SShape::iso();
    for s in Surface::BOTH {
        for z in [11.0, 25.0] {
            let pts: Vec<_> = (0..16).map(|i| interpolated(&part, s, i, z)).collect();
            let c = testpiece::geometry::BSplineCurve::clamped_uniform(3, pts).unwrap();
            for k in 0..=100 {
                let u = k as f64 / 100.0;
                let d = (c.point_at(u) - part.point_at(s, u, z / 30.0)).norm();
                assert_near!(d, 0.0, 1e-12);
            }
        }
    }
}
