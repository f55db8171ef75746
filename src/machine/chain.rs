//! A five-axis machine as data: structural code, axis signs, offsets and tool offset.
//!
//! ## Structural code (in the spirit of ISO 10791-1 / ISO 841)
//! The chain is read from the **workpiece** `w` through the frame (bed) `b` to the **tool** `t`,
//! one letter per axis: `X Y Z` linear along x, y, z; `A B C` rotary about x, y, z. Letters
//! between `w` and `b` carry the workpiece (listed from the workpiece towards the frame), letters
//! between `b` and `t` carry the tool (from the frame towards the tool). A prime `'` after a letter
//! means that its moving body moves in the **negative** sense of the letter when the axis value
//! increases (ISO 841: a moving workpiece moves opposite to the relative tool motion). Spaces are
//! optional; `b` (lowercase) is the frame and `B` (uppercase) the B axis.
//!
//! | machine | code | source |
//! |---|---|---|
//! | B head / C table, Five Machining Flexiax V | `w C Y' b X Z B t` | paper 000 eq. 8-9 |
//! | B-C tilting table (NMV 1500 DCG; the peer machine) | `w C' B' b X Y Z t` | paper 002 eq. 1 |
//! | XFYZBA, B-A head (GMC820u) | `w X' b Y Z B A t` | paper 001 Appendix 2, Table 6 |
//!
//! ## Transforms
//! Every axis `i` of value `q` contributes, from its carrier's frame,
//! `F_i(q) = Trans(o_i) · D_i · M_i(q) · E_i(q)` where `o_i` is the axis offset (the "position
//! transformation" of paper 001 Table 6; for a rotary axis its line passes through the offset
//! frame's origin), `D_i` the location-error matrix of paper 000 eq. 11, `M_i(q)` the motion
//! (`Trans(s·q·e)` or the right-handed `Rot(e, s·q)`, `s = -1` if primed) and `E_i(q)` the
//! error-motion matrix of paper 004 eq. S2. With `W = Π F` over the workpiece side (frame →
//! workpiece) and `T = Π F` over the tool side (frame → tool), the tool point `h` above the tip and
//! the tool direction in the workpiece frame are (paper 000 eq. 12)
//! `p = W⁻¹ · T · (o_tool + h·ẑ, 1)`, `w = W⁻¹ · T · (ẑ, 0)`.
//! Paper 000: `p = Rz(C)ᵀ([X, Y, Z] + Ry(B)·[0, 0, -L0])`, `w = (sinB cosC, -sinB sinC, cosB)`.
//!
//! ```
//! use testpiece::machine::{AxisValues, Chain};
//! use testpiece::machine::direct::nominal;
//! use testpiece::machine::location_errors::minimal_set;
//! let chain = Chain::paper000(499.889); // = "w C Y' b X Z B t" with the tip 499.889 below B
//! // B = C = 0: the tip is L0 below the spindle point, the tool vertical.
//! let p = nominal(&chain, &AxisValues::xyzbc(1.0, 2.0, 499.889, 0.0, 0.0), 0.0);
//! assert!((p.point - nalgebra::Vector3::new(1.0, 2.0, 0.0)).norm() < 1e-12);
//! assert_eq!(p.direction, nalgebra::Vector3::z());
//! // Paper 000 Table 3, derived from the chain:
//! assert_eq!(
//!     minimal_set(&chain).names(),
//!     ["EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B"]
//! );
//! ```

use nalgebra::{Matrix4, Vector3};
use serde::{Deserialize, Serialize};

use super::transform::{rotation, translation};
use super::MachineError;

/// `L0` of paper 000 (mm): distance from the B axis to the tool tip on the Flexiax V.
pub const PAPER000_L0: f64 = 499.889;

/// One of the six ISO axis letters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum AxisName {
    X,
    Y,
    Z,
    A,
    B,
    C,
}

/// Linear (mm) or rotary (rad) axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisKind {
    Linear,
    Rotary,
}

impl AxisName {
    pub const ALL: [AxisName; 6] = [
        AxisName::X,
        AxisName::Y,
        AxisName::Z,
        AxisName::A,
        AxisName::B,
        AxisName::C,
    ];
    /// 0..6 in the order X, Y, Z, A, B, C.
    pub fn index(self) -> usize {
        self as usize
    }
    /// The coordinate direction of the axis: 0 = x (X, A), 1 = y (Y, B), 2 = z (Z, C).
    pub fn direction(self) -> usize {
        self.index() % 3
    }
    pub fn kind(self) -> AxisKind {
        if self.index() < 3 {
            AxisKind::Linear
        } else {
            AxisKind::Rotary
        }
    }
    pub fn letter(self) -> char {
        ['X', 'Y', 'Z', 'A', 'B', 'C'][self.index()]
    }
    pub fn from_letter(c: char) -> Option<Self> {
        Some(match c {
            'X' => AxisName::X,
            'Y' => AxisName::Y,
            'Z' => AxisName::Z,
            'A' => AxisName::A,
            'B' => AxisName::B,
            'C' => AxisName::C,
            _ => return None,
        })
    }
}

impl std::fmt::Display for AxisName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.letter())
    }
}

/// Which side of the loop an axis carries: the workpiece or the tool.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Side {
    Workpiece,
    Tool,
}

/// One axis of a chain.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainAxis {
    pub name: AxisName,
    pub side: Side,
    /// +1, or -1 when primed: the body moves by `sign·q` along / about its coordinate direction.
    pub sign: f64,
    /// Offset of the axis frame in its carrier's frame (mm); a rotary axis's line passes through
    /// the offset frame's origin.
    pub offset: Vector3<f64>,
}

/// Axis values (mm for X, Y, Z; rad for A, B, C). Axes a chain lacks are ignored.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct AxisValues {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub a: f64,
    pub b: f64,
    pub c: f64,
}

impl AxisValues {
    /// Values of a B/C machine: `(X, Y, Z, B, C)`, A = 0.
    pub fn xyzbc(x: f64, y: f64, z: f64, b: f64, c: f64) -> Self {
        Self {
            x,
            y,
            z,
            a: 0.0,
            b,
            c,
        }
    }
    /// Sets axis `n` from a value in the units of a program or trace: mm for linear axes, and
    /// `to_rad` radians per unit for rotary axes (π/180 for degrees).
    pub fn set_in_units(&mut self, n: AxisName, value: f64, to_rad: f64) {
        let v = if n.kind() == AxisKind::Rotary {
            value * to_rad
        } else {
            value
        };
        self.set(n, v);
    }

    pub fn get(&self, n: AxisName) -> f64 {
        match n {
            AxisName::X => self.x,
            AxisName::Y => self.y,
            AxisName::Z => self.z,
            AxisName::A => self.a,
            AxisName::B => self.b,
            AxisName::C => self.c,
        }
    }
    pub fn set(&mut self, n: AxisName, v: f64) {
        match n {
            AxisName::X => self.x = v,
            AxisName::Y => self.y = v,
            AxisName::Z => self.z = v,
            AxisName::A => self.a = v,
            AxisName::B => self.b = v,
            AxisName::C => self.c = v,
        }
    }
}

/// A kinematic chain: the structural code plus offsets (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    code: String,
    /// Workpiece-side axes in transform order, frame → workpiece.
    workpiece: Vec<ChainAxis>,
    /// Tool-side axes in transform order, frame → tool.
    tool: Vec<ChainAxis>,
    /// The tool tip in the last tool-side frame (mm); the tool axis is that frame's +z.
    tool_offset: Vector3<f64>,
}

impl Chain {
    /// Parses a structural code (module docs); all offsets zero, tool tip at the last frame.
    pub fn from_code(code: &str) -> Result<Self, MachineError> {
        let bad = |reason: &str| MachineError::BadCode {
            code: code.to_string(),
            reason: reason.to_string(),
        };
        let chars: Vec<char> = code.chars().filter(|c| !c.is_whitespace()).collect();
        if chars.first() != Some(&'w') {
            return Err(bad("must start with `w` (the workpiece)"));
        }
        if chars.last() != Some(&'t') {
            return Err(bad("must end with `t` (the tool)"));
        }
        let mut workpiece_code = Vec::new();
        let mut tool = Vec::new();
        let mut side: Option<Side> = Some(Side::Workpiece);
        let mut seen = Vec::new();
        let mut i = 1;
        while i + 1 < chars.len() {
            let c = chars[i];
            i += 1;
            if c == 'b' {
                if side != Some(Side::Workpiece) {
                    return Err(bad("the frame `b` appears more than once"));
                }
                side = Some(Side::Tool);
                continue;
            }
            let Some(name) = AxisName::from_letter(c) else {
                return Err(bad(&format!(
                    "`{c}` is not an axis letter (X Y Z A B C), `b`, or a prime"
                )));
            };
            if seen.contains(&name) {
                return Err(bad(&format!("axis {name} appears twice")));
            }
            seen.push(name);
            let primed = chars.get(i) == Some(&'\'');
            if primed {
                i += 1;
            }
            let s = side.unwrap_or(Side::Tool);
            let axis = ChainAxis {
                name,
                side: s,
                sign: if primed { -1.0 } else { 1.0 },
                offset: Vector3::zeros(),
            };
            match s {
                Side::Workpiece => workpiece_code.push(axis),
                Side::Tool => tool.push(axis),
            }
        }
        if side != Some(Side::Tool) {
            return Err(bad(
                "has no frame `b` between the workpiece and the tool axes",
            ));
        }
        if seen.is_empty() {
            return Err(bad("has no axes"));
        }
        // The code lists workpiece axes from the workpiece towards the frame; transforms run
        // from the frame.
        workpiece_code.reverse();
        Ok(Self {
            code: code.split_whitespace().collect::<Vec<_>>().join(" "),
            workpiece: workpiece_code,
            tool,
            tool_offset: Vector3::zeros(),
        })
    }

    /// Sets the offset of axis `name` in its carrier's frame (mm).
    pub fn with_offset(
        mut self,
        name: AxisName,
        offset: Vector3<f64>,
    ) -> Result<Self, MachineError> {
        let code = self.code.clone();
        let ax =
            self.axes_mut()
                .find(|a| a.name == name)
                .ok_or_else(|| MachineError::UnknownAxis {
                    name: format!("offset of {name}"),
                    axis: name.to_string(),
                    code,
                })?;
        ax.offset = offset;
        Ok(self)
    }

    /// Sets the tool tip in the last tool-side frame (mm), e.g. `(0, 0, -L0)`.
    pub fn with_tool_offset(mut self, offset: Vector3<f64>) -> Self {
        self.tool_offset = offset;
        self
    }

    /// Paper 000 (eq. 8-9): B head on Z on X, C table on Y; tool tip `L0` below the B axis.
    /// `Chain::paper000(499.889)` is the Flexiax V of the paper.
    pub fn paper000(l0: f64) -> Self {
        Self::from_code("w C Y' b X Z B t")
            .expect("the paper 000 code is valid")
            .with_tool_offset(Vector3::new(0.0, 0.0, -l0))
    }

    /// Paper 002 eq. 1: B-C tilting table, `x_t = Rz(C)·Ry(B)·x_m`, tool tip at the machine point.
    pub fn paper002() -> Self {
        Self::from_code("w C' B' b X Y Z t").expect("the paper 002 code is valid")
    }

    /// Paper 001 Appendix 2 (XFYZBA, Table 6): X table; Y, Z, B and A in the head. The Z frame
    /// is raised by `ls + lt` (`T_12p`), the spindle nose is `ls` below the A axis (`T_45p`) and
    /// the tool tip `lt` below the nose (`T_56p`). The paper gives no values for `ls`, `lt`.
    pub fn paper001(ls: f64, lt: f64) -> Self {
        Self::from_code("w X' b Y Z B A t")
            .expect("the paper 001 code is valid")
            .with_offset(AxisName::Z, Vector3::new(0.0, 0.0, ls + lt))
            .expect("Z exists")
            .with_tool_offset(Vector3::new(0.0, 0.0, -(ls + lt)))
    }

    /// The normalised structural code.
    pub fn code(&self) -> &str {
        &self.code
    }
    /// Workpiece-side axes, frame → workpiece.
    pub fn workpiece_axes(&self) -> &[ChainAxis] {
        &self.workpiece
    }
    /// Tool-side axes, frame → tool.
    pub fn tool_axes(&self) -> &[ChainAxis] {
        &self.tool
    }
    pub fn tool_offset(&self) -> Vector3<f64> {
        self.tool_offset
    }
    /// All axes: workpiece side (frame → workpiece) then tool side (frame → tool).
    pub fn axes(&self) -> impl Iterator<Item = &ChainAxis> {
        self.workpiece.iter().chain(self.tool.iter())
    }
    fn axes_mut(&mut self) -> impl Iterator<Item = &mut ChainAxis> {
        self.workpiece.iter_mut().chain(self.tool.iter_mut())
    }
    pub fn axis(&self, name: AxisName) -> Option<&ChainAxis> {
        self.axes().find(|a| a.name == name)
    }
    /// The axes in structural-code order (workpiece → tool).
    pub fn code_order(&self) -> Vec<&ChainAxis> {
        self.workpiece
            .iter()
            .rev()
            .chain(self.tool.iter())
            .collect()
    }

    /// The nominal motion `M_i(q)` of one axis (no errors, no offset).
    pub(crate) fn motion(axis: &ChainAxis, q: f64) -> Matrix4<f64> {
        let k = axis.name.direction();
        match axis.name.kind() {
            AxisKind::Linear => {
                let mut v = Vector3::zeros();
                v[k] = axis.sign * q;
                translation(&v)
            }
            AxisKind::Rotary => rotation(k, axis.sign * q),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_parse_with_sides_and_primes() {
        let c = Chain::from_code("w C Y' b X Z B t").unwrap();
        let w: Vec<_> = c
            .workpiece_axes()
            .iter()
            .map(|a| (a.name, a.sign))
            .collect();
        assert_eq!(w, vec![(AxisName::Y, -1.0), (AxisName::C, 1.0)]);
        let t: Vec<_> = c.tool_axes().iter().map(|a| a.name).collect();
        assert_eq!(t, vec![AxisName::X, AxisName::Z, AxisName::B]);
        assert_eq!(Chain::from_code("wC'B'bXYZt").unwrap().code(), "wC'B'bXYZt");
        assert!(Chain::from_code("w C C b X t").is_err());
        assert!(Chain::from_code("w C Q b X t").is_err());
        assert!(Chain::from_code("C b X t").is_err());
        assert!(Chain::from_code("w C X t").is_err());
    }
}
