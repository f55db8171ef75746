//! Tolerances used across tests and numerical checks, in one place (STYLE.md rule 9).
//! Units: mm for lengths, rad for angles.

/// Agreement with the reference points and normals of `../shared/reference/points.csv` (mm).
pub const POINTS_MM: f64 = 1e-6;
/// Agreement with `envelope.csv` (mm); also the refinement target of the envelope solver.
pub const ENVELOPE_MM: f64 = 1e-5;
/// Agreement with `envelope_surface_max.csv` (mm).
pub const SURFACE_MAX_MM: f64 = 1e-4;
/// Relative agreement of a sensitivity column with the reference, of that column's largest value.
pub const SENSITIVITY_REL: f64 = 1e-6;
/// Relative tolerance of an analytic derivative against a central finite difference.
pub const FD_REL: f64 = 1e-5;
/// Round trip of direct(inverse(pose)) (mm).
pub const KINEMATICS_MM: f64 = 1e-9;

/// `assert_near!(a, b, tol)`: `|a - b| <= tol`, printing both values and the difference.
#[macro_export]
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            (a - b).abs() <= tol,
            "assert_near!({}, {}): {} vs {} differ by {:e} > {:e}",
            stringify!($a),
            stringify!($b),
            a,
            b,
            (a - b).abs(),
            tol
        );
    }};
}
