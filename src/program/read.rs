//! Reading a part program of [`super::gcode`] back, as its controller would: the motion
//! blocks with their modal axis values, rapid or feed, in machine coordinates or not, with TCP
//! on or off.
//!
//! - ISO, Fanuc, LinuxCNC, SINUMERIK: words `letter number` (`G43.4`, `X-12.5`), comments
//!   `( … )` and `;` to the end of the line; the SINUMERIK keywords `SUPA` (machine
//!   coordinates), `TRAORI` / `TRAFOOF` (TCP on / off). `G00`/`G0` rapid, `G01`/`G1` feed,
//!   `G53` machine coordinates for its block, `G43.4` TCP on, `G49` off.
//! - Klartext: `n L X+… Y+… R0 FMAX|F… M…` (`FMAX` rapid, `M91` machine coordinates),
//!   `FUNCTION TCPM …` / `FUNCTION RESET TCPM`; other blocks (`BEGIN PGM`, `TOOL CALL`, `;`
//!   comments, `END PGM`) carry no motion.
//!
//! Axis values: mm, rotary axes in degrees (returned in rad); with TCP on, X Y Z are the tool
//! tip in the part frame.

use super::dialect::Dialect;
use super::ProgramError;
use crate::machine::{AxisName, AxisValues, Chain};

/// One motion block read back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReadBlock {
    /// Line in the text (1-based).
    pub line: usize,
    pub rapid: bool,
    /// A block in machine coordinates (`G53`, `SUPA`, `M91`).
    pub machine: bool,
    pub tcp: bool,
    /// The modal axis words after the block (mm, rad; tip with TCP); axes never written: 0.
    pub words: AxisValues,
    /// Which axes the block names.
    pub named: [bool; 6],
}

/// The motion blocks of `text` in `dialect` for the axes of `chain`.
pub fn read_program(
    text: &str,
    dialect: Dialect,
    chain: &Chain,
) -> Result<Vec<ReadBlock>, ProgramError> {
    let axes = super::gcode::program_axes(chain);
    let mut q = AxisValues::default();
    let mut rapid = true;
    let mut tcp = false;
    let mut out = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let bad = |message| ProgramError::GCode {
            line,
            message,
            text: raw.trim().to_string(),
        };
        let mut named = [false; 6];
        let mut machine = false;
        let mut moved = false;
        let mut set = |c: char, v: &str, q: &mut AxisValues| -> Result<bool, ProgramError> {
            match AxisName::from_letter(c).filter(|a| axes.contains(a)) {
                Some(a) => {
                    let v: f64 = v
                        .parse()
                        .map_err(|_| bad("expected a number after the letter"))?;
                    q.set_in_units(a, v, std::f64::consts::PI / 180.0);
                    named[a.index()] = true;
                    Ok(true)
                }
                None => Ok(false),
            }
        };
        if dialect == Dialect::Heidenhain {
            let body = raw.trim();
            let body = body
                .split_once(' ')
                .filter(|(n, _)| n.chars().all(|c| c.is_ascii_digit()))
                .map_or(body, |(_, b)| b);
            if body.starts_with("FUNCTION TCPM") {
                tcp = true;
            } else if body.starts_with("FUNCTION RESET TCPM") {
                tcp = false;
            }
            let Some(rest) = body.strip_prefix("L ") else {
                continue;
            };
            // FMAX holds for its block only (TNC 640 manual), F is modal.
            rapid = false;
            for w in rest.split_whitespace() {
                let (c, v) = w.split_at(1);
                let c = c.chars().next().unwrap_or(' ');
                if w == "FMAX" {
                    rapid = true;
                } else if c == 'F' {
                    rapid = false;
                } else if w == "M91" {
                    machine = true;
                } else if set(c, v, &mut q)? {
                    moved = true;
                } else if !matches!(c, 'R' | 'M') {
                    return Err(bad("a word this reader does not know"));
                }
            }
        } else {
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
            for w in code.split_whitespace() {
                match w {
                    "%" => continue,
                    "SUPA" => machine = true,
                    "TRAORI" => tcp = true,
                    "TRAFOOF" => tcp = false,
                    _ => {
                        let (c, v) = w.split_at(1);
                        let c = c.chars().next().unwrap_or(' ');
                        if c == 'G' {
                            // `G0`/`G00`, `G1`/`G01`, `G53`, `G43.4`, `G49`; others modal only.
                            let g: f64 = v.parse().map_err(|_| bad("expected a number after G"))?;
                            if g == 0.0 {
                                rapid = true;
                            } else if g == 1.0 {
                                rapid = false;
                            } else if g == 53.0 {
                                machine = true;
                            } else if g == 43.4 {
                                tcp = true;
                            } else if g == 49.0 {
                                tcp = false;
                            }
                        } else if set(c, v, &mut q)? {
                            moved = true;
                        } else if !matches!(c, 'N' | 'F' | 'M' | 'O' | 'T' | 'S' | 'D' | 'H') {
                            return Err(bad("a word this reader does not know"));
                        }
                    }
                }
            }
        }
        if moved {
            out.push(ReadBlock {
                line,
                rapid,
                machine,
                tcp,
                words: q,
                named,
            });
        }
    }
    Ok(out)
}

/// The replay's waypoints of the blocks read back ([`super::clearance::replay`]): from
/// `start` (the machine's home modelled as in [`super::motion::Motion::start`]), each motion
/// block not in machine coordinates, its unnamed axes kept, with TCP the tip solved into
/// machine axes by the chain's inverse kinematics.
pub fn waypoints_of(
    blocks: &[ReadBlock],
    chain: &Chain,
    start: &AxisValues,
) -> Result<Vec<super::clearance::Waypoint>, ProgramError> {
    use super::clearance::{Interpolation, Waypoint};
    use crate::machine::direct::nominal;
    let mut machine = *start;
    let mut out = Vec::new();
    for b in blocks.iter().filter(|b| !b.machine) {
        let mut words = machine;
        if b.tcp {
            let tip = nominal(chain, &machine, 0.0).point;
            words.x = tip.x;
            words.y = tip.y;
            words.z = tip.z;
        }
        for a in AxisName::ALL {
            if b.named[a.index()] {
                words.set(a, b.words.get(a));
            }
        }
        let q = if b.tcp {
            let tip = nalgebra::Vector3::new(words.x, words.y, words.z);
            crate::machine::inverse::solve_linear(chain, &words, &tip).map_err(|source| {
                ProgramError::TipKinematics {
                    line: b.line,
                    source,
                }
            })?
        } else {
            words
        };
        out.push(Waypoint {
            q,
            rapid: b.rapid,
            interpolation: if b.tcp {
                Interpolation::TipPoint
            } else {
                Interpolation::MachineAxes
            },
        });
        machine = q;
    }
    Ok(out)
}
