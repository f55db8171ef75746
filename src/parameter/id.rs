//! The typed id of a parameter a fit estimates: what it is ([`ParamKind`]), its name as files,
//! the CLI's JSON and the page write it, and its unit, set where the parameter is defined:
//! - a machine error ([`ErrorParam`]: a location error `EC0Y` of ISO 230-1, paper 000 eq. 11,
//!   or an error motion's coefficient `EXX1`): mm for a position component (X, Y, Z), rad for
//!   an orientation (A, B, C), from the component's kind ([`ErrorParam::unit`]);
//! - the tool-radius term `dR` (mm, + = a larger tool; s-shape.md, cli.md);
//! - a parameter of an effect of effects.md (`tool_taper.g`), in the unit of effects.md's table
//!   ([`Effect::parameters`]);
//! - a term of one part of a pooled identification (`dR[2]`, `Rz[2]`, `Tx[2]`, `Ty[2]`);
//! - a column of the caller's own, with the name and unit it came in with.
//!
//! Names are read into ids only where text comes in ([`ParamId::parse`]: a CLI argument, a
//! file's header); nothing derives a unit or a kind from a name's letters.

use std::fmt;
use std::str::FromStr;

use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};

use crate::machine::location_errors::{TYPICAL_ANGLE_RAD, TYPICAL_LENGTH_MM};
use crate::machine::{ErrorParam, Unit};

use super::{Effect, ParameterError};

/// Name of the tool-radius term (cli.md): mm, + = a larger tool, column = -1 (s-shape.md).
pub const TOOL_RADIUS: &str = "dR";

/// What a parameter is (serialised as `kind`: `location_error`, `error_motion`, `tool_radius`,
/// `effect`, `per_part`, `user`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ParamKind {
    LocationError,
    ErrorMotion,
    ToolRadius,
    Effect,
    PerPart,
    User,
}

/// A term of one part in a pooled identification ([`crate::pool`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartTerm {
    /// `dR[k]`: the part's own tool-radius term (mm).
    ToolRadius,
    /// `Rz[k]`: the part's set-up rotation about Z (rad).
    SetupRotation,
    /// `Tx[k]`: the part's set-up shift along x (mm).
    SetupShiftX,
    /// `Ty[k]`: the part's set-up shift along y (mm).
    SetupShiftY,
}

impl PartTerm {
    fn symbol(self) -> &'static str {
        match self {
            PartTerm::ToolRadius => TOOL_RADIUS,
            PartTerm::SetupRotation => "Rz",
            PartTerm::SetupShiftX => "Tx",
            PartTerm::SetupShiftY => "Ty",
        }
    }
    /// Its unit: rad for the rotation, mm otherwise.
    pub fn unit(self) -> Unit {
        match self {
            PartTerm::SetupRotation => Unit::Rad,
            _ => Unit::Mm,
        }
    }
    /// Its typical size, in its unit: 1e-4 rad for the rotation, 0.01 mm otherwise.
    pub fn typical(self) -> f64 {
        match self {
            PartTerm::SetupRotation => TYPICAL_ANGLE_RAD,
            _ => TYPICAL_LENGTH_MM,
        }
    }
}

/// One parameter's id (module docs).
#[derive(Debug, Clone, PartialEq)]
pub enum ParamId {
    /// A machine error: a location error or an error motion's coefficient.
    Machine(ErrorParam),
    /// The tool-radius term `dR` (mm).
    ToolRadius,
    /// The parameter `index` of `effect`, in the order of [`Effect::parameters`].
    Effect { effect: Effect, index: usize },
    /// A term of part `part` (1-based) of a pooled identification.
    PerPart { part: usize, term: PartTerm },
    /// A column of the caller's own: its name and unit as given where it came in.
    User { name: String, unit: Unit },
}

impl ParamId {
    /// What it is.
    pub fn kind(&self) -> ParamKind {
        match self {
            ParamId::Machine(ErrorParam::Location(_)) => ParamKind::LocationError,
            ParamId::Machine(ErrorParam::Motion { .. }) => ParamKind::ErrorMotion,
            ParamId::ToolRadius => ParamKind::ToolRadius,
            ParamId::Effect { .. } => ParamKind::Effect,
            ParamId::PerPart { .. } => ParamKind::PerPart,
            ParamId::User { .. } => ParamKind::User,
        }
    }

    /// Its name as files, the CLI's JSON and the page write it: `EC0Y`, `EXX1`, `dR`,
    /// `<effect id>.<parameter>` (`tool_taper.g`), `dR[2]`, or the user's own.
    pub fn name(&self) -> String {
        match self {
            ParamId::Machine(e) => e.name(),
            ParamId::ToolRadius => TOOL_RADIUS.to_string(),
            ParamId::Effect { effect, index } => {
                format!("{}.{}", effect.id(), effect.parameters()[*index].0)
            }
            ParamId::PerPart { part, term } => format!("{}[{part}]", term.symbol()),
            ParamId::User { name, .. } => name.clone(),
        }
    }

    /// Its unit, as defined with the parameter (module docs).
    pub fn unit(&self) -> Unit {
        match self {
            ParamId::Machine(e) => e.unit(),
            ParamId::ToolRadius => Unit::Mm,
            ParamId::Effect { effect, index } => effect.parameters()[*index].1.clone(),
            ParamId::PerPart { term, .. } => term.unit(),
            ParamId::User { unit, .. } => unit.clone(),
        }
    }

    /// The typical size of the parameter on a real machine, in its unit, where its kind has one:
    /// a machine error's ([`ErrorParam::typical`]: 1e-4 rad, 0.01 mm), 0.01 mm for the tool
    /// radius and a part's shifts, 1e-4 rad for a part's rotation. `None` for an effect's
    /// parameter (its size follows from its signature on the part) and a user's column.
    pub fn typical(&self) -> Option<f64> {
        match self {
            ParamId::Machine(e) => Some(e.typical()),
            ParamId::ToolRadius => Some(TYPICAL_LENGTH_MM),
            ParamId::PerPart { term, .. } => Some(term.typical()),
            ParamId::Effect { .. } | ParamId::User { .. } => None,
        }
    }

    /// The machine error, for a machine error's id.
    pub fn machine_error(&self) -> Option<ErrorParam> {
        match self {
            ParamId::Machine(e) => Some(*e),
            _ => None,
        }
    }

    /// The effect, for an effect's parameter.
    pub fn effect(&self) -> Option<Effect> {
        match self {
            ParamId::Effect { effect, .. } => Some(*effect),
            _ => None,
        }
    }

    /// Reads a name that comes in as text: `dR`, a machine error (`EX0B`, `EA0C`, also `E_X0B`;
    /// `EXX1`), or an effect's parameter (`tool_taper.g`, or `backlash_c` for a one-parameter
    /// effect: [`Effect::parse_parameter`]). Anything else is [`ParameterError::NotAParameter`].
    pub fn parse(text: &str) -> Result<ParamId, ParameterError> {
        if text == TOOL_RADIUS {
            return Ok(ParamId::ToolRadius);
        }
        if let Ok(e) = ErrorParam::parse(text) {
            return Ok(ParamId::Machine(e));
        }
        match Effect::parse_parameter(text) {
            Ok((effect, index)) => Ok(ParamId::Effect { effect, index }),
            Err(ParameterError::UnknownEffect(_)) => Err(ParameterError::NotAParameter {
                name: text.to_string(),
            }),
            Err(e) => Err(e),
        }
    }
}

impl fmt::Display for ParamId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(&self.name())
    }
}

impl FromStr for ParamId {
    type Err = ParameterError;
    fn from_str(s: &str) -> Result<Self, ParameterError> {
        ParamId::parse(s)
    }
}

/// Serialised as `{kind, name, unit}`; an effect's parameter adds `effect` (its id) and
/// `parameter` (its name in the effect), a part's term `part`.
impl Serialize for ParamId {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("kind", &self.kind())?;
        m.serialize_entry("name", &self.name())?;
        m.serialize_entry("unit", &self.unit())?;
        match self {
            ParamId::Effect { effect, index } => {
                m.serialize_entry("effect", effect)?;
                m.serialize_entry("parameter", effect.parameters()[*index].0)?;
            }
            ParamId::PerPart { part, .. } => m.serialize_entry("part", part)?,
            _ => {}
        }
        m.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::{AxisName, LocationError};

    #[test]
    fn names_units_and_kinds_come_from_the_definition() {
        let ex0b = ParamId::Machine(ErrorParam::Location(LocationError::new(
            AxisName::X,
            AxisName::B,
        )));
        assert_eq!((ex0b.name().as_str(), ex0b.unit()), ("EX0B", Unit::Mm));
        assert_eq!(ex0b.kind(), ParamKind::LocationError);
        let g = ParamId::Effect {
            effect: Effect::ToolTaper,
            index: 1,
        };
        assert_eq!(
            (g.name().as_str(), g.unit().to_string()),
            ("tool_taper.g", "mm/mm".into())
        );
        let rz = ParamId::PerPart {
            part: 2,
            term: PartTerm::SetupRotation,
        };
        assert_eq!((rz.name().as_str(), rz.unit()), ("Rz[2]", Unit::Rad));
        // A user's column keeps the unit it came with, whatever its name says.
        let user = ParamId::User {
            name: "EA0B_lab".into(),
            unit: Unit::Mm,
        };
        assert_eq!(user.unit(), Unit::Mm);
        assert_eq!(
            serde_json::to_value(&g).unwrap(),
            serde_json::json!({"kind": "effect", "name": "tool_taper.g", "unit": "mm/mm",
                "effect": "tool_taper", "parameter": "g"})
        );
    }

    #[test]
    fn text_that_comes_in_is_read_into_ids() {
        for name in ["EC0Y", "EX0B", "dR", "tool_taper.g", "backlash_c.b", "EXX1"] {
            assert_eq!(ParamId::parse(name).unwrap().name(), name);
        }
        assert_eq!(ParamId::parse("E_A0B").unwrap().name(), "EA0B");
        // A one-parameter effect may be named by its id alone.
        assert_eq!(
            ParamId::parse("backlash_c").unwrap(),
            ParamId::Effect {
                effect: Effect::Backlash(crate::machine::AxisName::C),
                index: 0
            }
        );
        assert_eq!(
            ParamId::parse("FOO").unwrap_err(),
            ParameterError::NotAParameter { name: "FOO".into() }
        );
        assert!(matches!(
            ParamId::parse("tool_taper.h"),
            Err(ParameterError::UnknownParameter { .. })
        ));
    }
}
