//! Axis rates along a tool path: `dq/du` by implicit differentiation of the inverse kinematics
//! (paper 000 eq. 9-10). The direct model maps the axis values `q` to the tool tip `T(q)` and the
//! tool direction `w(q)` in the workpiece frame; along the path `T(q(u)) = T_tool(u)` and
//! `w(q(u)) = R(u)`, so
//!
//! `[∂T/∂q; ∂w/∂q] · dq/du = [T_tool'(u); R'(u)]`,
//!
//! six equations (five independent: `w` is a unit vector) in the five axis rates, solved by least
//! squares. `∂T/∂q` and `∂w/∂q` are the direct model's Jacobian of the tool body
//! ([`super::direct::jacobian_body_point`] at the tip, for a change of each axis value).
//!
//! Where `w` is parallel to the outer rotary axis (the S-shape's vertical zone) the outer angle
//! does not follow from the pose: [`super::inverse::inverse_path`] interpolates it linearly in
//! `u`, so its rate is that interpolation's slope, given by the caller; the other four rates are
//! then solved with it. Units: mm and rad per unit `u`.

use nalgebra::Vector3;

use super::chain::{AxisName, AxisValues, Chain};
use super::direct::{jacobian_body_point, ErrorParam, MachineErrors};
use super::MachineError;

/// The axis rates `dq/du` at axis values `q` where the tool tip is `tip` (workpiece frame, mm)
/// and the path's tip and direction move by `tip_u` (mm per unit u) and `w_u` (per unit u).
/// `fixed`: an axis whose rate is imposed (the outer angle on a singular zone), and that rate.
pub fn axis_rates(
    chain: &Chain,
    q: &AxisValues,
    tip: &Vector3<f64>,
    tip_u: &Vector3<f64>,
    w_u: &Vector3<f64>,
    fixed: Option<(AxisName, f64)>,
) -> Result<AxisValues, MachineError> {
    let axes: Vec<AxisName> = chain.axes().map(|a| a.name).collect();
    let params: Vec<ErrorParam> = axes.iter().map(|&a| ErrorParam::axis_value(a)).collect();
    let (jp, jd) = jacobian_body_point(chain, q, tip, &MachineErrors::none(), &params)?;
    let mut rhs = [tip_u.x, tip_u.y, tip_u.z, w_u.x, w_u.y, w_u.z];
    let free: Vec<usize> = (0..axes.len())
        .filter(|&k| fixed.is_none_or(|(a, _)| a != axes[k]))
        .collect();
    let mut out = AxisValues::default();
    if let Some((a, rate)) = fixed {
        if let Some(k) = axes.iter().position(|&x| x == a) {
            for r in 0..3 {
                rhs[r] -= jp[(r, k)] * rate;
                rhs[r + 3] -= jd[(r, k)] * rate;
            }
            out.set(a, rate);
        }
    }
    let cols: Vec<[f64; 6]> = free
        .iter()
        .map(|&k| {
            let (p, d) = (jp.column(k), jd.column(k));
            [p[0], p[1], p[2], d[0], d[1], d[2]]
        })
        .collect();
    let x = least_squares(cols, rhs).ok_or(MachineError::SingularRates)?;
    for (c, &k) in free.iter().enumerate() {
        out.set(axes[k], x[c]);
    }
    Ok(out)
}

/// Least squares `min ‖A x − b‖` of six equations by Householder QR (`A` by columns): the
/// condition number is not squared as in the normal equations (the rotary columns are ~L0 mm/rad
/// beside 1 mm/mm, and nearly dependent next to the vertical zone). `None` when a column is
/// dependent on the ones before it.
fn least_squares(mut a: Vec<[f64; 6]>, mut b: [f64; 6]) -> Option<Vec<f64>> {
    let n = a.len();
    let scale = a
        .iter()
        .flat_map(|c| c.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    for k in 0..n {
        // The reflection that maps column k's rows k.. onto e_k.
        let norm = (k..6).map(|r| a[k][r] * a[k][r]).sum::<f64>().sqrt();
        if norm <= 1e-14 * scale {
            return None;
        }
        let alpha = if a[k][k] > 0.0 { -norm } else { norm };
        let mut v = [0.0; 6];
        v[k] = a[k][k] - alpha;
        v[(k + 1)..6].copy_from_slice(&a[k][(k + 1)..6]);
        let vv: f64 = (k..6).map(|r| v[r] * v[r]).sum();
        let reflect = |c: &mut [f64; 6]| {
            let f = 2.0 * (k..6).map(|r| v[r] * c[r]).sum::<f64>() / vv;
            for r in k..6 {
                c[r] -= f * v[r];
            }
        };
        for col in a.iter_mut().skip(k + 1) {
            reflect(col);
        }
        reflect(&mut b);
        a[k][k] = alpha;
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let sum: f64 = (k + 1..n).map(|c| a[c][k] * x[c]).sum();
        x[k] = (b[k] - sum) / a[k][k];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::chain::PAPER000_L0;
    use crate::machine::inverse::inverse_path;
    use crate::machine::Branch;
    use crate::part::{SShape, Surface};
    use crate::toolpath::flank::{tool_pose, tool_pose_derivs};

    /// The analytic rates against central differences of the inverse kinematics along the
    /// S-shape's flank path, for the three chains, both branches and both surfaces, inside and
    /// outside the vertical zone (where the outer rate is the interpolation's slope).
    #[test]
    fn rates_equal_finite_differences_of_the_inverse_kinematics() {
        let part = SShape::iso();
        let h = 1e-6;
        for chain in [
            Chain::paper000(PAPER000_L0),
            Chain::paper002(),
            Chain::paper001(120.0, 80.0),
        ] {
            for branch in [Branch::Signed, Branch::Positive] {
                for s in Surface::BOTH {
                    let pose = |u: f64| {
                        let p = tool_pose(&part, s, u);
                        (p.tip, p.axis)
                    };
                    let mut us = Vec::new();
                    let centres: Vec<f64> = (1..40).map(|k| k as f64 / 40.0 + 0.0037).collect();
                    for &u in &centres {
                        us.extend([u - h, u, u + h]);
                    }
                    let path = inverse_path(&chain, branch, pose, (0.0, 1.0), 260, &us).unwrap();
                    let pair = crate::machine::inverse::RotaryPair::of(&chain).unwrap();
                    for (c, &u) in centres.iter().enumerate() {
                        let (a, m, b) = (&path[3 * c], &path[3 * c + 1], &path[3 * c + 2]);
                        if a.singular != b.singular {
                            continue;
                        }
                        let d = tool_pose_derivs(&part, s, u);
                        let fixed = m.singular.then(|| {
                            let o = pair.outer;
                            (o, (b.values.get(o) - a.values.get(o)) / (2.0 * h))
                        });
                        let r =
                            axis_rates(&chain, &m.values, &d.pose.tip, &d.tip_u, &d.axis_u, fixed)
                                .unwrap();
                        for ax in chain.axes().map(|x| x.name) {
                            let fd = (b.values.get(ax) - a.values.get(ax)) / (2.0 * h);
                            let err = (r.get(ax) - fd).abs();
                            assert!(
                                err <= 1e-5 * (1.0 + fd.abs()),
                                "{} {branch:?} {s:?} u={u} {ax}: analytic {} fd {fd}",
                                chain.code(),
                                r.get(ax)
                            );
                        }
                    }
                }
            }
        }
    }
}
