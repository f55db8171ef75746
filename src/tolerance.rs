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

/// The plan's predicted std against the identification of a part measured with the plan
/// (relative; the design is rebuilt from the file by projection, which recovers `u` to ~1e-12).
pub const PLAN_STD_REL: f64 = 1e-9;
/// Tool tips of a part program's G-code replayed as an NC trace against its CL (mm), beyond the
/// program's own rounding bound (`Program::rounding_bound`, from its words' decimals).
pub const GCODE_REPLAY_MM: f64 = 1e-9;
/// The predicted part after compensation against the exact eq. 12 simulation of the
/// compensated machine (mm): the exact and linear models differ by < 0.3 µm at |ξ| ≤ 3e-4 rad.
pub const COMPENSATED_PART_MM: f64 = 5e-4;

/// A controller's rigid-body model (SINUMERIK toolholder, CEC, work offset) against the chain
/// with the same location errors (mm): eq. 11's matrix is orthogonal only to first order, its
/// second-order terms `ε_a·ε_b` ≤ (3e-4)² rad² over paper 000's 500 mm head give 4.5e-5 mm.
pub const CONTROLLER_POSE_MM: f64 = 5e-5;

/// The physics generator's servo loops against the time-domain columns of
/// `servo_signatures.csv` (mm): the reference README's own convergence of those columns
/// ("halving the step changes the columns by ≤ 0.001 µm").
pub const SERVO_COLUMNS_MM: f64 = 1e-6;
