//! The corrected kinematic description written as a SINUMERIK orientable toolholder
//! (`$TC_CARR`, used by TRAORI and CYCLE800), its tool's length components, a cross-error
//! compensation (CEC) of the linear axes' squareness and the part program's work offset
//! (the parameters and their meaning: [`super::siemens_kinematics`]).
//!
//! From the chain with the entered location errors ([`crate::machine::axis_lines`], machine
//! frame, every axis at 0; the toolholder reference point and the machine reference point at
//! the machine zero):
//! - kinematic type: one rotary axis on each side `M` (axis 1 the head's, axis 2 the table's),
//!   two in the head `T`, two in the table `P` (axis 1 the one nearer the frame);
//! - `v1`, `v2`: the rotary lines' directions (the rotation vector of the moving body's positive
//!   motion);
//! - head: the tool's length vector `t = −o_tool` (nominal; tip → tool adapter); with the tip at
//!   the reference pose `p0` the tool adapter is at `p0 + t`; the pivots `c` are the rotation
//!   centres of the description; type `M`: `l2 = c1 − (p0 + t)`, `l1 = −c1`; type `T`:
//!   `l3 = c2 − (p0 + t)`, `l2 = c1 − c2`, `l1 = −c1`; type `P` (no head): `t = −p0`;
//! - table: type `M`: `l3 = c2`, `l4 = −l3`; type `P`: `l2 = c1`, `l3 = c2 − c1`,
//!   `l4 = −(l2 + l3)` (the chain closed: at zero angles the table's frame is the machine's);
//! - CEC: linear axis `a` moves the tool relative to the table along `r_a` (its direction in
//!   the description, reversed for an axis that carries the table); the controller, which
//!   assumes `e_a`, adds `q_a·(r_a − e_a)`: the slopes of the squareness table with `a` as
//!   input axis;
//! - work offset: the chain's workpiece frame at zero, `W0` (the table's location errors turn
//!   and shift it; a toolholder's table frame is the machine's at zero angles), as
//!   `x_table = R_w·x_part + t_w` with `R_w = Rz(γ)·Ry(β)·Rx(α)`;
//! - what has no home: the tool's direction at zero angles. A controller's tool points along
//!   `ẑ` at zero angles (G17); the chain's tool direction there, `d0`, tilts with the location
//!   errors of the axes that carry the head (a spindle tilt). Its `(x, y)` components are
//!   reported; the position of the tip is still reproduced (`l1`, `l2` take it).
//!
//! Exactness: the location-error matrix of paper 000 eq. 11 is orthogonal only to first order
//! (its entries `√(1 − a² − b²)` against the products `a·b` of two angles of one axis), so a
//! controller's rigid rotations reproduce the chain to `|ε|²·L` (≈ 5e-6 mm at 1e-4 rad over the
//! 500 mm of paper 000's head): [`crate::tolerance::CONTROLLER_POSE_MM`].

use nalgebra::{Matrix4, Vector3};

use super::siemens_kinematics::{KinematicType, Toolholder};
use crate::machine::axis_lines::{
    kinematic_description, rotation_centres, workpiece_frame_at_zero, AxisLine,
};
use crate::machine::{AxisName, Chain, MachineErrors, Side};

/// Why a chain has no orientable toolholder.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SiemensError {
    #[error(
        "chain {code}: {tool} rotary axes in the head and {table} in the table; an orientable \
         toolholder holds two (T: 2 + 0, P: 0 + 2, M: 1 + 1)"
    )]
    RotaryAxes {
        code: String,
        tool: usize,
        table: usize,
    },
    #[error(
        "chain {code}: linear axis {axis} is carried by a rotary axis; a toolholder's linear \
         axes move the tool reference point in the machine frame"
    )]
    LinearAfterRotary { code: String, axis: AxisName },
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// The `(α, β, γ)` of `R = Rz(γ)·Ry(β)·Rx(α)` (rad).
fn rpy(m: &Matrix4<f64>) -> [f64; 3] {
    [
        m[(2, 1)].atan2(m[(2, 2)]),
        (-m[(2, 0)]).clamp(-1.0, 1.0).asin(),
        m[(1, 0)].atan2(m[(0, 0)]),
    ]
}

/// The rotary lines of `side`, frame outwards.
fn rotary(axes: &[AxisLine], side: Side) -> Vec<&AxisLine> {
    axes.iter().filter(|a| a.rotary && a.side == side).collect()
}

/// Checks the chain's shape and returns its kinematic type.
pub fn kinematic_type(chain: &Chain) -> Result<KinematicType, SiemensError> {
    let count = |axes: &[crate::machine::ChainAxis]| {
        for (k, a) in axes.iter().enumerate() {
            let carried = axes[..k]
                .iter()
                .any(|b| b.name.kind() == crate::machine::AxisKind::Rotary);
            if carried && a.name.kind() == crate::machine::AxisKind::Linear {
                return Err(SiemensError::LinearAfterRotary {
                    code: chain.code().to_string(),
                    axis: a.name,
                });
            }
        }
        Ok(axes
            .iter()
            .filter(|a| a.name.kind() == crate::machine::AxisKind::Rotary)
            .count())
    };
    let (tool, table) = (count(chain.tool_axes())?, count(chain.workpiece_axes())?);
    match (tool, table) {
        (1, 1) => Ok(KinematicType::M),
        (2, 0) => Ok(KinematicType::T),
        (0, 2) => Ok(KinematicType::P),
        _ => Err(SiemensError::RotaryAxes {
            code: chain.code().to_string(),
            tool,
            table,
        }),
    }
}

/// The toolholder, CEC and work offset of `chain` with `errors` (module docs), and the tool's
/// direction at zero angles `d0` (unit), which no parameter holds.
pub fn toolholder(
    chain: &Chain,
    errors: &MachineErrors,
) -> Result<(Toolholder, [f64; 3]), SiemensError> {
    let kind = kinematic_type(chain)?;
    let d = kinematic_description(chain, errors);
    let p0 = Vector3::from(d.tool_tip);
    let t = -chain.tool_offset();
    let head = rotation_centres(&rotary(&d.axes, Side::Tool), Some(p0));
    let table = rotation_centres(&rotary(&d.axes, Side::Workpiece), None);
    let dir = |s: Side, k: usize| rotary(&d.axes, s).get(k).map_or([0.0; 3], |a| a.direction);
    let adapter = p0 + t;
    let z = Vector3::zeros();
    let (l1, l2, l3, l4, v1, v2, tool) = match kind {
        KinematicType::M => (
            -head[0],
            head[0] - adapter,
            table[0],
            -table[0],
            dir(Side::Tool, 0),
            dir(Side::Workpiece, 0),
            t,
        ),
        KinematicType::T => (
            -head[0],
            head[0] - head[1],
            head[1] - adapter,
            z,
            dir(Side::Tool, 0),
            dir(Side::Tool, 1),
            t,
        ),
        KinematicType::P => (
            z,
            table[0],
            table[1] - table[0],
            -table[1],
            dir(Side::Workpiece, 0),
            dir(Side::Workpiece, 1),
            -p0,
        ),
    };
    let mut cec = [[0.0; 3]; 3];
    for a in d.axes.iter().filter(|a| !a.rotary) {
        let k = a.axis.index();
        let sign = if a.side == Side::Tool { 1.0 } else { -1.0 };
        for (i, c) in cec[k].iter_mut().enumerate() {
            let e = if i == k { 1.0 } else { 0.0 };
            *c = sign * a.direction[i] - e;
        }
    }
    let w0 = workpiece_frame_at_zero(chain, errors);
    // The tool direction at zero angles: the head's factors at 0 applied to ẑ.
    let d0 = tool_direction_at_zero(chain, errors);
    Ok((
        Toolholder {
            kinematic_type: kind,
            l1: arr(&l1),
            l2: arr(&l2),
            l3: arr(&l3),
            l4: arr(&l4),
            v1,
            v2,
            tool: arr(&tool),
            cec,
            work_offset_translation: [w0[(0, 3)], w0[(1, 3)], w0[(2, 3)]],
            work_offset_rotation: rpy(&w0),
        },
        d0,
    ))
}

/// The chain's tool direction with every axis at 0, in the machine frame (unit).
fn tool_direction_at_zero(chain: &Chain, errors: &MachineErrors) -> [f64; 3] {
    let q = crate::machine::AxisValues::default();
    let w0 = workpiece_frame_at_zero(chain, errors);
    match crate::machine::direct::tool_point(chain, &q, 0.0, errors) {
        Ok(p) => {
            let v = w0.fixed_view::<3, 3>(0, 0) * p.direction;
            arr(&v.normalize())
        }
        Err(_) => [0.0, 0.0, 1.0],
    }
}

/// The programmed axes of a toolholder at the chain's axis values: `(X, Y, Z)` and the rotary
/// axes in the toolholder's order (axis 1, axis 2; rad).
pub fn toolholder_axes(
    chain: &Chain,
    kind: KinematicType,
    q: &crate::machine::AxisValues,
) -> ([f64; 3], [f64; 2]) {
    let rot = |axes: &[crate::machine::ChainAxis]| -> Vec<f64> {
        axes.iter()
            .filter(|a| a.name.kind() == crate::machine::AxisKind::Rotary)
            .map(|a| q.get(a.name))
            .collect()
    };
    let (t, w) = (rot(chain.tool_axes()), rot(chain.workpiece_axes()));
    let alpha = match kind {
        KinematicType::M => [t[0], w[0]],
        KinematicType::T => [t[0], t[1]],
        KinematicType::P => [w[0], w[1]],
    };
    (
        [q.get(AxisName::X), q.get(AxisName::Y), q.get(AxisName::Z)],
        alpha,
    )
}
