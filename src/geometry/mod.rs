//! Curves and surfaces of the test pieces (paper 000 §2): B-splines, ruled surfaces, frames,
//! closest-point projection. Units: mm; parameters unitless.

pub mod arc_length;
pub mod bspline;
pub mod length_series;

pub use arc_length::ArcLength;
pub use bspline::{BSplineCurve, CurveDerivs};

/// Failures of geometric construction and evaluation, with the offending values.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeometryError {
    #[error("a degree-{degree} B-spline needs more than {degree} control points, found {points}")]
    TooFewControlPoints { degree: usize, points: usize },
    #[error("{expected} knots expected for this degree and control-point count, found {knots}")]
    KnotCount { knots: usize, expected: usize },
    #[error("knot {index} = {value} is smaller than the previous knot {previous}")]
    KnotsNotIncreasing {
        index: usize,
        previous: f64,
        value: f64,
    },
    #[error("{weights} weights for {points} control points")]
    WeightCount { weights: usize, points: usize },
    #[error("weight {index} = {value} is not a positive finite number")]
    BadWeight { index: usize, value: f64 },
    #[error("the two curves have different degrees or knot vectors")]
    IncompatibleCurves,
    #[error("arc length {length} mm is outside the curve's length 0..{total} mm")]
    ArcLengthOutOfRange { length: f64, total: f64 },
    #[error("unknown measurement curve `{name}` (expected A_Z11, A_Z25, B_Z11 or B_Z25)")]
    UnknownCurve { name: String },
    #[error("cone frustum D = {bottom_diameter} mm, t = {thickness} mm, beta = {inclination} rad, theta = {half_apex} rad is not valid (needs D, t > 0, 0 < theta < pi/2, |beta| < pi/2, finite offsets; top radius {top_radius} mm must be > 0)")]
    BadCone {
        bottom_diameter: f64,
        thickness: f64,
        inclination: f64,
        half_apex: f64,
        top_radius: f64,
    },
    #[error("point ({x}, {y}, {z}) has a coordinate that is not a finite number")]
    NonFinitePoint { x: f64, y: f64, z: f64 },
    #[error("closest-point projection of ({x}, {y}, {z}) onto surface {surface} did not converge")]
    ProjectionDidNotConverge {
        x: f64,
        y: f64,
        z: f64,
        surface: &'static str,
    },
}
