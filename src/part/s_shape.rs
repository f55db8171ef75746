//! The ISO 10791-7:2020 S-shape test piece (paper 000 §2, eq. 1; control points from the NC
//! programs of its Table 1, as fixed in `shared/spec/s-shape.md`).
//!
//! Two ruled surfaces `S(u,v) = (1-v)·C0(u) + v·C1(u)`, `v = Z/30`, each between a bottom cubic
//! B-spline `C0` in the plane Z = 0 and a top one `C1` in Z = 30 (16 control points, clamped
//! uniform knots `{0,0,0,0, 1/13, …, 12/13, 1,1,1,1}`, weights 1). Units: mm.

use nalgebra::Vector3;

use crate::geometry::{BSplineCurve, GeometryError};

use super::frame::share_one_basis;

/// Height of the part: the top curves lie in Z = 30 mm.
pub const HEIGHT: f64 = 30.0;

/// Which of the two flank surfaces (surface A is block 1 of paper 000 Table 1, B is block 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Surface {
    A,
    B,
}

impl Surface {
    pub const BOTH: [Surface; 2] = [Surface::A, Surface::B];
    /// Position in [`Surface::BOTH`]: 0 for A, 1 for B (the index of a surface's pass, path or
    /// table in pairs kept in that order).
    pub fn index(self) -> usize {
        self as usize
    }
    /// Sign `s` of the outward normal `N = s·unit(R × T)`: +1 on A, -1 on B (s-shape.md).
    pub fn normal_sign(self) -> f64 {
        match self {
            Surface::A => 1.0,
            Surface::B => -1.0,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Surface::A => "A",
            Surface::B => "B",
        }
    }
}

const A_BOTTOM: [(f64, f64); 16] = [
    (-137.0, -95.5),
    (-134.0, -41.0),
    (-138.0, 23.0),
    (-118.0, 87.0),
    (-49.0, 84.0),
    (-23.0, 58.0),
    (-11.0, 10.0),
    (-9.0, 2.0),
    (-7.0, -6.0),
    (-5.0, -14.0),
    (3.0, -46.0),
    (36.0, -88.0),
    (111.0, -84.0),
    (119.0, -13.0),
    (118.0, 43.0),
    (121.0, 99.5),
];
const A_TOP: [(f64, f64); 16] = [
    (-131.0, -95.5),
    (-126.0, -41.0),
    (-131.0, 23.0),
    (-116.0, 78.0),
    (-51.0, 77.0),
    (-20.0, 46.0),
    (-11.0, 10.0),
    (-9.0, 2.0),
    (-7.0, -6.0),
    (-5.0, -14.0),
    (3.0, -46.0),
    (32.0, -80.0),
    (103.0, -81.0),
    (116.0, -13.0),
    (110.0, 43.0),
    (115.0, 99.5),
];
const B_BOTTOM: [(f64, f64); 16] = [
    (-127.0, -95.5),
    (-124.0, -29.0),
    (-128.0, 30.0),
    (-108.0, 76.0),
    (-62.0, 74.0),
    (-33.0, 56.0),
    (-22.0, 12.0),
    (-20.0, 4.0),
    (-18.0, -4.0),
    (-16.0, -12.0),
    (-7.0, -48.0),
    (30.0, -95.0),
    (100.0, -97.0),
    (132.0, -46.0),
    (127.0, 27.0),
    (131.0, 99.5),
];
const B_TOP: [(f64, f64); 16] = [
    (-121.0, -95.5),
    (-117.0, -29.0),
    (-121.0, 30.0),
    (-107.0, 68.0),
    (-62.0, 67.0),
    (-31.0, 48.0),
    (-22.0, 12.0),
    (-20.0, 4.0),
    (-18.0, -4.0),
    (-16.0, -12.0),
    (-7.0, -48.0),
    (26.0, -88.0),
    (95.0, -91.0),
    (129.0, -42.0),
    (118.0, 28.0),
    (125.0, 99.5),
];

fn curve(xy: &[(f64, f64); 16], z: f64) -> Result<BSplineCurve, GeometryError> {
    BSplineCurve::clamped_uniform(3, xy.iter().map(|&(x, y)| Vector3::new(x, y, z)).collect())
}

/// The two ruled surfaces of the S-shape, as the four boundary curves.
#[derive(Debug, Clone, PartialEq)]
pub struct SShape {
    /// `C0` (bottom, Z = 0) and `C1` (top, Z = 30) of surface A.
    a: [BSplineCurve; 2],
    /// `C0` and `C1` of surface B.
    b: [BSplineCurve; 2],
    /// Per surface ([`Surface::index`]), whether its two curves share one non-rational basis
    /// ([`super::frame::share_one_basis`]): decided once with the curves, not at each of the
    /// millions of sections a dense scan evaluates (comparing their weights and knots had been
    /// a third of a section's time, issue 31).
    one_basis: [bool; 2],
}

impl SShape {
    /// The nominal part of the spec.
    pub fn iso() -> Self {
        // The control points are constants checked by the tests: construction cannot fail.
        let build =
            |c: &[(f64, f64); 16], z| curve(c, z).expect("S-shape control points are valid");
        Self::new(
            [build(&A_BOTTOM, 0.0), build(&A_TOP, HEIGHT)],
            [build(&B_BOTTOM, 0.0), build(&B_TOP, HEIGHT)],
        )
    }

    /// The part of surfaces A and B, each given by its bottom and top curves `[C0, C1]`.
    pub(crate) fn new(a: [BSplineCurve; 2], b: [BSplineCurve; 2]) -> Self {
        let one_basis = [share_one_basis(&a), share_one_basis(&b)];
        Self { a, b, one_basis }
    }

    /// Whether the two curves of surface `s` share one non-rational basis (see the field).
    pub(crate) fn one_basis(&self, s: Surface) -> bool {
        self.one_basis[s.index()]
    }

    /// Bottom and top curves of one surface.
    pub fn curves(&self, s: Surface) -> &[BSplineCurve; 2] {
        match s {
            Surface::A => &self.a,
            Surface::B => &self.b,
        }
    }

    /// `S(u, v) = (1-v)·C0(u) + v·C1(u)` (mm), `v = Z/30`.
    pub fn point_at(&self, s: Surface, u: f64, v: f64) -> Vector3<f64> {
        let [c0, c1] = self.curves(s);
        c0.point_at(u) * (1.0 - v) + c1.point_at(u) * v
    }

    /// Length of the curve `v = const` on surface `s` over `u ∈ [0, 1]` (mm), by 5-point
    /// Gauss–Legendre on `per_span` equal parts of each knot span (the integrand is smooth
    /// inside a span, so the rule converges fast there).
    pub fn curve_length(&self, s: Surface, v: f64, per_span: usize) -> f64 {
        const X: [f64; 5] = [
            0.0,
            -0.538_469_310_105_683_1,
            0.538_469_310_105_683_1,
            -0.906_179_845_938_664,
            0.906_179_845_938_664,
        ];
        const W: [f64; 5] = [
            0.568_888_888_888_888_9,
            0.478_628_670_499_366_47,
            0.478_628_670_499_366_47,
            0.236_926_885_056_189_08,
            0.236_926_885_056_189_08,
        ];
        let [c0, c1] = self.curves(s);
        let mut knots = c0.knots().to_vec();
        knots.dedup();
        let mut pieces = Vec::new();
        for w in knots.windows(2) {
            let h = (w[1] - w[0]) / per_span as f64;
            pieces.extend((0..per_span).map(|k| (w[0] + (k as f64 + 0.5) * h, h)));
        }
        pieces
            .into_iter()
            .map(|(mid, h)| {
                X.iter()
                    .zip(W)
                    .map(|(x, w)| {
                        let u = mid + 0.5 * h * x;
                        let d = c0.derivs_at(u).d1 * (1.0 - v) + c1.derivs_at(u).d1 * v;
                        w * d.norm()
                    })
                    .sum::<f64>()
                    * 0.5
                    * h
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn ends_are_the_first_and_last_control_points() {
        let p = SShape::iso();
        let a = p.point_at(Surface::A, 0.0, 0.0);
        assert_near!(a.x, -137.0, 1e-12);
        assert_near!(a.y, -95.5, 1e-12);
        let b = p.point_at(Surface::B, 1.0, 1.0);
        assert_near!(b.x, 125.0, 1e-12);
        assert_near!(b.z, 30.0, 1e-12);
    }

    #[test]
    fn curve_length_converges() {
        let p = SShape::iso();
        let l1 = p.curve_length(Surface::A, 11.0 / 30.0, 8);
        let l2 = p.curve_length(Surface::A, 11.0 / 30.0, 32);
        assert_near!(l1, l2, 1e-9);
        // The part spans about 195 mm in y and 250 mm in x; the S is longer than its chord.
        assert!(l1 > 300.0 && l1 < 800.0, "length {l1}");
    }
}
