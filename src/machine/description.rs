//! The machine-description file (JSON) read by `testpiece forward --machine FILE`.
//!
//! ```json
//! {
//!   "name": "free text",
//!   "code": "w C' B' b X Y Z t",
//!   "angle_unit": "deg",
//!   "offsets": { "B": [0.033, 0.033, -139.192], "C": [-0.033, -0.033, 139.192] },
//!   "tool_offset": [0, 0, -120],
//!   "errors": { "EX0B": 0.0 },
//!   "notes": "free text"
//! }
//! ```
//! - `code`: the structural code of [`super::chain`] (workpiece `w`, frame `b`, tool `t`, a prime
//!   for an axis whose body moves in the negative sense).
//! - `angle_unit`: `"deg"` (default) or `"rad"`: the unit of the rotary values in input files.
//! - `offsets`: per axis, the offset of its frame in its carrier's frame (mm); a rotary axis's line
//!   passes through it. Omitted axes have none.
//! - `tool_offset`: the tool tip in the last tool-side frame (mm); the tool axis is that frame's +z.
//! - `errors` (optional): error parameters by name (`EC0Y`, `EXX`, `EXX1`, …; mm, rad).
//!
//! Unknown fields are rejected so that a misspelt key does not pass silently.

use std::collections::BTreeMap;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::chain::{AxisName, Chain};
use super::direct::{ErrorParam, MachineErrors};
use super::MachineError;

/// Unit of the rotary axis values in input files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AngleUnit {
    #[default]
    Deg,
    Rad,
}

impl AngleUnit {
    /// Factor from this unit to rad.
    pub fn to_rad(self) -> f64 {
        match self {
            AngleUnit::Deg => std::f64::consts::PI / 180.0,
            AngleUnit::Rad => 1.0,
        }
    }
}

/// The file's content (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MachineDescription {
    #[serde(default)]
    pub name: String,
    pub code: String,
    #[serde(default)]
    pub angle_unit: AngleUnit,
    #[serde(default)]
    pub offsets: BTreeMap<String, [f64; 3]>,
    #[serde(default)]
    pub tool_offset: [f64; 3],
    #[serde(default)]
    pub errors: BTreeMap<String, f64>,
    #[serde(default)]
    pub notes: String,
}

impl MachineDescription {
    /// Parses the JSON text.
    pub fn from_json(text: &str) -> Result<Self, MachineError> {
        serde_json::from_str(text).map_err(|e| MachineError::DescriptionJson {
            message: e.to_string(),
        })
    }

    /// The chain it describes.
    pub fn chain(&self) -> Result<Chain, MachineError> {
        let mut c = Chain::from_code(&self.code)?;
        for (name, o) in &self.offsets {
            let mut chars = name.chars();
            let axis = match (chars.next().and_then(AxisName::from_letter), chars.next()) {
                (Some(a), None) => a,
                _ => return Err(MachineError::OffsetAxis { name: name.clone() }),
            };
            c = c.with_offset(axis, Vector3::new(o[0], o[1], o[2]))?;
        }
        let t = self.tool_offset;
        Ok(c.with_tool_offset(Vector3::new(t[0], t[1], t[2])))
    }

    /// The error values it lists (validated against the chain).
    pub fn machine_errors(&self) -> Result<MachineErrors, MachineError> {
        let chain = self.chain()?;
        let mut e = MachineErrors::none();
        for (name, v) in &self.errors {
            e = e.with(ErrorParam::parse(name)?, *v);
        }
        e.validate(&chain)?;
        Ok(e)
    }
}
