//! An NC controller trace as tool positions (paper 000 §5.1: the Sinumerik 840D captures the
//! five axis positions every 8 ms; the geometric deviations are then computed as for a CAM
//! path).
//!
//! The file is CSV with a header naming the machine's axes (`X, Y, Z, B, C` for paper 000's B
//! head / C table; any chain of [`crate::machine::Chain`] through a machine description) and
//! optionally `time` (s, or `time [ms]`); other columns are ignored. Linear axes in mm, rotary
//! axes in degrees (or rad when the machine description says `"angle_unit": "rad"`). Each row is
//! turned into a tool position by the **nominal** direct kinematics of the chain
//! ([`crate::machine::direct::nominal`], paper 000 eq. 9 for its machine: `x = X cos C + Y sin C
//! − L0 cos C sin B`, …): the path the controller commanded in the part frame. The machine's
//! own geometric errors are a separate source of the budget (identified), so error values listed
//! in a machine description are not applied here.
//!
//! Bad rows are listed with line, column, text found and what was expected (cmm-csv.md);
//! `NaN`/`inf` are refused; times must not decrease.

use super::cl::{header_separator, number_problem};
use super::{decode_text, reject, BudgetError, LineProblem, ToolPath, MAX_POSITIONS};
use crate::cmm::delimited::{excerpt, split, Separator};
use crate::cmm::lines::classify;
use crate::cmm::number::parse_number;
use crate::cmm::ColumnRef;
use crate::machine::chain::PAPER000_L0;
use crate::machine::description::{AngleUnit, MachineDescription};
use crate::machine::direct::nominal;
use crate::machine::{AxisKind, AxisValues, Chain};
use crate::numerics::order::sort_by_index;

/// The machine a trace is replayed through: its chain and the unit of its rotary values.
#[derive(Debug, Clone, PartialEq)]
pub struct TraceMachine {
    /// For messages and the report (`paper 000 B head / C table, L0 = …` or the description's).
    pub name: String,
    pub chain: Chain,
    pub angle_unit: AngleUnit,
}

impl Default for TraceMachine {
    fn default() -> Self {
        Self::paper000(PAPER000_L0)
    }
}

impl TraceMachine {
    /// Paper 000's B head / C table with pivot-to-tip length `l0` (mm), angles in degrees.
    pub fn paper000(l0: f64) -> Self {
        Self {
            name: format!("paper 000 B head / C table (w C Y' b X Z B t), L0 = {l0} mm"),
            chain: Chain::paper000(l0),
            angle_unit: AngleUnit::Deg,
        }
    }

    /// The machine of a JSON description (`testpiece forward --machine FILE`).
    pub fn from_description(d: &MachineDescription) -> Result<Self, BudgetError> {
        Ok(Self {
            name: if d.name.is_empty() {
                d.code.clone()
            } else {
                format!("{} ({})", d.name, d.code)
            },
            chain: d.chain()?,
            angle_unit: d.angle_unit,
        })
    }

    /// The chain's axes in the order X, Y, Z, A, B, C.
    pub fn axis_names(&self) -> Vec<crate::machine::AxisName> {
        let mut a: Vec<_> = self.chain.axes().map(|a| a.name).collect();
        sort_by_index(&mut a, |n| n.index());
        a
    }

    /// Nominal tool tip (mm) and unit tool axis in the part frame for axis values `q` (mm, rad).
    pub fn tool_position(&self, q: &AxisValues) -> ([f64; 3], [f64; 3]) {
        let t = nominal(&self.chain, q, 0.0);
        let (p, w) = (t.point, t.direction);
        ([p.x, p.y, p.z], [w.x, w.y, w.z])
    }
}

fn normalise(h: &str) -> (String, Option<String>) {
    let s = h.trim().trim_matches('"').to_lowercase();
    let unit = s
        .find(['[', '('])
        .map(|k| s[k + 1..].trim_end_matches([']', ')']).trim().to_string());
    let base = match s.find(['[', '(']) {
        Some(k) => &s[..k],
        None => &s[..],
    };
    (
        base.chars()
            .filter(|c| !matches!(c, ' ' | '_' | '-' | '.'))
            .collect(),
        unit,
    )
}

/// Reads a controller trace and replays it through `machine` (module docs).
pub fn read_trace(
    bytes: &[u8],
    name: &str,
    machine: &TraceMachine,
) -> Result<ToolPath, BudgetError> {
    let text = decode_text(bytes, name)?;
    let lines = classify(&text);
    let axes = machine.axis_names();
    let letters: Vec<String> = axes.iter().map(|a| a.letter().to_string()).collect();
    let Some(&(header_line, head)) = lines.content.first() else {
        return Err(BudgetError::NoPositions {
            name: name.to_string(),
            expected: format!(
                "a header row {} (optional time) and one row of axis values per sample",
                letters.join(",")
            ),
        });
    };
    let (sep, header) = header_separator(head);
    let names: Vec<(String, Option<String>)> = header.iter().map(|h| normalise(h)).collect();
    let mut cols = Vec::new();
    let mut missing = Vec::new();
    for (a, l) in axes.iter().zip(&letters) {
        match names.iter().position(|(n, _)| n == &l.to_lowercase()) {
            Some(c) => cols.push((*a, c)),
            None => missing.push(l.clone()),
        }
    }
    if cols.is_empty() {
        return Err(BudgetError::NoHeader {
            name: name.to_string(),
            line: header_line,
            found: excerpt(head),
            expected: format!(
                "a header row naming the axes of {}: {} (and optionally time)",
                machine.chain.code(),
                letters.join(",")
            ),
        });
    }
    if !missing.is_empty() {
        return Err(BudgetError::MissingColumns {
            name: name.to_string(),
            line: header_line,
            missing: format!("{} (axes of {})", missing.join(", "), machine.chain.code()),
            found: header.join(", "),
        });
    }
    let time_col = names
        .iter()
        .position(|(n, _)| matches!(n.as_str(), "time" | "t" | "timestamp"));
    let time_scale = match time_col.and_then(|c| names[c].1.as_deref()) {
        Some("ms") => 1e-3,
        _ => 1.0,
    };
    let to_rad = machine.angle_unit.to_rad();
    let decimal_comma = sep != Separator::Comma;
    let data = &lines.content[1..];
    if data.len() > MAX_POSITIONS {
        return Err(BudgetError::TooManyPositions {
            name: name.to_string(),
            found: data.len(),
            limit: MAX_POSITIONS,
        });
    }
    let mut path = ToolPath {
        name: name.to_string(),
        format: format!("trace {} through {}", letters.join(","), machine.name),
        tips: Vec::with_capacity(data.len()),
        axes: Vec::with_capacity(data.len()),
        lines: Vec::with_capacity(data.len()),
        times: time_col.map(|_| Vec::with_capacity(data.len())),
        cutter_diameter: None,
        notes: Vec::new(),
    };
    let mut problems = Vec::new();
    let mut last_time: Option<(usize, f64)> = None;
    for &(line, row) in data {
        let fields = split(row, sep);
        let column = |c: usize| ColumnRef {
            number: c + 1,
            name: header[c].clone(),
        };
        let mut q = AxisValues::default();
        let mut ok = true;
        for &(a, c) in &cols {
            let Some(f) = fields.get(c) else {
                problems.push(LineProblem {
                    line,
                    column: Some(column(c)),
                    reason: "truncated row".into(),
                    found: excerpt(row),
                    expected: format!("{} fields like the header", header.len()),
                });
                ok = false;
                break;
            };
            let rotary = a.kind() == AxisKind::Rotary;
            match parse_number(f, decimal_comma) {
                Ok(v) => q.set(a, if rotary { v * to_rad } else { v }),
                Err(e) => {
                    let unit = if !rotary {
                        "mm"
                    } else if to_rad == 1.0 {
                        "rad"
                    } else {
                        "degrees"
                    };
                    problems.push(number_problem(line, column(c), f, e, unit));
                    ok = false;
                }
            }
        }
        if let Some(c) = time_col.filter(|_| ok) {
            let f = fields.get(c).map(String::as_str).unwrap_or("");
            match parse_number(f, decimal_comma) {
                Ok(t) => {
                    let t = t * time_scale;
                    if let Some((l0, t0)) = last_time.filter(|&(_, t0)| t < t0) {
                        problems.push(LineProblem {
                            line,
                            column: Some(column(c)),
                            reason: "time goes backwards".into(),
                            found: f.trim().to_string(),
                            expected: format!("a time >= {t0} s (line {l0})"),
                        });
                        ok = false;
                    } else {
                        last_time = Some((line, t));
                        if let Some(ts) = path.times.as_mut() {
                            ts.push(t);
                        }
                    }
                }
                Err(e) => {
                    problems.push(number_problem(line, column(c), f, e, "s"));
                    ok = false;
                }
            }
        }
        if ok {
            let (tip, axis) = machine.tool_position(&q);
            path.tips.push(tip);
            path.axes.push(axis);
            path.lines.push(line);
        }
    }
    reject(name, problems)?;
    if path.is_empty() {
        return Err(BudgetError::NoPositions {
            name: name.to_string(),
            expected: format!("rows of axis values {} after the header", letters.join(",")),
        });
    }
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq9_closed_form_of_paper000() {
        // paper 000 eq. 9: x = X cos C + Y sin C − L0 cos C sin B, y = −X sin C + Y cos C +
        // L0 sin B sin C, z = Z − L0 cos B; tool axis from eq. 9's tan C = −j/i, tan B = √(i²+j²)/k.
        let m = TraceMachine::paper000(499.889);
        let csv = "time [ms],X,Y,Z,B,C\n0,10,20,530,12,30\n8,11,21,531,-5,200\n";
        let p = read_trace(csv.as_bytes(), "t.csv", &m).unwrap();
        assert_eq!(p.times, Some(vec![0.0, 0.008]));
        let l0 = 499.889;
        for (r, (x, y, z, b, c)) in [
            (10.0, 20.0, 530.0, 12.0f64, 30.0f64),
            (11.0, 21.0, 531.0, -5.0, 200.0),
        ]
        .into_iter()
        .enumerate()
        {
            let (b, c) = (b.to_radians(), c.to_radians());
            let ex = [
                x * c.cos() + y * c.sin() - l0 * c.cos() * b.sin(),
                -x * c.sin() + y * c.cos() + l0 * b.sin() * c.sin(),
                z - l0 * b.cos(),
            ];
            for (got, want) in p.tips[r].iter().zip(ex) {
                crate::assert_near!(*got, want, 1e-9);
            }
            let w = p.axes[r];
            crate::assert_near!(w[2], b.cos(), 1e-12);
            crate::assert_near!((w[0] * w[0] + w[1] * w[1]).sqrt(), b.sin().abs(), 1e-12);
        }
    }

    #[test]
    fn bad_rows_name_line_and_column() {
        let m = TraceMachine::default();
        let csv =
            "t,X,Y,Z,B,C\n0.01,1,2,3,4,5\n0.02,1,2,abc,4,5\n0.005,1,2,3,4,5\n0.03,1,2,3,inf,5\n";
        let e = read_trace(csv.as_bytes(), "t.csv", &m)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(
                "line 3, column 4 'Z': not a number: found 'abc', expected a finite number (mm)"
            ),
            "{e}"
        );
        assert!(
            e.contains("line 4, column 1 't': time goes backwards"),
            "{e}"
        );
        assert!(e.contains("line 5, column 5 'B': not a finite number: found 'inf', expected a finite number (degrees)"), "{e}");
        let e = read_trace(b"X,Y,Z,C\n1,2,3,4\n", "t.csv", &m)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 1: required column missing: B"), "{e}");
    }
}
