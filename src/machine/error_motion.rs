//! Position-dependent error motions of an axis (ISO 230-1; paper 004 eq. S2; paper 002 §2).
//!
//! Each axis has six error motions, named like ISO 230-1 `E{component}{axis}`: `EXX` is the
//! positioning error of X (paper 002 `E_XX`), `EYX`, `EZX` its straightness, `EAX`, `EBX`, `ECX`
//! its roll, pitch and yaw; `EBB`, `ECC` the angular positioning errors of B and C (paper 002).
//! Components X, Y, Z are translations δ (mm), A, B, C rotations ε (rad) about x, y, z.
//! Each is a polynomial in the axis position `q` (mm or rad): `E(q) = Σ c_k q^k`, so a constant
//! error is `[c0]` and a linear one (e.g. a scale error of X) is `[0, c1]`.
//!
//! They enter the chain after the axis motion as the small-angle matrix of eq. S2,
//! `[[1, -εz, εy, δx], [εz, 1, -εx, δy], [-εy, εx, 1, δz]]`. Error motions are stated in the
//! axis's positive sense as the motion of the tool relative to the workpiece; for a primed axis
//! (a moving workpiece) the carried body moves by the opposite. So paper 002 eq. 1,
//! `x_t = Rz(C + E_CC)·Ry(B + E_BB)·(x_m + E_XX, …)`, is `ECC`, `EBB`, `EXX` constants on
//! `w C' B' b X Y Z t` (to first order in the angles).

use serde::{Deserialize, Serialize};

use super::chain::AxisName;
use super::MachineError;

/// Alias kept for readability: an error-motion component is named by an axis letter
/// (X, Y, Z: translation along; A, B, C: rotation about).
pub type MotionComponent = AxisName;

/// One error motion of one axis, polynomial in the axis position.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ErrorMotion {
    pub component: MotionComponent,
    pub axis: AxisName,
    /// `c_k` of `Σ c_k q^k` (mm or rad per unit of `q^k`).
    pub coefficients: Vec<f64>,
}

impl ErrorMotion {
    /// A constant error motion (e.g. paper 002's `E_XX = 0.01 mm`).
    pub fn constant(component: MotionComponent, axis: AxisName, value: f64) -> Self {
        Self {
            component,
            axis,
            coefficients: vec![value],
        }
    }
    /// `EXX` etc.
    pub fn name(&self) -> String {
        motion_name(self.component, self.axis)
    }
    /// The value at axis position `q`.
    pub fn value_at(&self, q: f64) -> f64 {
        self.coefficients
            .iter()
            .rev()
            .fold(0.0, |acc, c| acc * q + c)
    }
}

/// `E{component}{axis}`.
pub fn motion_name(component: MotionComponent, axis: AxisName) -> String {
    format!("E{}{}", component.letter(), axis.letter())
}

/// Parses `EXX`, `EBB`, or with a power suffix `EXX1` (coefficient of `q¹`); returns
/// `(component, axis, power)`.
pub fn parse_motion_name(s: &str) -> Result<(MotionComponent, AxisName, u32), MachineError> {
    let bad = || MachineError::BadErrorName {
        name: s.to_string(),
    };
    let t: Vec<char> = s.chars().filter(|&c| c != '_').collect();
    if t.len() < 3 || t[0] != 'E' {
        return Err(bad());
    }
    let component = AxisName::from_letter(t[1]).ok_or_else(bad)?;
    let axis = AxisName::from_letter(t[2]).ok_or_else(bad)?;
    let rest: String = t[3..].iter().collect();
    let power = if rest.is_empty() {
        0
    } else {
        rest.parse::<u32>().map_err(|_| bad())?
    };
    Ok((component, axis, power))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomial_and_names() {
        let m = ErrorMotion {
            component: AxisName::X,
            axis: AxisName::X,
            coefficients: vec![1.0, 2.0, 3.0],
        };
        assert_eq!(m.value_at(2.0), 1.0 + 4.0 + 12.0);
        assert_eq!(m.name(), "EXX");
        assert_eq!(
            parse_motion_name("EBB2").unwrap(),
            (AxisName::B, AxisName::B, 2)
        );
        assert!(parse_motion_name("EQX").is_err());
    }
}
