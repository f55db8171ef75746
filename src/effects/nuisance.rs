//! Shapes no candidate names, kept for the model spread only (issue 29 item 3): the common
//! sources of a real part's structure that are not in effects.md's catalogue, each as a small
//! family of columns (mm per unit of each coefficient, one value per point).
//!
//! The diagnosis never names them; [`crate::final_fit::model_spread`] fits each beside the
//! location errors, as it fits the candidates, so that a structure of that kind (too small to be
//! seen, or seen and left `unexplained`) widens the std of the location errors it moves. The
//! families share the prior of one candidate (the spread's weights), and a family is never added
//! to a named answer's model: it is an alternative to the answer, not a second effect of it.
//! The families:
//! - **error motions of the linear axes** (ISO 230-1; paper 004 eq. S2), `E_{c,q}(q)` for each
//!   linear axis `q` and translation `c` as a cubic in `q`
//!   ([`crate::effects::machine::scale_and_motions`]): powers 2 and 3 across the axis (a
//!   straightness: its linear term is a squareness, a location error), 1 to 3 along it (a
//!   positioning error: its linear term is the scale candidate). A ballscrew's pitch error, a
//!   guideway's bow, a long cyclic error. Nearly collinear with the location errors, they are not
//!   alternatives of their own (noise alone would move the errors far in them): they are
//!   *pooled* into one random effect whose amplitude the part's residual says
//!   ([`crate::final_fit::pooled`]).
//! - **probing** ([`probing`]): a touch probe's pre-travel varying with the probing direction,
//!   the terms of order 2 and 3 of its Fourier series in the azimuth `φ` of the probing direction
//!   `−N` (order 0 is the tool radius, order 1 a shift of the part; a kinematic three-point probe
//!   triggers at three lobes: the probing form error ISO 10360-5 tests).
//! - **part drift** ([`drift`]): the part moving on the CMM table while it is measured, a rigid
//!   rotation about z and a shift growing linearly over the measuring order (the file's order):
//!   the setup error's columns times `x = k/(n − 1)` for the `k`-th point.

use nalgebra::DMatrix;

use crate::effects::EffectPoint;

/// One family of [`crate::effects::nuisance`] shapes: its id and its columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Nuisance {
    /// `probing`, `part_drift`, or `motion_E{c}{q}` (an error motion, ISO 230-1's name).
    pub id: String,
    pub columns: DMatrix<f64>,
    /// Pooled with the other pooled families into one random effect
    /// ([`crate::final_fit::pooled`]; the error motions), rather than fitted as an alternative
    /// of its own.
    pub pooled: bool,
}

/// The probing family: `cos 2φ`, `sin 2φ`, `cos 3φ`, `sin 3φ` (mm per mm of each coefficient),
/// `φ` the azimuth of `−N` in the part's xy plane.
pub fn probing(points: &[EffectPoint]) -> Nuisance {
    let phi: Vec<f64> = points.iter().map(|p| (-p.n.y).atan2(-p.n.x)).collect();
    let n = points.len();
    Nuisance {
        id: "probing".into(),
        pooled: false,
        columns: DMatrix::from_fn(n, 4, |i, j| {
            let k = (2 + j / 2) as f64;
            if j % 2 == 0 {
                libm::cos(k * phi[i])
            } else {
                libm::sin(k * phi[i])
            }
        }),
    }
}

/// The part-drift family: `x·(ẑ × p)·N` (mm per rad), `x·N_x`, `x·N_y` (mm per mm), `x = k/(n − 1)`
/// for the `k`-th point of `points` (the measuring order).
pub fn drift(points: &[EffectPoint]) -> Nuisance {
    let n = points.len();
    let x = |i: usize| {
        if n > 1 {
            i as f64 / (n - 1) as f64
        } else {
            0.0
        }
    };
    Nuisance {
        id: "part_drift".into(),
        pooled: false,
        columns: DMatrix::from_fn(n, 3, |i, j| {
            let p = &points[i];
            x(i) * match j {
                0 => -p.p.y * p.n.x + p.p.x * p.n.y,
                1 => p.n.x,
                _ => p.n.y,
            }
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn point(p: [f64; 3], n: [f64; 3]) -> EffectPoint {
        EffectPoint {
            p: Vector3::from(p),
            n: Vector3::from(n).normalize(),
            h: 15.0,
            s: 0.0,
            second: false,
        }
    }

    /// A normal along −x is probed along +x (φ = 0): `cos 2φ = cos 3φ = 1`, the sines 0; along
    /// −y (probed along +y, φ = 90°): `cos 2φ = −1`, `sin 3φ = −1` (exact to 1e-15).
    #[test]
    fn the_probing_columns_are_the_harmonics_of_the_probing_azimuth() {
        let f = probing(&[
            point([0.0; 3], [-1.0, 0.0, 0.0]),
            point([0.0; 3], [0.0, -1.0, 0.0]),
        ]);
        assert_eq!(f.columns.shape(), (2, 4));
        let want = [[1.0, 0.0, 1.0, 0.0], [-1.0, 0.0, 0.0, -1.0]];
        for (i, row) in want.iter().enumerate() {
            for (j, w) in row.iter().enumerate() {
                assert!(
                    (f.columns[(i, j)] - w).abs() < 1e-15,
                    "{i} {j}: {}",
                    f.columns
                );
            }
        }
    }

    /// The drift is nothing at the first point and the whole setup error's columns at the last:
    /// at `p = (10, 20, 0)` with `N = x̂`, `(ẑ × p)·N = −20`, `N_x = 1`, `N_y = 0`; half of
    /// them at the middle of three points (exact).
    #[test]
    fn the_drift_grows_over_the_measuring_order() {
        let q = point([10.0, 20.0, 0.0], [1.0, 0.0, 0.0]);
        let f = drift(&[q, q, q]);
        assert_eq!(
            f.columns.row(0).iter().copied().collect::<Vec<_>>(),
            [0.0; 3]
        );
        assert_eq!(
            f.columns.row(1).iter().copied().collect::<Vec<_>>(),
            [-10.0, 0.5, 0.0]
        );
        assert_eq!(
            f.columns.row(2).iter().copied().collect::<Vec<_>>(),
            [-20.0, 1.0, 0.0]
        );
    }
}
