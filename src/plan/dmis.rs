//! The plan as a DMIS program (ISO 22093, Dimensional Measuring Interface Standard) a CMM runs:
//!
//! ```text
//! DMISMN/'testpiece S-shape measurement plan',05.3
//! $$ header comments
//! UNITS/MM,ANGDEC
//! S(A000B1800)=SNSDEF/PROBE,INDEX,POL,tilt,azimuth,0,0,-1,50,4.000   per stylus orientation
//! SNSLCT/S(A000B1800)                     vertical for the datums; others between touches
//! SNSET/APPRCH,3.000 and SNSET/RETRCT,3.000
//! MODE/MAN                                                 the datums, touched by hand
//! F(DATUM_A)=FEAT/PLANE,CART,x,y,z,i,j,k                   (fixture.rs: A, B, C)
//! MEAS/PLANE,F(DATUM_A),4 / PTMEAS/CART,x,y,z,i,j,k ... / ENDMES
//! DATDEF/FA(DATUM_A),DAT(A)
//! D(FIXTURE)=DATSET/DA(A),ZDIR,ZORIG,DA(B),YDIR,YORIG,DA(C),XORIG
//! D(PART)=TRANS/XORIG,-160,YORIG,-120,ZORIG,10              the part frame
//! MODE/PROG,MAN                                            the points, programmed
//! GOTO/x,y,z                                               clearance moves (probe_path.rs)
//! F(P7_A_Z11)=FEAT/POINT,CART,x,y,z,i,j,k
//! MEAS/POINT,F(P7_A_Z11),1 / PTMEAS/CART,x,y,z,i,j,k / ENDMES
//! OUTPUT/FA(P7_A_Z11)                                      per point, after the last
//! ENDFIL
//! ```
//!
//! `x,y,z` the nominal position (mm, the part frame of `shared/spec/s-shape.md`: origin at the
//! part origin, Z up from the base), `i,j,k` the outward unit normal `N`: the DMIS approach
//! vector, the probe touching along `−N` (from outside the wall). `GOTO` positions are the tip
//! centre. Labels are `P<id>_<curve>`. The points' numbers are written with 9 decimals (1e-9
//! mm), so the file reads back to the plan's points within 5e-10 mm ([`super::dmis_read`]);
//! `GOTO`s with 3. The text is ASCII only (the header's σ, µ, √ spelt out), every line at
//! most [`MAX_LINE`] characters: a longer statement is cut after a comma and continued on the
//! next line, the cut marked by `$` at the end of the line; `$$` starts a comment.

use nalgebra::Vector3;

use super::fixture::{datum_planes, PART_ORIGIN_IN_DATUM_FRAME};
use super::probe_path::{
    probe_path, Obstacles, PathStep, ProbeReplay, Touch, APPROACH_DISTANCE, STYLUS_LENGTH,
    TIP_DIAMETER,
};
use super::stylus::Stylus;
use super::PlanError;
use crate::part::MeasurementPoint;

/// Longest line of the program (characters).
pub const MAX_LINE: usize = 80;

/// A DMIS program and the replay of its probe path.
#[derive(Debug, Clone, PartialEq)]
pub struct DmisProgram {
    pub text: String,
    pub replay: ProbeReplay,
}

/// The DMIS label of a plan's point.
pub fn point_label(p: &MeasurementPoint) -> String {
    format!("P{}_{}", p.id, p.curve.name())
}

/// `s` in printable ASCII (line breaks kept, other control characters made spaces): the
/// symbols of the plan's notes spelt out, anything else outside ASCII `?`.
pub fn ascii_text(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '\n' => out.push('\n'),
            c if c.is_ascii_control() => out.push(' '),
            c if c.is_ascii() => out.push(c),
            'σ' => out.push_str("sigma"),
            'µ' | 'μ' => out.push('u'),
            '√' => out.push_str("sqrt"),
            '≤' => out.push_str("<="),
            '≥' => out.push_str(">="),
            '±' => out.push_str("+/-"),
            '×' => out.push('x'),
            '−' | '–' | '—' => out.push('-'),
            '·' => out.push('*'),
            '°' => out.push_str(" deg"),
            '→' => out.push_str("->"),
            _ => out.push('?'),
        }
    }
    out
}

/// The lines of one statement: cut after commas so that each line, with its `$`, keeps within
/// [`MAX_LINE`] characters.
pub fn statement_lines(stmt: &str) -> Vec<String> {
    if stmt.len() <= MAX_LINE {
        return vec![stmt.to_string()];
    }
    let mut lines = Vec::new();
    let mut cur = String::new();
    for piece in stmt.split_inclusive(',') {
        if !cur.is_empty() && cur.len() + piece.len() + 1 > MAX_LINE {
            cur.push('$');
            lines.push(std::mem::take(&mut cur));
        }
        cur.push_str(piece);
    }
    lines.push(cur);
    lines
}

/// `$$` comment lines of `text` (ASCII), cut at spaces within [`MAX_LINE`] characters.
fn comment_lines(text: &str) -> Vec<String> {
    let mut lines = Vec::new();
    for raw in ascii_text(text).lines() {
        let mut cur = String::from("$$");
        for word in raw.split_whitespace() {
            if cur.len() > 2 && cur.len() + 1 + word.len() > MAX_LINE {
                lines.push(std::mem::replace(&mut cur, String::from("$$")));
            }
            cur.push(' ');
            cur.push_str(&word[..word.len().min(MAX_LINE - 3)]);
        }
        lines.push(cur);
    }
    lines
}

struct Writer(String);

impl Writer {
    fn stmt(&mut self, s: &str) {
        for l in statement_lines(s) {
            self.0.push_str(&l);
            self.0.push('\n');
        }
    }
    fn comment(&mut self, s: &str) {
        for l in comment_lines(s) {
            self.0.push_str(&l);
            self.0.push('\n');
        }
    }
    fn step(&mut self, s: &PathStep) {
        match s {
            PathStep::Goto(g) => self.stmt(&format!("GOTO/{:.3},{:.3},{:.3}", g.x, g.y, g.z)),
            PathStep::Index(st) => self.stmt(&format!("SNSLCT/S({})", st.label())),
        }
    }
}

fn xyzijk(p: &Vector3<f64>, n: &Vector3<f64>) -> String {
    format!(
        "{:.9},{:.9},{:.9},{:.9},{:.9},{:.9}",
        p.x, p.y, p.z, n.x, n.y, n.z
    )
}

/// The DMIS program of `points` (module docs) with its probe path replayed against `obs`;
/// each line of `header` becomes a `$$` comment.
pub fn write_dmis(
    points: &[MeasurementPoint],
    header: &str,
    obs: &Obstacles,
) -> Result<DmisProgram, PlanError> {
    let touches: Vec<Touch> = points
        .iter()
        .map(|p| Touch::new(p.point, p.normal))
        .collect();
    let ids: Vec<usize> = points.iter().map(|p| p.id).collect();
    let path = probe_path(obs, &touches, &ids)?;
    let r = &path.replay;
    let mut w = Writer(String::new());
    w.stmt("DMISMN/'testpiece S-shape measurement plan',05.3");
    w.comment(header);
    w.comment(&format!(
        "Part frame of the ISO 10791-7 S-shape (paper 000 Table 1, Z = 0 at the base, Z up), \
         set by datums A, B, C of the fixture plate (top face z = -10 mm, edge faces y = +120 \
         mm and x = +160 mm). Probe: tip diameter {} mm, stylus {} mm on an indexable \
         head (tilt and azimuth in 7.5 deg steps; tilted away from the wall where it overhangs), \
         indexed with the tip centre at Z = {} mm. Approach along -N, approach and retract {} \
         mm. Start the programmed part with the probe at Z >= {} mm. Moves between touches \
         keep {:.3} mm from the part and plate (replayed; sampled {:.3} mm less the sampling \
         bound {:.3} mm); {} of {} moves cleared by GOTOs.",
        r.tip_diameter,
        r.stylus_length,
        r.index_z,
        r.approach_distance,
        r.safe_z,
        r.min_distance_certain,
        r.min_distance,
        r.sampling_bound,
        r.cleared_moves,
        r.cleared_moves + r.straight_moves
    ));
    w.stmt("UNITS/MM,ANGDEC");
    let mut styli: Vec<Stylus> = vec![Stylus::VERTICAL];
    for t in &touches {
        if !styli.contains(&t.stylus) {
            styli.push(t.stylus);
        }
    }
    for st in &styli {
        w.stmt(&format!(
            "S({})=SNSDEF/PROBE,INDEX,POL,{:.1},{:.1},0,0,-1,{STYLUS_LENGTH:.3},{TIP_DIAMETER:.3}",
            st.label(),
            st.tilt_deg,
            st.azimuth_deg
        ));
    }
    w.stmt(&format!("SNSLCT/S({})", Stylus::VERTICAL.label()));
    w.stmt(&format!("SNSET/APPRCH,{APPROACH_DISTANCE:.3}"));
    w.stmt(&format!("SNSET/RETRCT,{APPROACH_DISTANCE:.3}"));
    w.comment("Datums of the fixture plate, touched by hand (machine coordinates).");
    w.stmt("MODE/MAN");
    let datums = datum_planes();
    for d in &datums {
        let n = &d.normal;
        let short = |p: &Vector3<f64>| {
            format!(
                "{:.3},{:.3},{:.3},{:.3},{:.3},{:.3}",
                p.x, p.y, p.z, n.x, n.y, n.z
            )
        };
        w.stmt(&format!(
            "F({})=FEAT/PLANE,CART,{}",
            d.label,
            short(&d.point)
        ));
        w.stmt(&format!("MEAS/PLANE,F({}),{}", d.label, d.touches.len()));
        for t in &d.touches {
            w.stmt(&format!("PTMEAS/CART,{}", short(t)));
        }
        w.stmt("ENDMES");
        w.stmt(&format!("DATDEF/FA({}),DAT({})", d.label, d.datum));
    }
    let [a, b, c] = &datums;
    w.stmt(&format!(
        "D(FIXTURE)=DATSET/DA({}),ZDIR,ZORIG,DA({}),YDIR,YORIG,DA({}),XORIG",
        a.datum, b.datum, c.datum
    ));
    let [ox, oy, oz] = PART_ORIGIN_IN_DATUM_FRAME;
    w.stmt(&format!(
        "D(PART)=TRANS/XORIG,{ox:.3},YORIG,{oy:.3},ZORIG,{oz:.3}"
    ));
    w.comment("The points, programmed, in the part frame.");
    w.stmt("MODE/PROG,MAN");
    for (p, steps) in points.iter().zip(&path.before) {
        for s in steps {
            w.step(s);
        }
        let label = point_label(p);
        let v = xyzijk(&p.point, &p.normal);
        w.stmt(&format!("F({label})=FEAT/POINT,CART,{v}"));
        w.stmt(&format!("MEAS/POINT,F({label}),1"));
        w.stmt(&format!("PTMEAS/CART,{v}"));
        w.stmt("ENDMES");
    }
    for s in &path.after {
        w.step(s);
    }
    w.comment("The measured points (actual features).");
    for p in points {
        w.stmt(&format!("OUTPUT/FA({})", point_label(p)));
    }
    w.stmt("ENDFIL");
    Ok(DmisProgram {
        text: w.0,
        replay: path.replay,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_statement_is_cut_after_commas() {
        let s = format!("PTMEAS/CART,{}", ["-123.123456789"; 6].join(","));
        let lines = statement_lines(&s);
        assert!(lines.len() == 2, "{lines:?}");
        assert!(lines.iter().all(|l| l.len() <= MAX_LINE));
        assert!(lines[0].ends_with(",$"));
        let joined: String = lines
            .iter()
            .map(|l| l.strip_suffix('$').unwrap_or(l))
            .collect();
        assert_eq!(joined, s);
    }

    #[test]
    fn comments_are_ascii() {
        let c = comment_lines("σ = 1.2 µm (MPE/√3)");
        assert_eq!(c, vec!["$$ sigma = 1.2 um (MPE/sqrt3)".to_string()]);
    }
}
