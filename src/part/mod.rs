//! Test pieces as data: the ISO 10791-7 S-shape (paper 000) and, later, the cone frustums
//! M3_15 / M3_45 (paper 002 Table 3).

pub mod frame;
pub mod points;
pub mod s_shape;

pub use frame::{Frame, FrameDerivs, Section};
pub use points::{builtin_points, Curve, MeasurementPoint};
pub use s_shape::{SShape, Surface, HEIGHT};
