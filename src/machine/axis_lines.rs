//! The chain as a controller's kinematic description holds it: where each axis is and which way
//! it points, in the machine frame `b` with every axis at 0, with or without location errors.
//!
//! For axis `i` the frame of its line is `P_i = Π_{j before i} F_j(0) · Trans(o_i) · D_i`
//! ([`super::chain`]: `F_j(q) = Trans(o_j) D_j M_j(q) E_j(q)`, the factors from the frame `b`
//! towards the workpiece or the tool; `M_j(0) = I`; error motions are not part of a location
//! description and are left out). A rotary axis's line passes through `P_i·(0, 0, 0, 1)` along
//! `P_i·(e_k, 0)`; a linear axis moves along `P_i·(e_k, 0)`. Directions are given in the sense of
//! the body's positive motion (`sign · e_k`, `sign = −1` for a primed axis). The point reported
//! for a rotary line is its point nearest the machine origin (one point per line, so that two
//! descriptions compare point by point). The tool tip at the reference pose is
//! `Π_tool F_j(0) · (o_tool, 1)`. With the location errors `D_i` of paper 000 eq. 11 (exact),
//! the description is the real machine's; without, the nominal one. Units: mm, unit vectors.
//!
//! **Offset vectors** ([`OffsetVector`]), the form a five-axis controller's kinematic
//! transformation chains them (machine zero → rotation centres → tool tip): on each side, the
//! rotation centre of a rotary axis is the foot of the common perpendicular with the other
//! rotary axis of the same side (two axes: a head's or a table's pair), else, alone on its
//! side, the foot of the perpendicular from the tool tip (tool side) or from the machine origin
//! (workpiece side). The vectors run machine zero → first centre → second centre (→ tool tip
//! on the tool side). Parallel lines have no common perpendicular: their points nearest the
//! origin are used.

use nalgebra::{Matrix4, Vector3, Vector4};
use serde::Serialize;

use super::chain::{AxisKind, AxisName, Chain, ChainAxis, Side};
use super::direct::{ErrorParam, MachineErrors};
use super::transform::{location_matrix, translation};

/// One axis of the description.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxisLine {
    pub axis: AxisName,
    pub side: Side,
    pub rotary: bool,
    /// Rotary axis: the point of its line nearest the machine origin (mm); `None` for a linear
    /// axis (a direction only).
    pub point: Option<[f64; 3]>,
    /// Unit direction of positive motion (linear) or of the rotation vector (rotary).
    pub direction: [f64; 3],
}

/// One offset vector of the description (mm, machine frame): from a reference point to the
/// next (`machine zero`, `<axis> centre`, `tool tip`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OffsetVector {
    pub from: String,
    pub to: String,
    pub vector: [f64; 3],
}

/// The kinematic description of a chain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KinematicDescription {
    pub code: String,
    /// Axes from the frame outwards: the workpiece side, then the tool side.
    pub axes: Vec<AxisLine>,
    /// Tool tip at the reference pose (all axes 0), machine frame (mm).
    pub tool_tip: [f64; 3],
    /// Machine zero → rotation centres (→ tool tip), per side (module docs).
    pub offsets: Vec<OffsetVector>,
}

/// The feet on lines `(p, d)` and `(q, e)` (unit directions) of their common perpendicular;
/// `None` for parallel lines.
pub fn common_perpendicular(
    (p, d): (Vector3<f64>, Vector3<f64>),
    (q, e): (Vector3<f64>, Vector3<f64>),
) -> Option<(Vector3<f64>, Vector3<f64>)> {
    let b = d.dot(&e);
    let den = 1.0 - b * b;
    if den < 1e-12 {
        return None;
    }
    let w = p - q;
    let (dw, ew) = (d.dot(&w), e.dot(&w));
    let s = (b * ew - dw) / den;
    let t = (ew - b * dw) / den;
    Some((p + d * s, q + e * t))
}

/// The foot of the perpendicular from `x` on the line `(p, d)` (unit `d`).
fn foot(x: &Vector3<f64>, (p, d): (Vector3<f64>, Vector3<f64>)) -> Vector3<f64> {
    p + d * (x - p).dot(&d)
}

/// The rotation centres of one side's rotary lines, in order (module docs); `tip` on the tool
/// side.
pub fn rotation_centres(lines: &[&AxisLine], tip: Option<Vector3<f64>>) -> Vec<Vector3<f64>> {
    let line = |l: &AxisLine| {
        (
            Vector3::from(l.point.unwrap_or([0.0; 3])),
            Vector3::from(l.direction),
        )
    };
    match lines {
        [a, b] => match common_perpendicular(line(a), line(b)) {
            Some((x, y)) => vec![x, y],
            None => vec![line(a).0, line(b).0],
        },
        [a] => vec![match tip {
            Some(t) => foot(&t, line(a)),
            None => line(a).0,
        }],
        _ => lines.iter().map(|l| line(l).0).collect(),
    }
}

/// The offset vectors of one side's rotary lines (module docs); `tip` on the tool side.
fn side_offsets(lines: &[&AxisLine], tip: Option<Vector3<f64>>) -> Vec<OffsetVector> {
    let centres = rotation_centres(lines, tip);
    let mut names: Vec<String> = vec!["machine zero".to_string()];
    names.extend(lines.iter().map(|l| format!("{} centre", l.axis)));
    let mut pts = vec![Vector3::zeros()];
    pts.extend(centres);
    if let Some(t) = tip {
        names.push("tool tip".to_string());
        pts.push(t);
    }
    (1..pts.len())
        .map(|k| OffsetVector {
            from: names[k - 1].clone(),
            to: names[k].clone(),
            vector: arr(&(pts[k] - pts[k - 1])),
        })
        .collect()
}

/// The location-error vector `(X, Y, Z, A, B, C)` of `axis` in `errors` (mm, rad).
fn location_of(errors: &MachineErrors, axis: AxisName) -> [f64; 6] {
    let mut e = [0.0; 6];
    for (p, v) in &errors.values {
        if let ErrorParam::Location(l) = p {
            if l.axis == axis {
                e[l.component_index()] += v;
            }
        }
    }
    e
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// The lines of one side, in the order of its factors (frame outwards), and the product of
/// all its factors at `q = 0`.
fn side_lines(axes: &[ChainAxis], errors: &MachineErrors) -> (Vec<AxisLine>, Matrix4<f64>) {
    let mut prefix = Matrix4::identity();
    let mut out = Vec::new();
    for a in axes {
        let p: Matrix4<f64> =
            prefix * translation(&a.offset) * location_matrix(&location_of(errors, a.name));
        let mut e: Vector4<f64> = Vector4::zeros();
        e[a.name.direction()] = a.sign;
        let d: Vector3<f64> = (p * e).xyz().normalize();
        let rotary = a.name.kind() == AxisKind::Rotary;
        let point = rotary.then(|| {
            let o: Vector3<f64> = (p * Vector4::new(0.0, 0.0, 0.0, 1.0)).xyz();
            arr(&(o - d * o.dot(&d)))
        });
        out.push(AxisLine {
            axis: a.name,
            side: a.side,
            rotary,
            point,
            direction: arr(&d),
        });
        prefix = p;
    }
    (out, prefix)
}

/// The workpiece frame in the machine frame `b` with every axis at 0: the product of the
/// workpiece side's factors `Trans(o_i)·D_i` (module docs), with the location errors of `errors`.
/// A controller that holds the rotary axes' lines but not this frame needs it as the part
/// program's work offset.
pub fn workpiece_frame_at_zero(chain: &Chain, errors: &MachineErrors) -> Matrix4<f64> {
    side_lines(chain.workpiece_axes(), errors).1
}

/// The description of `chain` with the location errors of `errors` (none: the nominal one).
pub fn kinematic_description(chain: &Chain, errors: &MachineErrors) -> KinematicDescription {
    let (mut axes, _) = side_lines(chain.workpiece_axes(), errors);
    let (tool, t) = side_lines(chain.tool_axes(), errors);
    axes.extend(tool);
    let o = chain.tool_offset();
    let tip: Vector3<f64> = (t * Vector4::new(o.x, o.y, o.z, 1.0)).xyz();
    let rotary_on = |side: Side| -> Vec<&AxisLine> {
        axes.iter().filter(|a| a.rotary && a.side == side).collect()
    };
    let mut offsets = side_offsets(&rotary_on(Side::Workpiece), None);
    offsets.extend(side_offsets(&rotary_on(Side::Tool), Some(tip)));
    KinematicDescription {
        code: chain.code().to_string(),
        tool_tip: arr(&tip),
        offsets,
        axes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::machine::chain::PAPER000_L0;
    use crate::machine::direct::nominal;
    use crate::machine::{AxisValues, LocationError};

    /// Paper 000's machine: nominal B line through the origin along +y, C along +z, the tip L0
    /// below; with EX0B = 0.03 mm the B line moves 0.03 mm along x, with EA0B = 3e-4 rad it
    /// turns about x (direction (0, cos, sin) to first order: (0, 1, 3e-4)), and the tip follows
    /// the B line (closed form, 1e-12).
    #[test]
    fn paper000_lines_move_with_their_location_errors() {
        let chain = Chain::paper000(PAPER000_L0);
        let nom = kinematic_description(&chain, &MachineErrors::none());
        let b = nom.axes.iter().find(|a| a.axis == AxisName::B).unwrap();
        assert_eq!(b.point, Some([0.0, 0.0, 0.0]));
        assert_eq!(b.direction, [0.0, 1.0, 0.0]);
        let c = nom.axes.iter().find(|a| a.axis == AxisName::C).unwrap();
        assert_eq!(c.direction, [0.0, 0.0, 1.0]);
        assert_near!(nom.tool_tip[2], -PAPER000_L0, 1e-12);
        // The tip at the reference pose is the direct kinematics' at q = 0 (workpiece = frame).
        let p = nominal(&chain, &AxisValues::default(), 0.0).point;
        assert_near!((p - Vector3::from(nom.tool_tip)).norm(), 0.0, 1e-12);
        let e = MachineErrors::none()
            .with(
                ErrorParam::Location(LocationError::new(AxisName::X, AxisName::B)),
                0.03,
            )
            .with(
                ErrorParam::Location(LocationError::new(AxisName::A, AxisName::B)),
                3e-4,
            );
        let real = kinematic_description(&chain, &e);
        let b = real.axes.iter().find(|a| a.axis == AxisName::B).unwrap();
        let pt = b.point.unwrap();
        assert_near!(pt[0], 0.03, 1e-12);
        assert_near!(b.direction[2], 3e-4, 1e-12);
        assert_near!(b.direction[1], (1.0 - 9e-8f64).sqrt(), 1e-12);
        assert_near!(real.tool_tip[0], 0.03, 1e-12);
        // Offsets: machine zero → C centre (workpiece side), machine zero → B centre → tip.
        let names: Vec<(&str, &str)> = real
            .offsets
            .iter()
            .map(|o| (o.from.as_str(), o.to.as_str()))
            .collect();
        assert_eq!(
            names,
            [
                ("machine zero", "C centre"),
                ("machine zero", "B centre"),
                ("B centre", "tool tip")
            ]
        );
        // B centre → tip is perpendicular to the B line and L0 long (the tip is on the tool
        // axis, L0 from the pivot, 1e-9 mm).
        let v = Vector3::from(real.offsets[2].vector);
        assert_near!(v.norm(), PAPER000_L0, 1e-9);
        assert_near!(v.dot(&Vector3::from(b.direction)), 0.0, 1e-9);
    }

    /// Two skew lines: x-axis and the line through (0, 0, 1) along y: feet (0,0,0), (0,0,1);
    /// parallel lines: none (closed form, 1e-15).
    #[test]
    fn common_perpendicular_of_skew_lines() {
        let (x, y) = common_perpendicular(
            (Vector3::new(5.0, 0.0, 0.0), Vector3::x()),
            (Vector3::new(0.0, -3.0, 1.0), Vector3::y()),
        )
        .unwrap();
        assert_near!((x - Vector3::zeros()).norm(), 0.0, 1e-15);
        assert_near!((y - Vector3::new(0.0, 0.0, 1.0)).norm(), 0.0, 1e-15);
        assert!(common_perpendicular(
            (Vector3::zeros(), Vector3::x()),
            (Vector3::y(), Vector3::x())
        )
        .is_none());
    }
}
