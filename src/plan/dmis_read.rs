//! Reading back the points of a DMIS program written by [`super::write_dmis`] (or any program
//! with `F(label)=FEAT/POINT,CART,x,y,z,i,j,k` features each followed by a
//! `MEAS/POINT,F(label),n` block with one `PTMEAS/CART,x,y,z,i,j,k`), in file order: the tests'
//! check that the program holds the plan's points.
//!
//! A line ending in `$` (not a `$$` comment) continues on the next; a statement's line number
//! is that of its first line. Other statements (`GOTO`, the datums' planes, `OUTPUT`) are
//! passed over.

use nalgebra::Vector3;

use crate::cmm::dmis_output::join_statements;

use super::PlanError;

/// One point read back from a DMIS program: its label, the feature's nominal position and
/// vector, and the measurement's position and approach vector (mm, unit vectors).
#[derive(Debug, Clone, PartialEq)]
pub struct DmisPoint {
    pub label: String,
    pub nominal: Vector3<f64>,
    pub normal: Vector3<f64>,
    pub touch: Vector3<f64>,
    pub approach: Vector3<f64>,
}

/// The statements of a DMIS text with the line each starts on: comments and blank lines left
/// out, continued lines (ending in `$`) joined.
pub fn dmis_statements(text: &str) -> Vec<(usize, String)> {
    join_statements(text.lines().enumerate().map(|(k, l)| (k + 1, l)))
}

/// Six numbers after a prefix on a DMIS statement.
pub(crate) fn six(rest: &str, line: usize, text: &str) -> Result<[f64; 6], PlanError> {
    let bad = |message| PlanError::Dmis {
        line,
        message,
        text: text.to_string(),
    };
    let v: Vec<f64> = rest
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad("expected numbers x,y,z,i,j,k"))?;
    <[f64; 6]>::try_from(v).map_err(|_| bad("expected 6 numbers x,y,z,i,j,k"))
}

/// The point features of a DMIS program and their measurements (module docs).
pub fn read_dmis_points(text: &str) -> Result<Vec<DmisPoint>, PlanError> {
    let mut out: Vec<DmisPoint> = Vec::new();
    let mut pending: Option<(String, [f64; 6])> = None;
    let mut measuring: Option<String> = None;
    for (line, t) in dmis_statements(text) {
        let t = t.as_str();
        let bad = |message| PlanError::Dmis {
            line,
            message,
            text: t.to_string(),
        };
        if let Some((lhs, rhs)) = t.split_once("=FEAT/POINT,CART,") {
            let label = lhs
                .strip_prefix("F(")
                .and_then(|l| l.strip_suffix(')'))
                .ok_or_else(|| bad("expected F(label)=FEAT/POINT"))?;
            pending = Some((label.to_string(), six(rhs, line, t)?));
        } else if let Some(rest) = t.strip_prefix("MEAS/POINT,F(") {
            let label = rest
                .split_once(')')
                .map(|(l, _)| l)
                .ok_or_else(|| bad("expected MEAS/POINT,F(label),n"))?;
            match &pending {
                Some((l, _)) if l == label => measuring = Some(label.to_string()),
                _ => return Err(bad("measurement of a feature not defined just before")),
            }
        } else if let Some(rest) = t.strip_prefix("PTMEAS/CART,") {
            let Some(m) = &measuring else {
                // A datum plane's touches.
                continue;
            };
            let (label, f) = match &pending {
                Some((l, f)) if m == l => (l.clone(), *f),
                _ => return Err(bad("PTMEAS outside a MEAS block")),
            };
            let m = six(rest, line, t)?;
            out.push(DmisPoint {
                label,
                nominal: Vector3::new(f[0], f[1], f[2]),
                normal: Vector3::new(f[3], f[4], f[5]),
                touch: Vector3::new(m[0], m[1], m[2]),
                approach: Vector3::new(m[3], m[4], m[5]),
            });
        } else if t == "ENDMES" {
            measuring = None;
            pending = None;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_number_names_the_line() {
        let e =
            read_dmis_points("DMISMN/'x',05.3\nF(P1)=FEAT/POINT,CART,1,2,x,0,0,1\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "DMIS line 2: expected numbers x,y,z,i,j,k (found `F(P1)=FEAT/POINT,CART,1,2,x,0,0,1`)"
        );
    }

    #[test]
    fn continued_lines_are_joined() {
        let s = dmis_statements("$$ c\nGOTO/1,$\n2,3\nENDFIL\n");
        assert_eq!(
            s,
            vec![(2, "GOTO/1,2,3".to_string()), (4, "ENDFIL".to_string())]
        );
    }
}
