//! Header names: what each column means and in which unit (cmm-csv.md, header table).
//!
//! A name is matched case-insensitively after removing spaces, `_`, `-`, `.` and a unit in
//! brackets (`[µm]`, `(mm)`); a unit may also be glued to the end (`dev_um`, `xmm`). Columns
//! with no meaning in the table are kept as extra columns, never an error.

use serde::{Deserialize, Serialize};

use super::error::CmmError;
use super::units::{parse_unit, LengthUnit, UnitText};

/// What a column holds. Axis index 0, 1, 2 = x, y, z (or i, j, k).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    Id,
    Curve,
    Nominal(usize),
    Normal(usize),
    Measured(usize),
    Deviation,
}

impl Role {
    /// The role in words, for messages.
    pub fn describe(self) -> String {
        let axis = |i: usize| ["x", "y", "z"][i.min(2)];
        match self {
            Self::Id => "the point id".into(),
            Self::Curve => "the curve label".into(),
            Self::Nominal(i) => format!("nominal {}", axis(i)),
            Self::Normal(i) => format!("normal {}", ["i", "j", "k"][i.min(2)]),
            Self::Measured(i) => format!("measured {}", axis(i)),
            Self::Deviation => "the normal deviation".into(),
        }
    }

    /// Whether the column holds a length (converted to mm by its unit).
    pub fn is_length(self) -> bool {
        matches!(self, Self::Nominal(_) | Self::Measured(_) | Self::Deviation)
    }
}

/// One column of the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Column {
    /// 1-based column number.
    pub number: usize,
    /// Header text as written.
    pub header: String,
    /// Meaning, if the name is recognised; `None` for extra columns.
    pub role: Option<Role>,
    /// Unit given in the header, if any.
    pub unit: Option<LengthUnit>,
}

const ID: &[&str] = &[
    "id",
    "point",
    "pt",
    "name",
    "label",
    "no",
    "nr",
    "punkt",
    "pointid",
    "pointname",
    "pointno",
    "pointnr",
    "pointnumber",
    "ptid",
    "ptno",
    "ptname",
    "number",
    "num",
    "punktnr",
    "punktname",
    "nummer",
];
const CURVE: &[&str] = &[
    "curve",
    "line",
    "group",
    "kurve",
    "gruppe",
    "curvename",
    "section",
    "scan",
];
const DEVIATION: &[&str] = &[
    "deviation",
    "dev",
    "t",
    "error",
    "normaldeviation",
    "d",
    "abweichung",
    "abw",
    "normaldev",
    "devn",
    "ndev",
    "err",
    "3ddev",
    "3ddeviation",
    "devnormal",
    "deviationnormal",
    "normalabweichung",
    "surfacedeviation",
    "offset",
];
/// `{a}` stands for x, y or z.
const NOMINAL: &[&str] = &[
    "{a}",
    "{a}nom",
    "nom{a}",
    "nominal{a}",
    "{a}nominal",
    "soll{a}",
    "{a}soll",
    "theo{a}",
    "{a}theo",
    "theoretical{a}",
    "{a}theoretical",
    "cad{a}",
    "{a}cad",
    "target{a}",
    "{a}target",
];
/// `{a}` stands for x, y or z.
const MEASURED: &[&str] = &[
    "{a}meas",
    "meas{a}",
    "{a}m",
    "actual{a}",
    "{a}act",
    "act{a}",
    "{a}actual",
    "ist{a}",
    "{a}ist",
    "measured{a}",
    "{a}measured",
    "{a}mes",
    "mes{a}",
];
/// `{a}` stands for x, y or z and `{i}` for i, j or k.
const NORMAL: &[&str] = &[
    "n{a}",
    "{i}",
    "vector{i}",
    "vektor{i}",
    "vec{i}",
    "{i}vec",
    "{i}vector",
    "vector{a}",
    "normal{a}",
    "{a}normal",
    "norm{a}",
    "{a}norm",
    "{i}nom",
    "nom{i}",
    "nominal{i}",
];

fn axis_match(patterns: &[&str], name: &str) -> Option<usize> {
    (0..3).find(|&k| {
        let a = ["x", "y", "z"][k];
        let i = ["i", "j", "k"][k];
        patterns.iter().any(|p| fills(p, name, a, i))
    })
}

/// Whether `name` is `pattern` with `{a}` replaced by `a` and `{i}` by `i` (without building the
/// replaced string: every header candidate of a file is matched against every pattern).
fn fills(pattern: &str, name: &str, a: &str, i: &str) -> bool {
    let (mut pat, mut rest) = (pattern, name);
    loop {
        let (sub, after) = match (pat.strip_prefix("{a}"), pat.strip_prefix("{i}")) {
            (Some(r), _) => (a, r),
            (_, Some(r)) => (i, r),
            _ => match pat.chars().next() {
                None => return rest.is_empty(),
                Some(c) => (&pat[..c.len_utf8()], &pat[c.len_utf8()..]),
            },
        };
        match rest.strip_prefix(sub) {
            Some(r) => (pat, rest) = (after, r),
            None => return false,
        }
    }
}

/// Meaning of an already normalised name.
fn role_of(name: &str) -> Option<Role> {
    if ID.contains(&name) {
        Some(Role::Id)
    } else if CURVE.contains(&name) {
        Some(Role::Curve)
    } else if DEVIATION.contains(&name) {
        Some(Role::Deviation)
    } else if let Some(k) = axis_match(NOMINAL, name) {
        Some(Role::Nominal(k))
    } else if let Some(k) = axis_match(NORMAL, name) {
        Some(Role::Normal(k))
    } else {
        axis_match(MEASURED, name).map(Role::Measured)
    }
}

/// Lower case without spaces, `_`, `-`, `.`.
fn normalise(name: &str) -> String {
    name.chars()
        .filter(|c| !c.is_whitespace() && !matches!(c, '_' | '-' | '.'))
        .flat_map(char::to_lowercase)
        .collect()
}

/// Splits `deviation [µm]` into (`deviation `, Some(`µm`)).
fn split_bracket(text: &str) -> (String, Option<String>) {
    for (open, close) in [('[', ']'), ('(', ')'), ('{', '}')] {
        if let Some(start) = text.find(open) {
            if let Some(len) = text[start + open.len_utf8()..].find(close) {
                let inner = &text[start + open.len_utf8()..start + open.len_utf8() + len];
                let rest = format!(
                    "{}{}",
                    &text[..start],
                    &text[start + open.len_utf8() + len + close.len_utf8()..]
                );
                return (rest, Some(inner.to_string()));
            }
        }
    }
    (text.to_string(), None)
}

/// Result of reading one header name.
#[derive(Debug, Clone, PartialEq)]
pub struct HeaderName {
    pub role: Option<Role>,
    /// The unit text and what it means, when the name carries one.
    pub unit: Option<(String, UnitText)>,
}

/// Reads one header name: its meaning and unit.
pub fn read_name(text: &str) -> HeaderName {
    let (base, bracket) = split_bracket(text.trim().trim_matches('"'));
    let norm = normalise(&base);
    if let Some(role) = role_of(&norm) {
        let unit = bracket.map(|u| {
            let parsed = parse_unit(&u);
            (u, parsed)
        });
        return HeaderName {
            role: Some(role),
            unit,
        };
    }
    // A unit glued to the end: `dev_um`, `xmm`, `deviationµm`.
    if bracket.is_none() {
        for suffix in ["mm", "um", "µm", "μm", "inch", "in"] {
            if let Some(stem) = norm.strip_suffix(suffix) {
                if let Some(role) = role_of(stem).filter(|r| r.is_length()) {
                    return HeaderName {
                        role: Some(role),
                        unit: Some((suffix.to_string(), parse_unit(suffix))),
                    };
                }
            }
        }
    }
    HeaderName {
        role: None,
        unit: bracket.map(|u| {
            let parsed = parse_unit(&u);
            (u, parsed)
        }),
    }
}

/// How many names of `fields` have a meaning (used to find the header row and its separator).
pub fn recognised(fields: &[String]) -> usize {
    fields
        .iter()
        .filter(|f| read_name(f).role.is_some())
        .count()
}

/// Which columns hold what (0-based indices into a row's fields).
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    pub columns: Vec<Column>,
    pub id: Option<usize>,
    pub curve: Option<usize>,
    pub nominal: Option<[usize; 3]>,
    pub normal: Option<[usize; 3]>,
    pub measured: Option<[usize; 3]>,
    pub deviation: Option<usize>,
    /// Columns without a meaning, kept as text.
    pub extra: Vec<usize>,
    /// True when the file has only `x, y, z` (no deviation, no measured columns): those are then
    /// the measured positions (rule 3), since nothing else could be compared with the part.
    pub positions_read_as_measured: bool,
}

impl Layout {
    /// Number of fields a row must have.
    pub fn width(&self) -> usize {
        self.columns.len()
    }
}

/// Builds the layout from a header row at `line`. Errors: unknown unit, two columns with the
/// same meaning, required columns missing.
pub fn layout_from_header(fields: &[String], line: usize) -> Result<Layout, CmmError> {
    let mut columns = Vec::with_capacity(fields.len());
    for (k, text) in fields.iter().enumerate() {
        let name = read_name(text);
        let unit = match (&name.unit, name.role) {
            (Some((u, UnitText::Unknown)), Some(role)) if role.is_length() => {
                return Err(CmmError::UnknownUnit {
                    line,
                    column: k + 1,
                    header: text.clone(),
                    unit: u.clone(),
                })
            }
            (Some((_, UnitText::Length(unit))), Some(role)) if role.is_length() => Some(*unit),
            _ => None,
        };
        columns.push(Column {
            number: k + 1,
            header: text.trim().to_string(),
            role: name.role,
            unit,
        });
    }
    from_columns(columns, line)
}

/// Builds the layout from columns whose roles are known (headers or fixed formats).
pub fn from_columns(columns: Vec<Column>, line: usize) -> Result<Layout, CmmError> {
    let mut slots: Vec<(Role, usize)> = Vec::new();
    let mut extra = Vec::new();
    for (k, c) in columns.iter().enumerate() {
        match c.role {
            Some(role) => {
                if let Some(&(_, first)) = slots.iter().find(|(r, _)| *r == role) {
                    return Err(CmmError::AmbiguousColumns {
                        line,
                        first: format!("{} '{}'", first + 1, columns[first].header),
                        second: format!("{} '{}'", k + 1, c.header),
                        meaning: role.describe(),
                    });
                }
                slots.push((role, k));
            }
            None => extra.push(k),
        }
    }
    let find = |role: Role| slots.iter().find(|(r, _)| *r == role).map(|&(_, k)| k);
    let mut missing: Vec<String> = Vec::new();
    let mut triple = |make: fn(usize) -> Role, what: &str| -> Option<[usize; 3]> {
        let found: Vec<Option<usize>> = (0..3).map(|i| find(make(i))).collect();
        match found.iter().filter(|f| f.is_some()).count() {
            0 => None,
            3 => Some([found[0]?, found[1]?, found[2]?]),
            _ => {
                for (i, f) in found.iter().enumerate() {
                    if f.is_none() {
                        missing.push(format!("{what} ({})", make(i).describe()));
                    }
                }
                None
            }
        }
    };
    let nominal = triple(Role::Nominal, "nominal position");
    let normal = triple(Role::Normal, "normal");
    let measured = triple(Role::Measured, "measured position");
    let deviation = find(Role::Deviation);
    let found = columns
        .iter()
        .map(|c| match c.role {
            Some(r) => format!("'{}' ({})", c.header, r.describe()),
            None => format!("'{}' (not recognised)", c.header),
        })
        .collect::<Vec<_>>()
        .join(", ");
    if !missing.is_empty() {
        return Err(CmmError::MissingColumns {
            line,
            missing: missing.join(", "),
            found,
        });
    }
    if nominal.is_none() && measured.is_none() {
        return Err(CmmError::MissingColumns {
            line,
            missing: "a position: x, y, z (nominal) or xmeas, ymeas, zmeas (measured)".into(),
            found,
        });
    }
    let positions_read_as_measured = measured.is_none() && deviation.is_none();
    let (nominal, measured) = if positions_read_as_measured {
        (None, nominal)
    } else {
        (nominal, measured)
    };
    Ok(Layout {
        id: find(Role::Id),
        curve: find(Role::Curve),
        nominal,
        normal,
        measured,
        deviation,
        extra,
        positions_read_as_measured,
        columns,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn role(s: &str) -> Option<Role> {
        read_name(s).role
    }

    /// `fills` agrees with plain string replacement on every pattern, for names that match,
    /// nearly match (one letter more, less or changed) and do not match.
    #[test]
    fn fills_is_the_replaced_pattern() {
        for p in NOMINAL.iter().chain(NORMAL).chain(MEASURED) {
            for (a, i) in [("x", "i"), ("y", "j"), ("z", "k")] {
                let full = p.replace("{a}", a).replace("{i}", i);
                let mut names = vec![full.clone(), format!("{full}x"), format!("x{full}")];
                names.push(full[..full.len() - 1].to_string());
                names.push(full.replacen(a, "q", 1));
                names.push(String::new());
                for n in &names {
                    assert_eq!(fills(p, n, a, i), *n == full, "{p} {a}{i} {n:?}");
                }
            }
        }
    }

    #[test]
    fn synonyms() {
        assert_eq!(role("Point ID"), Some(Role::Id));
        assert_eq!(role("Punkt"), Some(Role::Id));
        assert_eq!(role("X_Nom"), Some(Role::Nominal(0)));
        assert_eq!(role("Soll-Y"), Some(Role::Nominal(1)));
        assert_eq!(role("z [mm]"), Some(Role::Nominal(2)));
        assert_eq!(role("Vector I"), Some(Role::Normal(0)));
        assert_eq!(role("K"), Some(Role::Normal(2)));
        assert_eq!(role("nz"), Some(Role::Normal(2)));
        assert_eq!(role("Actual X"), Some(Role::Measured(0)));
        assert_eq!(role("Ist.Z"), Some(Role::Measured(2)));
        assert_eq!(role("x_meas"), Some(Role::Measured(0)));
        assert_eq!(role("Abw."), Some(Role::Deviation));
        assert_eq!(role("Normal Deviation"), Some(Role::Deviation));
        assert_eq!(role("Kurve"), Some(Role::Curve));
        assert_eq!(role("tolerance"), None);
        let n = read_name("dev (um)");
        assert_eq!(n.role, Some(Role::Deviation));
        assert_eq!(n.unit.unwrap().1, UnitText::Length(LengthUnit::Um));
        let n = read_name("dev_um");
        assert_eq!(n.role, Some(Role::Deviation));
        assert_eq!(n.unit.unwrap().1, UnitText::Length(LengthUnit::Um));
    }
}
