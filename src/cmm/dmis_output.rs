//! The DMIS output of a measurement (ISO 22093): what a CMM writes for each `OUTPUT/FA(label)`
//! of the plan's DMIS program (`plan::dmis`), the actual point feature
//!
//! ```text
//! FA(P7_A_Z11)=FEAT/POINT,CART,x,y,z,i,j,k
//! ```
//!
//! `x,y,z` the measured position, `i,j,k` the feature's vector (the outward normal the
//! program gave), in the frame of the program's alignment: the part frame. The form is that of
//! the standard's feature statements, as remembered (no DMIS output file of a CMM was at hand);
//! it is the form the plan's program reads back in its tests.
//!
//! Read as the canonical table `id, curve, x, y, z, nx, ny, nz` with measured positions (rule 3
//! of cmm-csv.md): a label `P<id>_<curve>` gives the id and the curve, any other label is the
//! id. A line ending in `$` continues on the next; `$$` starts a comment; `UNITS/MM` or
//! `UNITS/INCH` sets the unit (mm without it); statements other than point features
//! (`DMISMN`, `ENDFIL`, other features' outputs) carry no point and are passed over.

use super::delimited::RawRow;
use super::error::CmmError;
use super::header::{from_columns, Column, Role};
use super::rows::ParsedTable;
use super::table::FormatKind;
use super::units::LengthUnit;

/// Whether the first content line starts a DMIS output (`DMISMN/`, a `$$` comment or an
/// actual feature `FA(`).
pub fn is_dmis_output(first: &str) -> bool {
    let t = first.trim_start().to_ascii_uppercase();
    t.starts_with("DMISMN/") || t.starts_with("$$") || t.starts_with("FA(")
}

/// DMIS statements from numbered lines, each with the line it starts on: `$$` comments left
/// out, a blank line left out between statements, continued lines (ending in `$`) joined. The
/// one reader of DMIS statements: a measured output here, a written program in
/// [`crate::plan`].
pub fn join_statements<'a>(
    lines: impl IntoIterator<Item = (usize, &'a str)>,
) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut open: Option<(usize, String)> = None;
    for (line, raw) in lines {
        let t = raw.trim();
        if t.starts_with("$$") || (t.is_empty() && open.is_none()) {
            continue;
        }
        let (first, mut s) = open.take().unwrap_or((line, String::new()));
        match t.strip_suffix('$') {
            Some(head) => {
                s.push_str(head);
                open = Some((first, s));
            }
            None => {
                s.push_str(t);
                out.push((first, s));
            }
        }
    }
    out.extend(open);
    out
}

/// `P<id>_<curve>` split into id and curve.
fn id_and_curve(label: &str) -> Option<(&str, &str)> {
    let rest = label.strip_prefix('P')?;
    let (id, curve) = rest.split_once('_')?;
    (!id.is_empty() && id.bytes().all(|b| b.is_ascii_digit()) && !curve.is_empty())
        .then_some((id, curve))
}

/// Reads a DMIS output file (module docs).
pub fn dmis_output(content: &[(usize, &str)]) -> Result<ParsedTable, CmmError> {
    let first_line = content.first().map_or(1, |c| c.0);
    let mut unit = LengthUnit::Mm;
    let mut points: Vec<(usize, String, Vec<String>)> = Vec::new();
    for (line, s) in join_statements(content.iter().copied()) {
        let upper = s.to_ascii_uppercase();
        if upper.starts_with("UNITS/") {
            if upper.starts_with("UNITS/INCH") {
                unit = LengthUnit::Inch;
            }
            continue;
        }
        let Some((lhs, rhs)) = s.split_once('=') else {
            continue;
        };
        let label = lhs
            .trim()
            .strip_prefix("FA(")
            .and_then(|l| l.strip_suffix(')'));
        let values = rhs.trim().strip_prefix("FEAT/POINT,CART,");
        if let (Some(label), Some(values)) = (label, values) {
            let fields = values.split(',').map(|v| v.trim().to_string()).collect();
            points.push((line, label.to_string(), fields));
        }
    }
    let labelled = !points.is_empty() && points.iter().all(|p| id_and_curve(&p.1).is_some());
    let column = |number: usize, name: &str, role: Role, unit: Option<LengthUnit>| Column {
        number,
        header: name.to_string(),
        role: Some(role),
        unit,
    };
    let mut columns = vec![column(1, "label", Role::Id, None)];
    if labelled {
        columns.push(column(2, "curve", Role::Curve, None));
    }
    let at = columns.len();
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        columns.push(column(at + k + 1, name, Role::Measured(k), Some(unit)));
    }
    for (k, name) in ["i", "j", "k"].iter().enumerate() {
        columns.push(column(at + k + 4, name, Role::Normal(k), None));
    }
    let width = columns.len();
    let layout = from_columns(columns, first_line)?;
    let rows = points
        .into_iter()
        .map(|(line, label, mut values)| {
            let mut fields = match id_and_curve(&label) {
                Some((id, curve)) if labelled => vec![id.to_string(), curve.to_string()],
                _ => vec![label],
            };
            // Too few or too many numbers: padded or cut, the row reader names the gap.
            values.resize(width - fields.len(), String::new());
            fields.append(&mut values);
            RawRow { line, fields }
        })
        .collect();
    Ok(ParsedTable {
        kind: FormatKind::DmisOutput,
        layout,
        rows,
        problems: Vec::new(),
        separator: None,
        decimal_comma: false,
        header_line: None,
        preamble: Vec::new(),
        label: format!(
            "DMIS output (ISO 22093), actual point features, measured position + normal ({})",
            unit.symbol()
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_features_become_rows() {
        let text = "DMISMN/'x',05.3\n$$ c\nFA(P7_A_Z11)=FEAT/POINT,CART,1,2,$\n3,0,0,1\nENDFIL";
        let content: Vec<(usize, &str)> =
            text.lines().enumerate().map(|(k, l)| (k + 1, l)).collect();
        let t = dmis_output(&content).unwrap();
        assert_eq!(t.rows.len(), 1);
        assert_eq!(t.rows[0].line, 3);
        assert_eq!(
            t.rows[0].fields,
            ["7", "A_Z11", "1", "2", "3", "0", "0", "1"]
        );
    }
}
