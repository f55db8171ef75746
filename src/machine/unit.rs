//! The unit of a parameter's value, set where the parameter is defined: a location error's from
//! the kind of its component (X, Y, Z a length in mm; A, B, C an angle in rad), an error
//! motion's coefficient of `q^k` per the axis's unit to the `k`, an effect's from its row of
//! spec/effects.md, a user column's as its file writes it. Never derived from a name.
//!
//! Written (and serialised) as the text the reports have always carried: `mm`, `rad`, `1`,
//! `mm/mm`, `rad/mm^2`, or the user's own text.

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::chain::AxisKind;

/// The unit of a parameter's value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unit {
    /// `mm`: a length.
    Mm,
    /// `rad`: an angle.
    Rad,
    /// `1`: a pure number (e.g. the scale `k` of `overcut`).
    One,
    /// `mm^2`: a squared length (`servo_common.L2`, the square of the common servo lag).
    Mm2,
    /// The unit of a displacement of kind `of` per that of kind `per` to the `power` (≥ 1):
    /// `mm/mm` (a scale error, a taper), `rad/mm^2` (an error motion's coefficient of `q²`).
    Per {
        of: AxisKind,
        per: AxisKind,
        power: u32,
    },
    /// A unit as written where the parameter came in (a column of the caller's own).
    Text(String),
}

impl Unit {
    /// The unit of a displacement of this kind: `mm` (linear) or `rad` (rotary).
    pub const fn of_kind(kind: AxisKind) -> Unit {
        match kind {
            AxisKind::Linear => Unit::Mm,
            AxisKind::Rotary => Unit::Rad,
        }
    }

    /// A unit read from text that comes in (a file's header, a caller's settings): the forms
    /// [`Unit`] writes are read back as themselves, any other text is kept as written.
    pub fn parse(text: &str) -> Unit {
        let kind = |t: &str| match t {
            "mm" => Some(AxisKind::Linear),
            "rad" => Some(AxisKind::Rotary),
            _ => None,
        };
        match text {
            "mm" => return Unit::Mm,
            "rad" => return Unit::Rad,
            "1" => return Unit::One,
            "mm^2" => return Unit::Mm2,
            _ => {}
        }
        if let Some((of, rest)) = text.split_once('/') {
            let (per, power) = match rest.split_once('^') {
                Some((per, k)) => (per, k.parse::<u32>().ok().filter(|k| *k >= 2)),
                None => (rest, Some(1)),
            };
            if let (Some(of), Some(per), Some(power)) = (kind(of), kind(per), power) {
                return Unit::Per { of, per, power };
            }
        }
        Unit::Text(text.to_string())
    }

    /// Whether a value in this unit is an angle (`rad`).
    pub fn is_angle(&self) -> bool {
        *self == Unit::Rad
    }
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let base = |k: AxisKind| match k {
            AxisKind::Linear => "mm",
            AxisKind::Rotary => "rad",
        };
        match self {
            Unit::Mm => f.pad("mm"),
            Unit::Rad => f.pad("rad"),
            Unit::One => f.pad("1"),
            Unit::Mm2 => f.pad("mm^2"),
            Unit::Per { of, per, power: 1 } => f.pad(&format!("{}/{}", base(*of), base(*per))),
            Unit::Per { of, per, power } => f.pad(&format!("{}/{}^{power}", base(*of), base(*per))),
            Unit::Text(t) => f.pad(t),
        }
    }
}

/// Serialised as its text (`"mm"`, `"rad/mm^2"`).
impl Serialize for Unit {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// Read from its text ([`Unit::parse`]).
impl<'de> Deserialize<'de> for Unit {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(Unit::parse(&String::deserialize(d)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_are_written_as_the_reports_write_them_and_read_back() {
        let per = |of, per, power| Unit::Per { of, per, power };
        let cases = [
            (Unit::Mm, "mm"),
            (Unit::Rad, "rad"),
            (Unit::One, "1"),
            (Unit::Mm2, "mm^2"),
            (per(AxisKind::Linear, AxisKind::Linear, 1), "mm/mm"),
            (per(AxisKind::Rotary, AxisKind::Linear, 2), "rad/mm^2"),
            (Unit::Text("µm/K".into()), "µm/K"),
        ];
        for (unit, text) in cases {
            assert_eq!(unit.to_string(), text);
            assert_eq!(Unit::parse(text), unit);
            assert_eq!(serde_json::to_string(&unit).unwrap(), format!("\"{text}\""));
        }
        assert_eq!(Unit::parse("mm/mm^1"), Unit::Text("mm/mm^1".into()));
        assert_eq!(Unit::of_kind(AxisKind::Rotary), Unit::Rad);
    }
}
