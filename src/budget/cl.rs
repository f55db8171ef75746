//! CAM cutter-location files as tool positions (paper 000 §4.1: the programs TP1S1 … TP4S1 are
//! lists of tool positions with a tool axis, computed with a 0.5 mm point distance).
//!
//! Two formats, both in the part frame (mm), the tip of the flat end mill (eq. 2's `T_tool`) and
//! the tool axis from the tip towards the spindle (eq. 2's `R(u)`):
//! - **CSV** with a header row naming `x, y, z, i, j, k` (case-insensitive, ignoring spaces,
//!   `_`, `-`, `.` and a unit in brackets; also `tipx …`, `axisx …`); separator comma,
//!   semicolon, tab or spaces (decimal comma where the separator is not a comma); other columns
//!   ignored;
//! - **APT / CL data** as CAM systems write it: `GOTO/x,y,z,i,j,k` per position (`GOTO/x,y,z`
//!   after a `TLAXIS/i,j,k`), `$` continues a record on the next line, `$$` starts a comment.
//!   Records that do not move the tool are recognised and ignored (`PARTNO`, `UNITS/MM` (or
//!   `INCHES`: converted), `MULTAX`, `CUTTER/d` (diameter kept for the report), `FEDRAT`,
//!   `RAPID`, `SPINDL`, `COOLNT`, `LOADTL`, `FROM`, `FINI`, `END`, …); records that would move
//!   the tool along geometry testpiece cannot evaluate (`GOFWD`, `CIRCLE`, `TRANS`, …) and
//!   unknown words are reported.
//!
//! Every bad line is listed with its line, column (field), the text found and what was expected,
//! as for CMM files (cmm-csv.md); `NaN`/`inf` are refused; a tool axis must be a unit vector to
//! 1e-3 (CAM files round to 6-7 digits; it is then normalised).

use super::{decode_text, reject, BudgetError, LineProblem, ToolPath, MAX_POSITIONS};
use crate::cmm::delimited::{excerpt, split, Separator};
use crate::cmm::lines::classify;
use crate::cmm::number::{parse_number, NumberError};
use crate::cmm::ColumnRef;

/// Largest departure of `|(i, j, k)|` from 1 accepted (then normalised).
pub const AXIS_NORM_TOL: f64 = 1e-3;

const FIELDS: [&str; 6] = ["x", "y", "z", "i", "j", "k"];

/// APT words that carry no tool motion testpiece needs: recognised and skipped.
const IGNORED: [&str; 34] = [
    "PARTNO", "MULTAX", "FEDRAT", "RAPID", "SPINDL", "COOLNT", "LOADTL", "FROM", "FINI", "END",
    "PPRINT", "REMARK", "MACHIN", "CLPRNT", "NOPOST", "TOOLNO", "SELCTL", "INTOL", "OUTTOL",
    "TLON", "TLRGT", "TLLFT", "AUTOPS", "OPSKIP", "DISPLY", "INSERT", "STOP", "OPSTOP", "TPRINT",
    "SEQNO", "DELAY", "CUTCOM", "PITCH", "HEAD",
];
/// APT words that move the tool along geometry (or change the frame): not supported.
const UNSUPPORTED: [&str; 12] = [
    "GOFWD", "GOLFT", "GORGT", "GOBACK", "GOUP", "GODLTA", "CIRCLE", "INDIRV", "TRANS", "ORIGIN",
    "CYCLE", "GO",
];

/// Reads a CL file (CSV or APT, module docs). `name` is used in messages.
pub fn read_cl(bytes: &[u8], name: &str) -> Result<ToolPath, BudgetError> {
    let text = decode_text(bytes, name)?;
    let lines = classify(&text);
    let Some(&(first_line, first)) = lines.content.first() else {
        return Err(BudgetError::NoPositions {
            name: name.to_string(),
            expected: "a header row x,y,z,i,j,k and one tool position per line, or APT GOTO/x,y,z,i,j,k records".into(),
        });
    };
    let path = if looks_like_apt(first) {
        read_apt(&lines.all, name)?
    } else {
        read_csv(&lines.content, name, first_line)?
    };
    if path.is_empty() {
        return Err(BudgetError::NoPositions {
            name: name.to_string(),
            expected: if path.format == "APT" {
                "GOTO/x,y,z,i,j,k records".into()
            } else {
                "one tool position x,y,z,i,j,k per line after the header".into()
            },
        });
    }
    Ok(path)
}

fn looks_like_apt(line: &str) -> bool {
    let t = line.trim();
    if t.starts_with("$$") {
        return true;
    }
    let word: String = t
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric())
        .collect::<String>()
        .to_ascii_uppercase();
    let rest = t[word.len()..].trim_start();
    (rest.starts_with('/') && word.chars().next().is_some_and(|c| c.is_ascii_alphabetic()))
        || IGNORED.contains(&word.as_str()) && rest.is_empty()
}

/// Header name as matched: lower case, unit in brackets dropped, spaces `_ - .` removed.
fn normalise(h: &str) -> String {
    let mut s = h.trim().trim_matches('"').to_lowercase();
    for open in ['[', '('] {
        if let Some(k) = s.find(open) {
            s.truncate(k);
        }
    }
    s.chars()
        .filter(|c| !matches!(c, ' ' | '_' | '-' | '.'))
        .collect()
}

fn role(h: &str) -> Option<usize> {
    let n = normalise(h);
    let names: [&[&str]; 6] = [
        &["x", "tipx", "xtip", "clx", "px"],
        &["y", "tipy", "ytip", "cly", "py"],
        &["z", "tipz", "ztip", "clz", "pz"],
        &["i", "axisx", "toolaxisx", "ax", "u"],
        &["j", "axisy", "toolaxisy", "ay", "v"],
        &["k", "axisz", "toolaxisz", "az", "w"],
    ];
    names.iter().position(|alts| alts.contains(&n.as_str()))
}

/// Problem for a field that did not parse.
pub(crate) fn number_problem(
    line: usize,
    column: ColumnRef,
    field: &str,
    e: NumberError,
    what: &str,
) -> LineProblem {
    let reason = match e {
        NumberError::Empty => "empty value",
        NumberError::NotNumeric => "not a number",
        NumberError::NotFinite => "not a finite number",
    };
    LineProblem {
        line,
        column: Some(column),
        reason: reason.into(),
        found: field.trim().to_string(),
        expected: format!("a finite number ({what})"),
    }
}

/// A unit tool axis from `(i, j, k)`, or the reason it is not one.
pub(crate) fn unit_axis(v: [f64; 3]) -> Result<[f64; 3], f64> {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if (n - 1.0).abs() <= AXIS_NORM_TOL {
        Ok([v[0] / n, v[1] / n, v[2] / n])
    } else {
        Err(n)
    }
}

fn axis_problem(line: usize, v: [f64; 3], n: f64, column: Option<ColumnRef>) -> LineProblem {
    LineProblem {
        line,
        column,
        reason: "tool axis is not a unit vector".into(),
        found: format!("({}, {}, {}) of length {n}", v[0], v[1], v[2]),
        expected: format!("a unit tool axis i, j, k (length 1 ± {AXIS_NORM_TOL})"),
    }
}

fn new_path(name: &str, format: &str) -> ToolPath {
    ToolPath {
        name: name.to_string(),
        format: format.to_string(),
        tips: Vec::new(),
        axes: Vec::new(),
        lines: Vec::new(),
        times: None,
        cutter_diameter: None,
        notes: Vec::new(),
    }
}

fn too_many(name: &str, found: usize) -> BudgetError {
    BudgetError::TooManyPositions {
        name: name.to_string(),
        found,
        limit: MAX_POSITIONS,
    }
}

/// The separator of a header line: tab, semicolon or comma where one splits it, else spaces.
pub(crate) fn header_separator(line: &str) -> (Separator, Vec<String>) {
    for s in [Separator::Tab, Separator::Semicolon, Separator::Comma] {
        let f = split(line, s);
        if f.len() >= 2 {
            return (s, f);
        }
    }
    (Separator::Spaces, split(line, Separator::Spaces))
}

fn read_csv(
    content: &[(usize, &str)],
    name: &str,
    header_line: usize,
) -> Result<ToolPath, BudgetError> {
    let (sep, header) = header_separator(content[0].1);
    let mut cols = [None; 6];
    for (c, h) in header.iter().enumerate() {
        if let Some(r) = role(h) {
            cols[r].get_or_insert(c);
        }
    }
    if cols.iter().all(Option::is_none) {
        let numeric = header
            .iter()
            .filter(|f| parse_number(f, sep != Separator::Comma).is_ok())
            .count();
        let hint = if numeric * 2 >= header.len() {
            " (the first line holds numbers: the header row is missing)"
        } else {
            ""
        };
        return Err(BudgetError::NoHeader {
            name: name.to_string(),
            line: header_line,
            found: excerpt(content[0].1),
            expected: format!(
                "a header row x,y,z,i,j,k (CSV) or APT records such as GOTO/x,y,z,i,j,k{hint}"
            ),
        });
    }
    let missing: Vec<&str> = (0..6)
        .filter(|&r| cols[r].is_none())
        .map(|r| FIELDS[r])
        .collect();
    if !missing.is_empty() {
        return Err(BudgetError::MissingColumns {
            name: name.to_string(),
            line: header_line,
            missing: missing.join(", "),
            found: header.join(", "),
        });
    }
    let cols: Vec<usize> = cols.iter().flatten().copied().collect();
    let decimal_comma = sep != Separator::Comma;
    let mut path = new_path(name, "CSV x,y,z,i,j,k");
    let mut problems = Vec::new();
    let data = &content[1..];
    if data.len() > MAX_POSITIONS {
        return Err(too_many(name, data.len()));
    }
    for &(line, text) in data {
        let fields = split(text, sep);
        let mut v = [0.0; 6];
        let mut ok = true;
        for (r, &c) in cols.iter().enumerate() {
            let column = ColumnRef {
                number: c + 1,
                name: header[c].clone(),
            };
            let Some(field) = fields.get(c) else {
                problems.push(LineProblem {
                    line,
                    column: Some(column),
                    reason: "truncated row".into(),
                    found: excerpt(text),
                    expected: format!("{} fields like the header", header.len()),
                });
                ok = false;
                break;
            };
            match parse_number(field, decimal_comma) {
                Ok(x) => v[r] = x,
                Err(e) => {
                    let what = if r < 3 { "mm" } else { "tool axis component" };
                    problems.push(number_problem(line, column, field, e, what));
                    ok = false;
                }
            }
        }
        if !ok {
            continue;
        }
        let a = [v[3], v[4], v[5]];
        match unit_axis(a) {
            Ok(axis) => {
                path.tips.push([v[0], v[1], v[2]]);
                path.axes.push(axis);
                path.lines.push(line);
            }
            Err(n) => problems.push(axis_problem(line, a, n, None)),
        }
    }
    reject(name, problems)?;
    Ok(path)
}

/// Records of an APT file: `(first line, text)` with `$` continuations joined and `$$`
/// comments removed.
fn apt_records(all: &[&str]) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut pending: Option<(usize, String)> = None;
    for (k, raw) in all.iter().enumerate() {
        let line = k + 1;
        let mut t = raw.trim_matches(|c: char| c.is_whitespace() || c == '\u{1A}');
        if let Some(p) = t.find("$$") {
            t = t[..p].trim_end();
        }
        let (body, cont) = match t.strip_suffix('$') {
            Some(b) => (b.trim_end(), true),
            None => (t, false),
        };
        let rec = match pending.take() {
            Some((l, mut s)) => {
                s.push_str(body);
                (l, s)
            }
            None => (line, body.to_string()),
        };
        if cont {
            pending = Some(rec);
        } else if !rec.1.trim().is_empty() {
            out.push(rec);
        }
    }
    if let Some(rec) = pending {
        if !rec.1.trim().is_empty() {
            out.push(rec);
        }
    }
    out
}

fn read_apt(all: &[&str], name: &str) -> Result<ToolPath, BudgetError> {
    let mut path = new_path(name, "APT");
    let mut problems = Vec::new();
    let mut scale = 1.0;
    let mut tlaxis: Option<[f64; 3]> = None;
    let mut ignored: Vec<String> = Vec::new();
    for (line, rec) in apt_records(all) {
        let (word, args) = match rec.split_once('/') {
            Some((w, a)) => (w.trim().to_ascii_uppercase(), Some(a.trim().to_string())),
            None => (rec.trim().to_ascii_uppercase(), None),
        };
        let numbers = |what: &str, problems: &mut Vec<LineProblem>| -> Option<Vec<f64>> {
            let a = args.as_deref().unwrap_or("");
            let mut out = Vec::new();
            let mut ok = true;
            for (c, f) in a.split(',').enumerate() {
                let column = ColumnRef {
                    number: c + 1,
                    name: format!("{word} field {}", c + 1),
                };
                match parse_number(f, false) {
                    Ok(v) => out.push(v),
                    Err(e) => {
                        problems.push(number_problem(line, column, f, e, what));
                        ok = false;
                    }
                }
            }
            ok.then_some(out)
        };
        match word.as_str() {
            "GOTO" => {
                let Some(v) = numbers("mm or tool axis component", &mut problems) else {
                    continue;
                };
                let axis = match v.len() {
                    6 => match unit_axis([v[3], v[4], v[5]]) {
                        Ok(a) => a,
                        Err(n) => {
                            problems.push(axis_problem(
                                line,
                                [v[3], v[4], v[5]],
                                n,
                                Some(ColumnRef {
                                    number: 4,
                                    name: "GOTO i".into(),
                                }),
                            ));
                            continue;
                        }
                    },
                    3 => match tlaxis {
                        Some(a) => a,
                        None => {
                            problems.push(LineProblem {
                                line,
                                column: None,
                                reason: "tool axis missing".into(),
                                found: excerpt(&rec),
                                expected: "GOTO/x,y,z,i,j,k, or a TLAXIS/i,j,k record before GOTO/x,y,z".into(),
                            });
                            continue;
                        }
                    },
                    n => {
                        problems.push(LineProblem {
                            line,
                            column: None,
                            reason: "wrong number of values".into(),
                            found: format!("{n} value(s) in '{}'", excerpt(&rec)),
                            expected: "GOTO/x,y,z,i,j,k (6 values) or GOTO/x,y,z (3)".into(),
                        });
                        continue;
                    }
                };
                if path.tips.len() >= MAX_POSITIONS {
                    return Err(too_many(name, path.tips.len() + 1));
                }
                path.tips.push([v[0] * scale, v[1] * scale, v[2] * scale]);
                path.axes.push(axis);
                path.lines.push(line);
            }
            "TLAXIS" => {
                if let Some(v) = numbers("tool axis component", &mut problems) {
                    if v.len() < 3 {
                        problems.push(LineProblem {
                            line,
                            column: None,
                            reason: "wrong number of values".into(),
                            found: excerpt(&rec),
                            expected: "TLAXIS/i,j,k".into(),
                        });
                    } else {
                        match unit_axis([v[0], v[1], v[2]]) {
                            Ok(a) => tlaxis = Some(a),
                            Err(n) => problems.push(axis_problem(line, [v[0], v[1], v[2]], n, None)),
                        }
                    }
                }
            }
            "UNITS" => match args.as_deref().map(|a| a.trim().to_ascii_uppercase()).as_deref() {
                Some("MM") => scale = 1.0,
                Some("INCHES") | Some("INCH") => {
                    scale = 25.4;
                    path.notes.push(format!("line {line}: UNITS/INCHES: positions converted to mm"));
                }
                other => problems.push(LineProblem {
                    line,
                    column: Some(ColumnRef {
                        number: 1,
                        name: "UNITS field 1".into(),
                    }),
                    reason: "unknown unit".into(),
                    found: other.unwrap_or("").to_string(),
                    expected: "UNITS/MM or UNITS/INCHES".into(),
                }),
            },
            "CUTTER" => {
                let first = args.as_deref().unwrap_or("").split(',').next().unwrap_or("");
                match parse_number(first, false) {
                    Ok(d) if d > 0.0 => path.cutter_diameter = Some(d * scale),
                    Ok(d) => problems.push(LineProblem {
                        line,
                        column: Some(ColumnRef {
                            number: 1,
                            name: "CUTTER diameter".into(),
                        }),
                        reason: "not a tool diameter".into(),
                        found: d.to_string(),
                        expected: "a positive diameter (mm)".into(),
                    }),
                    Err(e) => problems.push(number_problem(
                        line,
                        ColumnRef {
                            number: 1,
                            name: "CUTTER diameter".into(),
                        },
                        first,
                        e,
                        "tool diameter",
                    )),
                }
            }
            w if IGNORED.contains(&w) => {
                if !ignored.iter().any(|x| x == w) {
                    ignored.push(w.to_string());
                }
            }
            w if UNSUPPORTED.contains(&w) => problems.push(LineProblem {
                line,
                column: None,
                reason: "unsupported record".into(),
                found: excerpt(&rec),
                expected: "tool positions as GOTO/x,y,z,i,j,k (export the path as points)".into(),
            }),
            _ => problems.push(LineProblem {
                line,
                column: None,
                reason: "unrecognised record".into(),
                found: excerpt(&rec),
                expected: "GOTO/x,y,z,i,j,k, TLAXIS/i,j,k, UNITS/MM, CUTTER/d or a record that does not move the tool (PARTNO, MULTAX, FEDRAT, RAPID, SPINDL, COOLNT, LOADTL, FROM, FINI, …)".into(),
            }),
        }
    }
    reject(name, problems)?;
    if !ignored.is_empty() {
        path.notes.push(format!(
            "records ignored (no tool motion): {}",
            ignored.join(", ")
        ));
    }
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_and_apt_give_the_same_positions() {
        let csv = "# a CL file\nx,y,z,i,j,k\n1,2,3,0,0,1\n4;5\n";
        let e = read_cl(csv.as_bytes(), "a.csv").unwrap_err().to_string();
        assert!(e.contains("line 4, column 1 'x'"), "{e}");
        let csv = "X [mm], Y, Z, I, J, K, feed\n1,2,3,0,0.6,0.8,100\n4,5,6,0,0,1.0000004,100\n";
        let p = read_cl(csv.as_bytes(), "a.csv").unwrap();
        let apt = "PARTNO/TEST\nUNITS/MM\nMULTAX\nCUTTER/20.000\n$$ comment\nFEDRAT/100\nGOTO/1,2,3,$\n0,0.6,0.8\nTLAXIS/0,0,1\nGOTO/4,5,6\nFINI\n";
        let q = read_cl(apt.as_bytes(), "a.apt").unwrap();
        assert_eq!(p.tips, q.tips);
        assert_eq!(q.lines, vec![7, 10]);
        assert_eq!(q.cutter_diameter, Some(20.0));
        for (a, b) in p.axes.iter().zip(&q.axes) {
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn bad_lines_are_listed_with_line_and_column() {
        let apt = "GOTO/1,2,nan,0,0,1\nGOFWD/(CIRCLE/0,0,0,5)\nFOO/1\nGOTO/1,2,3,0,0,2\n";
        let e = read_cl(apt.as_bytes(), "p.apt").unwrap_err().to_string();
        assert!(e.contains("4 bad line(s)"), "{e}");
        assert!(
            e.contains("line 1, column 3 'GOTO field 3': not a finite number: found 'nan'"),
            "{e}"
        );
        assert!(e.contains("line 2: unsupported record"), "{e}");
        assert!(
            e.contains("line 3: unrecognised record: found 'FOO/1'"),
            "{e}"
        );
        assert!(
            e.contains("line 4, column 4 'GOTO i': tool axis is not a unit vector"),
            "{e}"
        );
    }
}
