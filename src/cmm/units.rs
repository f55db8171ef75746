//! Length units of CMM columns. Everything the reader returns is in mm; a header may say
//! otherwise in brackets (`deviation [µm]`, `dev (um)`, `x [in]`, cmm-csv.md "Units").

use serde::{Deserialize, Serialize};

/// A length unit a column can be written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LengthUnit {
    Mm,
    Um,
    Inch,
    Cm,
    M,
}

impl LengthUnit {
    /// Millimetres per one of this unit (`value_mm = value · factor`).
    pub fn to_mm(self) -> f64 {
        match self {
            Self::Mm => 1.0,
            Self::Um => 1e-3,
            Self::Inch => 25.4,
            Self::Cm => 10.0,
            Self::M => 1000.0,
        }
    }

    /// The unit's usual symbol.
    pub fn symbol(self) -> &'static str {
        match self {
            Self::Mm => "mm",
            Self::Um => "µm",
            Self::Inch => "in",
            Self::Cm => "cm",
            Self::M => "m",
        }
    }

    /// Converts `value` in this unit to mm. Exact for mm (factor 1).
    pub fn mm(self, value: f64) -> f64 {
        match self {
            Self::Mm => value,
            Self::Um => value / 1000.0,
            other => value * other.to_mm(),
        }
    }
}

/// What a bracketed unit text means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitText {
    /// A length unit.
    Length(LengthUnit),
    /// No dimension (`[-]`, `[1]`, `[]`): fine for normals, ids and labels.
    Dimensionless,
    /// Something the reader does not know.
    Unknown,
}

/// Reads a unit as written in a header bracket (case-insensitive, spaces ignored).
pub fn parse_unit(text: &str) -> UnitText {
    let t: String = text
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect();
    match t.as_str() {
        "mm" | "millimeter" | "millimeters" | "millimetre" | "millimetres" => {
            UnitText::Length(LengthUnit::Mm)
        }
        // U+00B5 micro sign and U+03BC Greek mu both occur.
        "µm" | "μm" | "um" | "micron" | "microns" | "micrometer" | "micrometers" | "micrometre"
        | "micrometres" | "µ" | "μ" => UnitText::Length(LengthUnit::Um),
        "in" | "inch" | "inches" | "\"" | "''" => UnitText::Length(LengthUnit::Inch),
        "cm" => UnitText::Length(LengthUnit::Cm),
        "m" => UnitText::Length(LengthUnit::M),
        "" | "-" | "1" | "/" | "unitless" | "none" => UnitText::Dimensionless,
        _ => UnitText::Unknown,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_parse() {
        assert_eq!(parse_unit("µm"), UnitText::Length(LengthUnit::Um));
        assert_eq!(parse_unit("\u{3bc}m"), UnitText::Length(LengthUnit::Um));
        assert_eq!(parse_unit(" UM "), UnitText::Length(LengthUnit::Um));
        assert_eq!(parse_unit("Inch"), UnitText::Length(LengthUnit::Inch));
        assert_eq!(parse_unit("-"), UnitText::Dimensionless);
        assert_eq!(parse_unit("ft"), UnitText::Unknown);
        // Exact: 1 in = 25.4 mm by definition; µm divides by 1000 (correctly rounded).
        assert_eq!(LengthUnit::Inch.mm(1.0), 25.4);
        assert_eq!(LengthUnit::Um.mm(12.5), 0.0125);
    }
}
