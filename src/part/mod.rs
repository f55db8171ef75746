//! Test pieces as data: the ISO 10791-7 S-shape (paper 000) and the cone frustums M3_15 / M3_45
//! (paper 002 Table 3), both ruled parts ([`RuledPart`]) that the flank path, envelope and
//! projection accept.

pub mod cone;
pub mod flat;
pub mod frame;
pub mod points;
pub mod projection;
pub mod ruled;
pub mod s_shape;
pub mod scan;
pub mod start_rulings;

pub use cone::{ConeFrustum, ConePoint};
pub use flat::{Flat, FLAT_COLUMNS};
pub use frame::{Frame, FrameDerivs, Section};
pub use points::{builtin_points, curve_points_n, Curve, MeasurementPoint};
pub use projection::{project, project_on, Projection};
pub use ruled::RuledPart;
pub use s_shape::{SShape, Surface, HEIGHT};
pub use scan::ScanLayout;
