//! The plan as a DMIS program (ISO 22093, Dimensional Measuring Interface Standard) that CMM
//! software imports: per point a nominal point feature and its measurement,
//!
//! ```text
//! F(P7_A_Z11)=FEAT/POINT,CART,x,y,z,i,j,k
//! MEAS/POINT,F(P7_A_Z11),1
//! PTMEAS/CART,x,y,z,i,j,k
//! ENDMES
//! ```
//!
//! `x,y,z` the nominal position (mm, the part frame of `shared/spec/s-shape.md`: origin at the
//! part origin, Z up from the base), `i,j,k` the outward unit normal `N`: the DMIS approach
//! vector, the probe touching along `−N` (from outside the wall). Labels are `P<id>_<curve>`.
//! Numbers are written with 9 decimals (1e-9 mm), so the file reads back to the plan's points
//! within 5e-10 mm ([`read_dmis_points`], used by the tests). `$$` starts a comment.

use std::fmt::Write;

use nalgebra::Vector3;

use super::PlanError;
use crate::part::MeasurementPoint;

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

/// The DMIS program of `points`; each line of `header` becomes a `$$` comment.
pub fn write_dmis(points: &[MeasurementPoint], header: &str) -> String {
    let mut s = String::new();
    s.push_str("DMISMN/'testpiece S-shape measurement plan',05.3\n");
    for line in header.lines() {
        let _ = writeln!(s, "$$ {line}");
    }
    s.push_str("$$ part frame of ISO 10791-7 S-shape (paper 000 Table 1, Z = 0 at the base, Z up); probe approaches along -N\n");
    s.push_str("UNITS/MM,ANGDEC\n");
    s.push_str("MODE/PROG,MAN\n");
    for p in points {
        let label = format!("P{}_{}", p.id, p.curve.name());
        let xyzijk = format!(
            "{:.9},{:.9},{:.9},{:.9},{:.9},{:.9}",
            p.point.x, p.point.y, p.point.z, p.normal.x, p.normal.y, p.normal.z
        );
        let _ = writeln!(s, "F({label})=FEAT/POINT,CART,{xyzijk}");
        let _ = writeln!(s, "MEAS/POINT,F({label}),1");
        let _ = writeln!(s, "PTMEAS/CART,{xyzijk}");
        s.push_str("ENDMES\n");
    }
    s.push_str("ENDFIL\n");
    s
}

/// Six numbers after `prefix` on a DMIS line.
fn six(rest: &str, line: usize, text: &str) -> Result<[f64; 6], PlanError> {
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

/// The points of a DMIS program written by [`write_dmis`] (or any program with
/// `F(label)=FEAT/POINT,CART,x,y,z,i,j,k` features each followed by a `MEAS/POINT,F(label),n`
/// block with one `PTMEAS/CART,x,y,z,i,j,k`), in file order.
pub fn read_dmis_points(text: &str) -> Result<Vec<DmisPoint>, PlanError> {
    let mut out: Vec<DmisPoint> = Vec::new();
    let mut pending: Option<(String, [f64; 6])> = None;
    let mut measuring: Option<String> = None;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let t = raw.trim();
        let bad = |message| PlanError::Dmis {
            line,
            message,
            text: t.to_string(),
        };
        if t.starts_with("$$") || t.is_empty() {
            continue;
        }
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
            let (label, f) = match (&measuring, &pending) {
                (Some(m), Some((l, f))) if m == l => (l.clone(), *f),
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
}
