//! The tool pose a SINUMERIK controller computes from an orientable toolholder data set
//! (`$TC_CARR1 … $TC_CARR23`), its cross-error compensation (CEC) and the work offset: an
//! implementation written from Siemens' published documentation only. It uses nothing of this
//! crate's machine model (no chain, no transform, no forward kinematics), so that it checks the
//! parameters [`super::siemens`] writes independently.
//!
//! Sources (read for the equations, nothing copied):
//! - SINUMERIK 840D, *Tool Offset (W1)* function manual, "Toolholder with orientation
//!   capability" (08/2005 ed., §2.5; system variables `$TC_CARR1..33`): offset vectors
//!   `l1 = $TC_CARR1..3`, `l2 = 4..6`, `l3 = 15..17`, `l4 = 18..20`; rotary axis vectors
//!   `v1 = $TC_CARR7..9`, `v2 = 10..12`; kinematic type `$TC_CARR23` = `T` (only the tool
//!   rotates), `P` (only the part), `M` (tool and part: mixed mode). "The angle of rotation is
//!   counted positively for clockwise rotation facing the direction of the rotation vector"
//!   (a right-handed rotation about `v`). "Vectors which describe offsets in the rotary head are
//!   positive in the direction from the tool tip to the reference point." With `$TC_CARR21/22`
//!   naming the machine's rotary axes their positions are the angles.
//! - SINUMERIK Operate commissioning manual (IM9, 03/2013), "Swiveling", offset vectors:
//!   swivel head: `l3` tool adapter → pivot of the 2nd rotary axis, `l2` 2nd → 1st pivot, `l1`
//!   closes the chain; swivel table: `l2` machine reference point → pivot of the 1st rotary
//!   axis, `l3` 1st → 2nd pivot, `l4` closes; mixed kinematics: `l2` tool adapter → pivot of the
//!   1st rotary axis (the head's: "with mixed kinematics, rotary axis 1 is always the axis for
//!   the tool orientation"), `l1` closes the head, `l3` machine reference point → pivot of the
//!   2nd rotary axis (the table's), `l4` closes the table. "Rotary axis 2 is based on rotary
//!   axis 1."
//! - SINUMERIK 840D sl *Extended Functions (K3)*, "Sag compensation / angularity compensation"
//!   (CEC): a table per input axis adds to an output axis a correction interpolated from the
//!   input axis's position; a squareness is the linear table `Δ_out = slope · q_in`.
//!
//! The model, as those pages give it (all vectors in the machine frame, mm; `R(v, α)` the
//! right-handed rotation by `α` about unit `v`; `P = (X, Y, Z)` the programmed linear axes,
//! the tool's motion relative to the table; `t` the tool's length vector from its tip to the
//! tool adapter, `ẑ` its orientation at zero angles, G17):
//! - head (types `T`, `M`): the resulting tool length vector (tip → toolholder reference point)
//!   is `L = l1 + R(v1, α1)·(l2 + R(v2, α2)·(l3 + t))` (type `T`) or `L = l1 + R(v1, α1)·(l2 + t)`
//!   (type `M`); type `P`: `L = l1 + t`. The tip is at `m = P + c(P) − L`, `c` the CEC
//!   correction, the tool direction (tip towards adapter) `R(v1, α1)·R(v2, α2)·ẑ` (`T`),
//!   `R(v1, α1)·ẑ` (`M`), `ẑ` (`P`);
//! - table (types `P`, `M`): a point `w` of the table's frame is at `m = l2 + R(v1, α1)·(l3 +
//!   R(v2, α2)·(l4 + w))` (`P`) or `m = l3 + R(v2, α2)·(l4 + w)` (`M`), inverted for the tip;
//! - work offset: the part's frame sits on the table's frame as `x_table = R_w·x_part + t_w`,
//!   `R_w = Rz(γ)·Ry(β)·Rx(α)`.

use serde::Serialize;

/// `$TC_CARR23`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum KinematicType {
    /// Only the tool rotates (two head axes).
    T,
    /// Only the part rotates (two table axes).
    P,
    /// Mixed: rotary axis 1 in the head, rotary axis 2 in the table.
    M,
}

/// One orientable toolholder data set, its tool and the compensations around it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Toolholder {
    pub kinematic_type: KinematicType,
    /// `$TC_CARR1..3`, `4..6`, `15..17`, `18..20` (mm).
    pub l1: [f64; 3],
    pub l2: [f64; 3],
    pub l3: [f64; 3],
    pub l4: [f64; 3],
    /// `$TC_CARR7..9`, `10..12` (direction; any length ≠ 0).
    pub v1: [f64; 3],
    pub v2: [f64; 3],
    /// The tool's length components (tool table, G17: tip → tool adapter; mm).
    pub tool: [f64; 3],
    /// CEC: `cec[a]` is the correction vector (mm per mm) added per unit travel of linear axis
    /// `a` (X, Y, Z).
    pub cec: [[f64; 3]; 3],
    /// Work offset: translation (mm) and rotation angles `(α, β, γ)` (rad) about x, y, z,
    /// `R_w = Rz(γ)·Ry(β)·Rx(α)`.
    pub work_offset_translation: [f64; 3],
    pub work_offset_rotation: [f64; 3],
}

type V = [f64; 3];

fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: V, s: f64) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `R(v, α)·x` (Rodrigues: `x cos α + (k × x) sin α + k (k·x)(1 − cos α)`, `k = v/|v|`).
fn rotate(v: V, alpha: f64, x: V) -> V {
    let n = dot(v, v).sqrt();
    if n == 0.0 {
        return x;
    }
    let k = scale(v, 1.0 / n);
    let (s, c) = alpha.sin_cos();
    add(
        add(scale(x, c), scale(cross(k, x), s)),
        scale(k, dot(k, x) * (1.0 - c)),
    )
}

/// `R_wᵀ·x` with `R_w = Rz(γ)·Ry(β)·Rx(α)`.
fn work_rotation_inverse(r: V, x: V) -> V {
    let x = rotate([0.0, 0.0, 1.0], -r[2], x);
    let x = rotate([0.0, 1.0, 0.0], -r[1], x);
    rotate([1.0, 0.0, 0.0], -r[0], x)
}

/// The tool tip and the unit tool direction (tip towards the adapter) in the part's frame
/// (mm), at the programmed linear axes `p = (X, Y, Z)` (mm) and rotary axes `alpha = (α1, α2)`
/// (rad; an absent axis 0), with the CEC correction applied (module docs).
pub fn tool_pose(h: &Toolholder, p: V, alpha: [f64; 2]) -> (V, V) {
    let [a1, a2] = alpha;
    let z = [0.0, 0.0, 1.0];
    let (len, dir) = match h.kinematic_type {
        KinematicType::T => (
            add(
                h.l1,
                rotate(h.v1, a1, add(h.l2, rotate(h.v2, a2, add(h.l3, h.tool)))),
            ),
            rotate(h.v1, a1, rotate(h.v2, a2, z)),
        ),
        KinematicType::M => (
            add(h.l1, rotate(h.v1, a1, add(h.l2, h.tool))),
            rotate(h.v1, a1, z),
        ),
        KinematicType::P => (add(h.l1, h.tool), z),
    };
    let cec = (0..3).fold([0.0; 3], |acc, a| add(acc, scale(h.cec[a], p[a])));
    let tip = sub(add(p, cec), len);
    // Into the table's frame (the inverse of its rotations), then the part's.
    let (tip_t, dir_t) = match h.kinematic_type {
        KinematicType::T => (tip, dir),
        KinematicType::M => (
            sub(rotate(h.v2, -a2, sub(tip, h.l3)), h.l4),
            rotate(h.v2, -a2, dir),
        ),
        KinematicType::P => (
            sub(
                rotate(h.v2, -a2, sub(rotate(h.v1, -a1, sub(tip, h.l2)), h.l3)),
                h.l4,
            ),
            rotate(h.v2, -a2, rotate(h.v1, -a1, dir)),
        ),
    };
    let r = h.work_offset_rotation;
    (
        work_rotation_inverse(r, sub(tip_t, h.work_offset_translation)),
        work_rotation_inverse(r, dir_t),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    fn holder(kind: KinematicType) -> Toolholder {
        Toolholder {
            kinematic_type: kind,
            l1: [0.0; 3],
            l2: [0.0; 3],
            l3: [0.0; 3],
            l4: [0.0; 3],
            v1: [0.0, 1.0, 0.0],
            v2: [0.0, 0.0, 1.0],
            tool: [0.0, 0.0, 100.0],
            cec: [[0.0; 3]; 3],
            work_offset_translation: [0.0; 3],
            work_offset_rotation: [0.0; 3],
        }
    }

    /// W1's type-P example (08/2005, §4.1): `l4 = (0, 0, 15)` rotated by B = 45° about y moves
    /// the zero point by X 15·sin 45° = 10.607 and Z −15·(1 − cos 45°) = −4.393. Here: a part
    /// point at the table's reference (w = 0) with l2 = −l4 lies at m = R·l4 − l4 (closed
    /// form, 1e-12 mm).
    #[test]
    fn the_w1_table_example_moves_the_zero_point() {
        let mut h = holder(KinematicType::P);
        h.v1 = [0.0, 1.0, 0.0];
        h.v2 = [0.0, 0.0, 0.0];
        h.l4 = [0.0, 0.0, 15.0];
        h.l2 = [0.0, 0.0, -15.0];
        h.tool = [0.0; 3];
        let b = 45f64.to_radians();
        let m = sub(add(h.l2, rotate(h.v1, b, h.l4)), [0.0; 3]);
        assert_near!(m[0], 10.607, 5e-4);
        assert_near!(m[2], -4.393, 5e-4);
        // The tool at that machine point is at the part's origin.
        let (tip, _) = tool_pose(&h, m, [b, 0.0]);
        assert_near!(dot(tip, tip).sqrt(), 0.0, 1e-12);
    }

    /// A mixed head with the pivot at the tool adapter, 100 mm above the tip at the origin
    /// (`l2 = 0`, `l1 = −pivot`): B = 90° about +y swings the tip about the pivot (0, 0, 100) to
    /// (0, 0, 100) + Ry(90°)·(0, 0, −100) = (−100, 0, 100), the direction from z to x (closed
    /// form, 1e-12).
    #[test]
    fn the_head_rotates_the_tool_about_its_pivot() {
        let mut h = holder(KinematicType::M);
        h.l1 = [0.0, 0.0, -100.0];
        h.l2 = [0.0, 0.0, 0.0];
        let (tip, dir) = tool_pose(&h, [0.0; 3], [90f64.to_radians(), 0.0]);
        assert_near!(tip[0], -100.0, 1e-12);
        assert_near!(tip[2], 100.0, 1e-12);
        assert_near!(dir[0], 1.0, 1e-12);
    }
}
