//! Property tests of the closest-point projection onto the S-shape (paper 000 §4.1) for points
//! displaced from the surface in ANY direction by up to 3 mm (the in-crate proptest of
//! `geometry::projection` covers offsets along the normal): the foot lies on the surface
//! (S(u, v) within 1e-12 mm), the residual p − foot is parallel to the normal there (unless the
//! foot is clamped on an end ruling), and the foot is at least as close as the starting point.

use nalgebra::Vector3;
use proptest::prelude::*;
use testpiece::part::projection::project;
use testpiece::part::{SShape, Surface};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]
    #[test]
    fn projected_point_is_on_the_surface_along_the_normal(
        on_a in any::<bool>(), u in 0.01f64..0.99, v in 0.0f64..1.0,
        dir in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), len in 0.0f64..3.0,
    ) {
        let part = SShape::iso();
        let s = if on_a { Surface::A } else { Surface::B };
        let start = part.point_at(s, u, v);
        let d = Vector3::new(dir.0, dir.1, dir.2);
        prop_assume!(d.norm() > 1e-3);
        let p = start + d.normalize() * len;
        let pr = project(&part, &p).unwrap();
        // On the surface: the foot is S(u, v) of the reported parameters.
        prop_assert!((pr.foot - part.point_at(pr.surface, pr.u, pr.v)).norm() < 1e-12);
        // At least as close as the point we started from (a surface point at distance len).
        let dist = (p - pr.foot).norm();
        prop_assert!(dist <= len + 1e-9, "foot at {} mm, start at {} mm", dist, len);
        prop_assert!((pr.distance.abs() - dist).abs() < 1e-9 || pr.clamped);
        // Residual along the normal (sin of the angle below 1e-7, or a tiny residual).
        if !pr.clamped && dist > 1e-6 {
            let sin = (p - pr.foot).cross(&pr.normal).norm() / dist;
            prop_assert!(sin < 1e-7, "residual off the normal by sin = {}", sin);
        }
        prop_assert!((pr.normal.norm() - 1.0).abs() < 1e-12);
    }
}
