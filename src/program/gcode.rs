//! ISO 6983 G-code of the finishing pass in the machine axes of a chain, and its reading back.
//!
//! Written: `%`, a program number, `( … )` header comments, `G21 G90 G94 G17` (mm, absolute,
//! feed per minute, XY plane), then per surface a rapid `G00` to the first position raised
//! [`RETRACT`] mm along the tool axis (same rotary angles), the `G01` blocks of the pass (the
//! feed on the first), a `G00` retract, and `M30`, `%`. Every block names every axis of the chain
//! (`X Y Z B C`, or `X Y Z A B` for the A-B head), linear axes in mm with 7 decimals and rotary
//! axes in degrees with 8 decimals: rounding moves a tool point by less than 1e-7 mm + L0 ×
//! 1e-10 rad, far inside the read-back check (1e-6 mm). The values are those of the inverse
//! kinematics without tool-centre-point management (RTCP / TRAORI off): the part origin is at
//! the chain's machine zero, as the analysis assumes.
//!
//! Read back ([`read_gcode`]): the `G01` blocks as axis values (mm, rad), modal as a controller
//! reads them (G00/G01 and every axis value stay until changed); comments `( … )` and `;` are
//! skipped; `N` block numbers, `F`, `M`, `O`, `T`, `S` words are accepted and ignored.

use std::fmt::Write;

use super::ProgramError;
use crate::machine::{AxisKind, AxisName, AxisValues, Chain};
use crate::numerics::order::sort_by_index;

/// Height of the approach and retract above the first and last positions, along the tool
/// axis (mm).
pub const RETRACT: f64 = 50.0;

/// The chain's axes in the order X, Y, Z, A, B, C.
pub fn program_axes(chain: &Chain) -> Vec<AxisName> {
    let mut a: Vec<_> = chain.axes().map(|a| a.name).collect();
    sort_by_index(&mut a, |n| n.index());
    a
}

/// One block's axis words: `X… Y… Z… B… C…` (mm with 7 decimals, degrees with 8).
pub fn axis_words(axes: &[AxisName], q: &AxisValues) -> String {
    axes.iter()
        .map(|&a| match a.kind() {
            AxisKind::Linear => format!("{}{:.7}", a.letter(), q.get(a)),
            AxisKind::Rotary => format!("{}{:.8}", a.letter(), q.get(a).to_degrees()),
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// One pass as written: a title comment, the approach and retract axis values, the G01 blocks.
pub struct GcodePass<'a> {
    pub title: String,
    pub approach: AxisValues,
    pub blocks: &'a [AxisValues],
    pub retract: AxisValues,
}

/// The G-code program: header comments (each line in parentheses), then the passes.
pub fn write_gcode(chain: &Chain, header: &str, passes: &[GcodePass], feed: f64) -> String {
    let axes = program_axes(chain);
    let mut s = String::from("%\nO1019\n");
    for line in header.lines() {
        // Parentheses end a comment on most controllers: none inside.
        let clean: String = line
            .chars()
            .map(|c| match c {
                '(' => '[',
                ')' => ']',
                c => c,
            })
            .collect();
        let _ = writeln!(s, "({})", clean.trim_end());
    }
    s.push_str("G21 G90 G94 G17\n");
    for p in passes {
        let _ = writeln!(s, "({})", p.title.replace('(', "[").replace(')', "]"));
        let _ = writeln!(s, "G00 {}", axis_words(&axes, &p.approach));
        for (k, q) in p.blocks.iter().enumerate() {
            if k == 0 {
                let _ = writeln!(s, "G01 {} F{feed:.1}", axis_words(&axes, q));
            } else {
                let _ = writeln!(s, "G01 {}", axis_words(&axes, q));
            }
        }
        let _ = writeln!(s, "G00 {}", axis_words(&axes, &p.retract));
    }
    s.push_str("M30\n%\n");
    s
}

/// The `G01` blocks of a G-code program for `chain` as axis values (mm, rad), in order; modal
/// motion and axis values as a controller keeps them (module docs).
pub fn read_gcode(text: &str, chain: &Chain) -> Result<Vec<AxisValues>, ProgramError> {
    let axes = program_axes(chain);
    let mut q = AxisValues::default();
    let mut motion: Option<u32> = None;
    let mut out = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let bad = |message| ProgramError::GCode {
            line,
            message,
            text: raw.trim().to_string(),
        };
        let mut code = String::new();
        let mut depth = 0;
        for c in raw.split(';').next().unwrap_or("").chars() {
            match c {
                '(' => depth += 1,
                ')' if depth > 0 => depth -= 1,
                _ if depth == 0 => code.push(c.to_ascii_uppercase()),
                _ => {}
            }
        }
        let code = code.trim();
        if code.is_empty() || code == "%" {
            continue;
        }
        let mut moved = false;
        let mut chars = code.char_indices().peekable();
        while let Some((i, c)) = chars.next() {
            if c.is_whitespace() {
                continue;
            }
            if !c.is_ascii_alphabetic() {
                return Err(bad("expected a word: a letter and a number"));
            }
            let mut end = i + 1;
            while let Some(&(j, d)) = chars.peek() {
                if d.is_ascii_digit() || d == '.' || d == '-' || d == '+' {
                    end = j + d.len_utf8();
                    chars.next();
                } else {
                    break;
                }
            }
            let value: f64 = code[i + 1..end]
                .parse()
                .map_err(|_| bad("expected a number after the letter"))?;
            match c {
                'G' => {
                    if value == 0.0 || value == 1.0 {
                        motion = Some(value as u32);
                    }
                }
                _ => {
                    if let Some(a) = AxisName::from_letter(c).filter(|a| axes.contains(a)) {
                        q.set_in_units(a, value, std::f64::consts::PI / 180.0);
                        moved = true;
                    } else if !matches!(c, 'N' | 'F' | 'M' | 'O' | 'T' | 'S' | 'D' | 'H') {
                        return Err(bad("a word this reader does not know"));
                    }
                }
            }
        }
        if moved && motion == Some(1) {
            out.push(q);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::chain::PAPER000_L0;

    /// Modal G01 and axis values; comments skipped; degrees to rad.
    #[test]
    fn reads_modal_blocks() {
        let chain = Chain::paper000(PAPER000_L0);
        let t = "%\n(hello (x))\nG00 X1 Y2 Z3 B0 C0\nG01 X1.5 F100 ; cut\nY-2.25 C90.\nM30\n";
        let q = read_gcode(t, &chain).unwrap();
        assert_eq!(q.len(), 2);
        assert_eq!((q[0].x, q[0].y, q[0].z), (1.5, 2.0, 3.0));
        assert_eq!(q[1].y, -2.25);
        assert!((q[1].c - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let e = read_gcode("G01 X1 Q2\n", &chain).unwrap_err();
        assert_eq!(
            e.to_string(),
            "G-code line 1: a word this reader does not know (found `G01 X1 Q2`)"
        );
    }
}
