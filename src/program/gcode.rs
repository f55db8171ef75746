//! The part program in a controller's dialect ([`Dialect`]) from the moves of [`motion`]:
//!
//! 1. header comments; the safe start block (mm, XY plane, absolute, feed per minute, cutter
//!    radius, length offset and canned cycles cancelled; Klartext: `BEGIN PGM … MM`);
//! 2. Z to the machine's home in machine coordinates (`G53 G00 Z0`, `G0 SUPA Z0`,
//!    `L Z+0 R0 FMAX M91`), then the tool call with its length compensation, spindle on
//!    clockwise, flood coolant (one M code a block: Fanuc's default);
//! 3. per surface the rapids of [`motion`] (Z, then the rotary axes, then X Y, then Z down,
//!    each block naming only the axes it moves), the feed move along the tool axis into the
//!    pass, the pass, the feed move along the axis out of it;
//! 4. Z home again, spindle and coolant off, end of program.
//!
//! **Feed on the pass.** In machine axes (no TCP) the pass's blocks turn the rotary axes, so a
//! per-minute F would be spread over linear and rotary words differently by every controller:
//! the pass is written in inverse time, `G93` with `F = feed / (tip path length of the block)`
//! (1/min), every block carrying its F (RS274/NGC and LinuxCNC require it), and `G94` again
//! for the moves along the axis. Klartext has no inverse time: each block's F is the feed that
//! makes the contouring feed over the combined axis distance (mm and degrees counted alike)
//! give the programmed tip speed. With `tcp` the controller holds the tip speed itself: the
//! program is the tip in the part frame and the rotary angles, `G94 F feed`.
//!
//! **Words.** Linear axes in mm and rotary axes in degrees with [`Dialect::decimals`] decimals
//! (8 significant digits at most); rounding moves a tool point by at most
//! [`rounding_bound`] (mm), the read-back bound of the tool path. Values are those of the
//! inverse kinematics without TCP (the part origin at the chain's machine zero, as the
//! analysis assumes), or the tip with TCP.

use std::fmt::Write;

use super::dialect::{feed_number, number, Dialect};
use super::motion::{Group, Motion, StepKind};
use crate::machine::direct::nominal;
use crate::machine::{AxisKind, AxisName, AxisValues, Chain};
use crate::numerics::order::sort_by_index;

/// What the G-code writer needs beside the moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GcodeSettings {
    pub dialect: Dialect,
    /// Tool-centre-point mode (only where [`Dialect::offers_tcp`]).
    pub tcp: bool,
    /// Feed of the pass (mm/min).
    pub feed: f64,
    /// Spindle speed (1/min).
    pub spindle: f64,
    /// Tool number (also its length-offset register).
    pub tool: u32,
}

/// Program name of the Klartext program and the Fanuc program number.
pub const PROGRAM_NAME: &str = "SSHAPE";
pub const PROGRAM_NUMBER: u32 = 1019;

/// The chain's axes in the order X, Y, Z, A, B, C.
pub fn program_axes(chain: &Chain) -> Vec<AxisName> {
    let mut a: Vec<_> = chain.axes().map(|a| a.name).collect();
    sort_by_index(&mut a, |n| n.index());
    a
}

/// The largest move (mm) of a tool point (tip to `reach` mm above it) when every axis word of
/// the positions `qs` is rounded to `decimals` decimals: Σ over axes of half an increment
/// times the largest |∂ point / ∂ axis| over the positions (central differences).
pub fn rounding_bound(chain: &Chain, qs: &[AxisValues], decimals: usize, reach: f64) -> f64 {
    let half = 0.5 * 10f64.powi(-(decimals as i32));
    program_axes(chain)
        .into_iter()
        .map(|a| {
            let (step, unit) = match a.kind() {
                AxisKind::Linear => (1e-3, 1.0),
                AxisKind::Rotary => (1e-5, std::f64::consts::PI / 180.0),
            };
            let lever = qs
                .iter()
                .flat_map(|q| [0.0, reach].map(|h| (q, h)))
                .map(|(q, h)| {
                    let (mut p, mut m) = (*q, *q);
                    p.set(a, q.get(a) + step);
                    m.set(a, q.get(a) - step);
                    (nominal(chain, &p, h).point - nominal(chain, &m, h).point).norm()
                        / (2.0 * step)
                })
                .fold(0.0, f64::max);
            half * unit * lever
        })
        .sum()
}

/// The words of one block for the axes of `group`. With TCP the linear words are the tip, which
/// a move of machine Z or of X and Y alone moves along all three on a tilting table: such a
/// block names all three.
fn words(d: Dialect, axes: &[AxisName], vals: &[f64], group: Group, tcp: bool) -> String {
    let group = match group {
        Group::Z | Group::Xy if tcp => Group::Linear,
        g => g,
    };
    axes.iter()
        .zip(vals)
        .filter(|(a, _)| group.names(**a))
        .map(|(a, v)| {
            format!(
                "{}{}",
                a.letter(),
                number(*v, d.decimals(), d == Dialect::Heidenhain)
            )
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The values written for `q`: the machine axes, or with TCP the tip (part frame) then the
/// rotary axes; rotary axes in degrees.
fn values(chain: &Chain, axes: &[AxisName], q: &AxisValues, tcp: bool) -> Vec<f64> {
    let tip = nominal(chain, q, 0.0).point;
    axes.iter()
        .map(|&a| match (a.kind(), tcp) {
            (AxisKind::Rotary, _) => q.get(a).to_degrees(),
            (AxisKind::Linear, true) => tip[a.index()],
            (AxisKind::Linear, false) => q.get(a),
        })
        .collect()
}

/// A program being written: numbered blocks for Klartext.
struct Out {
    d: Dialect,
    text: String,
    block: usize,
}

impl Out {
    fn line(&mut self, s: &str) {
        if self.d == Dialect::Heidenhain {
            let _ = writeln!(self.text, "{} {s}", self.block);
        } else {
            let _ = writeln!(self.text, "{s}");
        }
        self.block += 1;
    }
    fn comment(&mut self, s: &str) {
        let c = self.d.comment(s);
        self.line(&c);
    }
    /// A move: rapid, or feed with its F word (None: modal).
    fn motion(&mut self, rapid: bool, words: &str, f: Option<String>) {
        if words.is_empty() {
            return;
        }
        let line = match self.d {
            Dialect::Heidenhain => {
                let feed = if rapid {
                    " FMAX".to_string()
                } else {
                    f.map_or(String::new(), |f| format!(" F{f}"))
                };
                format!("L {words} R0{feed}")
            }
            Dialect::Sinumerik => {
                let g = if rapid { "G0" } else { "G1" };
                format!(
                    "{g} {words}{}",
                    f.map_or(String::new(), |f| format!(" F{f}"))
                )
            }
            _ => {
                let g = if rapid { "G00" } else { "G01" };
                format!(
                    "{g} {words}{}",
                    f.map_or(String::new(), |f| format!(" F{f}"))
                )
            }
        };
        self.line(&line);
    }
    fn home(&mut self) {
        let l = match self.d {
            Dialect::Sinumerik => "G0 SUPA Z0",
            Dialect::Heidenhain => "L Z+0 R0 FMAX M91",
            _ => "G53 G00 Z0",
        };
        self.line(l);
    }
}

/// The program text of `motion` on `chain` with `header` lines as comments.
pub fn write_gcode(chain: &Chain, header: &str, motion: &Motion, s: &GcodeSettings) -> String {
    let d = s.dialect;
    let tcp = s.tcp && d.offers_tcp();
    let axes = program_axes(chain);
    let mut o = Out {
        d,
        text: String::new(),
        block: 0,
    };
    match d {
        Dialect::Heidenhain => o.line(&format!("BEGIN PGM {PROGRAM_NAME} MM")),
        Dialect::Sinumerik => {}
        Dialect::Fanuc => o.text.push_str(&format!("%\nO{PROGRAM_NUMBER}\n")),
        _ => o.text.push_str("%\n"),
    }
    for l in header.lines() {
        o.comment(l);
    }
    match d {
        Dialect::Sinumerik => {
            o.line("G17 G71 G90 G94 G40");
            o.line("TRAFOOF");
        }
        Dialect::Heidenhain => {}
        _ => o.line("G21 G17 G90 G94 G40 G49 G80"),
    }
    let t = s.tool;
    let rpm = number(s.spindle, 0, false);
    let mut prev: Option<AxisValues> = None;
    let mut inverse = false;
    let mut started = false;
    let mut m_pending: Vec<&str> = Vec::new();
    let mut modal_feed: Option<String> = None;
    for st in &motion.steps {
        match st.kind {
            StepKind::Home => {
                if started {
                    if tcp {
                        o.line(match d {
                            Dialect::Fanuc => "G49",
                            Dialect::Sinumerik => "TRAFOOF",
                            _ => "FUNCTION RESET TCPM",
                        });
                    }
                    o.home();
                    match d {
                        Dialect::Heidenhain => {
                            o.line("L Z+0 R0 FMAX M91 M5");
                            o.line("L Z+0 R0 FMAX M91 M9");
                            o.line("L Z+0 R0 FMAX M91 M30");
                            o.line(&format!("END PGM {PROGRAM_NAME} MM"));
                        }
                        Dialect::Sinumerik => {
                            o.line("M5");
                            o.line("M9");
                            o.line("M30");
                        }
                        _ => {
                            o.line("M05");
                            o.line("M09");
                            o.line("M30");
                            o.text.push_str("%\n");
                        }
                    }
                    continue;
                }
                started = true;
                o.home();
                match d {
                    Dialect::Heidenhain => {
                        o.line(&format!("TOOL CALL {t} Z S{rpm}"));
                        m_pending = vec!["M8", "M3"];
                    }
                    Dialect::Sinumerik => {
                        o.line(&format!("T{t} M6"));
                        o.line(&format!("D{t}"));
                        o.line(&format!("S{rpm} M3"));
                        o.line("M8");
                    }
                    _ => {
                        o.line(&format!("T{t} M06"));
                        if !tcp {
                            o.line(&format!("G43 H{t}"));
                        }
                        o.line(&format!("S{rpm} M03"));
                        o.line("M08");
                    }
                }
                if tcp {
                    o.line(&match d {
                        Dialect::Fanuc => format!("G43.4 H{t}"),
                        Dialect::Sinumerik => "TRAORI".to_string(),
                        _ => "FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS".to_string(),
                    });
                }
                prev = Some(motion.start);
                // The start's words are unknown to the controller: write every axis once.
                continue;
            }
            StepKind::Rapid => {
                let v = values(chain, &axes, &st.q, tcp);
                let w = words(d, &axes, &v, st.group, tcp);
                match m_pending.pop() {
                    Some(m) => o.line(&format!("L {w} R0 FMAX {m}")),
                    None => o.motion(true, &w, None),
                }
            }
            StepKind::Approach | StepKind::Exit | StepKind::Cut => {
                if st.kind == StepKind::Approach {
                    o.comment(&format!(
                        "surface {}: along the tool axis into the pass",
                        st.surface.map_or("", |s| s.name())
                    ));
                }
                let from = prev.unwrap_or(motion.start);
                let v = values(chain, &axes, &st.q, tcp);
                let cut = st.kind == StepKind::Cut;
                let f = if tcp || !cut {
                    if inverse {
                        o.line("G94");
                        inverse = false;
                        modal_feed = None;
                    }
                    let f = feed_number(s.feed);
                    // Klartext's FMAX holds for its block only, and an F after it would be
                    // read as the last F: write F on every feed block there and on LinuxCNC.
                    if !matches!(d, Dialect::Linuxcnc | Dialect::Heidenhain)
                        && modal_feed.as_deref() == Some(f.as_str())
                    {
                        None
                    } else {
                        modal_feed = Some(f.clone());
                        Some(f)
                    }
                } else {
                    let tip = (nominal(chain, &st.q, 0.0).point - nominal(chain, &from, 0.0).point)
                        .norm()
                        .max(1e-6);
                    if d.inverse_time() {
                        if !inverse {
                            o.line("G93");
                            inverse = true;
                        }
                        modal_feed = None;
                        Some(feed_number(s.feed / tip))
                    } else {
                        let combined: f64 = axes
                            .iter()
                            .map(|&a| {
                                let dv = st.q.get(a) - from.get(a);
                                if a.kind() == AxisKind::Rotary {
                                    dv.to_degrees()
                                } else {
                                    dv
                                }
                            })
                            .map(|x| x * x)
                            .sum::<f64>()
                            .sqrt();
                        modal_feed = None;
                        Some(feed_number(s.feed * combined.max(tip) / tip))
                    }
                };
                let w = words(d, &axes, &v, st.group, tcp);
                o.motion(false, &w, f);
                if st.kind == StepKind::Exit {
                    o.comment("out of the pass along the tool axis, clear of the part");
                }
            }
        }
        prev = Some(st.q);
    }
    o.text
}
