//! Homogeneous transforms of the chain (4×4, mm and rad): translations, rotations about a
//! coordinate axis, the location-error matrix of paper 000 eq. 11 and its derivatives, and the
//! small-angle error-motion matrix of paper 004 eq. S2.

use nalgebra::{Matrix3, Matrix4, Vector3};

/// `Trans(v)`: translation by `v` (mm).
pub(crate) fn translation(v: &Vector3<f64>) -> Matrix4<f64> {
    let mut m = Matrix4::identity();
    m[(0, 3)] = v.x;
    m[(1, 3)] = v.y;
    m[(2, 3)] = v.z;
    m
}

/// Right-handed rotation by `angle` (rad) about coordinate axis `k` (0 = x, 1 = y, 2 = z):
/// `Rx` rows (1,0,0) (0,c,-s) (0,s,c); `Ry` rows (c,0,s) (0,1,0) (-s,0,c); `Rz` rows
/// (c,-s,0) (s,c,0) (0,0,1) (paper 000 eq. 8 `ZT_B`).
pub(crate) fn rotation3(k: usize, angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    match k {
        0 => Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c),
        1 => Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c),
        _ => Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0),
    }
}

pub(crate) fn rotation(k: usize, angle: f64) -> Matrix4<f64> {
    let mut m = Matrix4::identity();
    m.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&rotation3(k, angle));
    m
}

/// Paper 000 eq. 11: `D = [[√(1-B²-C²), -C, B, X], [C, √(1-A²-C²), -A, Y],
/// [-B, A, √(1-A²-B²), Z], [0,0,0,1]]` with `e = (X, Y, Z, A, B, C)` = (EX0i, EY0i, EZ0i, EA0i,
/// EB0i, EC0i) of one axis (mm, rad). Not exactly orthogonal: eq. 12 is evaluated with it as
/// printed (the reference's `machine_exact`).
pub(crate) fn location_matrix(e: &[f64; 6]) -> Matrix4<f64> {
    let [x, y, z, a, b, c] = *e;
    Matrix4::new(
        (1.0 - b * b - c * c).sqrt(),
        -c,
        b,
        x,
        c,
        (1.0 - a * a - c * c).sqrt(),
        -a,
        y,
        -b,
        a,
        (1.0 - a * a - b * b).sqrt(),
        z,
        0.0,
        0.0,
        0.0,
        1.0,
    )
}

/// `∂D/∂e_k` of [`location_matrix`] at `e` (k = 0..6 in the order X, Y, Z, A, B, C).
pub(crate) fn location_matrix_derivative(e: &[f64; 6], k: usize) -> Matrix4<f64> {
    let [_, _, _, a, b, c] = *e;
    let mut m = Matrix4::zeros();
    let d00 = || (1.0 - b * b - c * c).sqrt();
    let d11 = || (1.0 - a * a - c * c).sqrt();
    let d22 = || (1.0 - a * a - b * b).sqrt();
    match k {
        0..=2 => m[(k, 3)] = 1.0,
        3 => {
            m[(1, 1)] = -a / d11();
            m[(2, 2)] = -a / d22();
            m[(1, 2)] = -1.0;
            m[(2, 1)] = 1.0;
        }
        4 => {
            m[(0, 0)] = -b / d00();
            m[(2, 2)] = -b / d22();
            m[(0, 2)] = 1.0;
            m[(2, 0)] = -1.0;
        }
        _ => {
            m[(0, 0)] = -c / d00();
            m[(1, 1)] = -c / d11();
            m[(0, 1)] = -1.0;
            m[(1, 0)] = 1.0;
        }
    }
    m
}

/// Paper 004 eq. S2 error-motion matrix, first order in the angles:
/// `[[1, -εz, εy, δx], [εz, 1, -εx, δy], [-εy, εx, 1, δz], [0,0,0,1]]`,
/// `m = (δx, δy, δz, εx, εy, εz)` (mm, rad).
pub(crate) fn motion_matrix(m: &[f64; 6]) -> Matrix4<f64> {
    let [dx, dy, dz, ex, ey, ez] = *m;
    Matrix4::new(
        1.0, -ez, ey, dx, ez, 1.0, -ex, dy, -ey, ex, 1.0, dz, 0.0, 0.0, 0.0, 1.0,
    )
}

/// `∂E/∂m_k` of [`motion_matrix`] (constant: the matrix is linear in `m`).
pub(crate) fn motion_matrix_derivative(k: usize) -> Matrix4<f64> {
    let mut m = Matrix4::zeros();
    match k {
        0..=2 => m[(k, 3)] = 1.0,
        3 => {
            m[(1, 2)] = -1.0;
            m[(2, 1)] = 1.0;
        }
        4 => {
            m[(0, 2)] = 1.0;
            m[(2, 0)] = -1.0;
        }
        _ => {
            m[(0, 1)] = -1.0;
            m[(1, 0)] = 1.0;
        }
    }
    m
}

/// Inverse of an affine 4×4 `[[A, t], [0, 1]]`: `[[A⁻¹, -A⁻¹t], [0, 1]]`, or `None` when `A` is
/// singular.
pub(crate) fn affine_inverse(m: &Matrix4<f64>) -> Option<Matrix4<f64>> {
    let a: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into_owned();
    let ai = a.try_inverse()?;
    let t: Vector3<f64> = m.fixed_view::<3, 1>(0, 3).into_owned();
    let mut r = Matrix4::identity();
    r.fixed_view_mut::<3, 3>(0, 0).copy_from(&ai);
    r.fixed_view_mut::<3, 1>(0, 3).copy_from(&(-(ai * t)));
    Some(r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::FD_REL;

    #[test]
    fn location_matrix_derivatives_match_finite_differences() {
        let e = [0.01, -0.02, 0.03, 2e-3, -3e-3, 1.5e-3];
        for k in 0..6 {
            let h = 1e-6;
            let mut ep = e;
            let mut em = e;
            ep[k] += h;
            em[k] -= h;
            let fd = (location_matrix(&ep) - location_matrix(&em)) / (2.0 * h);
            let an = location_matrix_derivative(&e, k);
            for (x, y) in an.iter().zip(fd.iter()) {
                assert_near!(*x, *y, FD_REL * (1.0 + x.abs()));
            }
        }
    }

    #[test]
    fn affine_inverse_is_an_inverse() {
        let m = translation(&Vector3::new(1.0, 2.0, 3.0))
            * rotation(1, 0.3)
            * location_matrix(&[0.1, 0.2, 0.3, 1e-3, 2e-3, 3e-3]);
        let p = m * affine_inverse(&m).unwrap() - Matrix4::identity();
        assert!(p.norm() < 1e-14, "{p}");
    }
}

/// A rigid motion `x ↦ R·x + t` on plain arrays: the nominal chain evaluated without the 4×4
/// machinery (fast also in unoptimised builds; the inverse kinematics calls it per path sample).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rigid {
    r: [[f64; 3]; 3],
    t: [f64; 3],
}

impl Rigid {
    pub(crate) const IDENTITY: Rigid = Rigid {
        r: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        t: [0.0; 3],
    };
    pub(crate) fn translation(v: &Vector3<f64>) -> Self {
        Rigid {
            t: [v.x, v.y, v.z],
            ..Self::IDENTITY
        }
    }
    /// Same convention as [`rotation3`].
    pub(crate) fn rotation(k: usize, angle: f64) -> Self {
        let (s, c) = angle.sin_cos();
        let r = match k {
            0 => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
            1 => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
            _ => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
        };
        Rigid { r, t: [0.0; 3] }
    }
    /// `self ∘ o` (apply `o` first).
    pub(crate) fn then(&self, o: &Rigid) -> Rigid {
        let col = |j: usize| [o.r[0][j], o.r[1][j], o.r[2][j]];
        let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let row = |i: usize| {
            let a = &self.r[i];
            [dot(a, &col(0)), dot(a, &col(1)), dot(a, &col(2))]
        };
        let tr = |i: usize| dot(&self.r[i], &o.t) + self.t[i];
        Rigid {
            r: [row(0), row(1), row(2)],
            t: [tr(0), tr(1), tr(2)],
        }
    }
    pub(crate) fn inverse(&self) -> Rigid {
        let m = &self.r;
        let r = [
            [m[0][0], m[1][0], m[2][0]],
            [m[0][1], m[1][1], m[2][1]],
            [m[0][2], m[1][2], m[2][2]],
        ];
        let t = |i: usize| -(r[i][0] * self.t[0] + r[i][1] * self.t[1] + r[i][2] * self.t[2]);
        Rigid {
            r,
            t: [t(0), t(1), t(2)],
        }
    }
    pub(crate) fn point(&self, v: &Vector3<f64>) -> Vector3<f64> {
        let p = [v.x, v.y, v.z];
        let f = |i: usize| (0..3).map(|k| self.r[i][k] * p[k]).sum::<f64>() + self.t[i];
        Vector3::new(f(0), f(1), f(2))
    }
    pub(crate) fn vector(&self, v: &Vector3<f64>) -> Vector3<f64> {
        let p = [v.x, v.y, v.z];
        let f = |i: usize| (0..3).map(|k| self.r[i][k] * p[k]).sum::<f64>();
        Vector3::new(f(0), f(1), f(2))
    }
}
