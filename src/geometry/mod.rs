//! Curves and surfaces of the test pieces (paper 000 §2): B-splines, ruled surfaces, frames,
//! closest-point projection. Units: mm; parameters unitless.

pub mod bspline;

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
}
