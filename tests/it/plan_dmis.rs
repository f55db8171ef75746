//! The plan's DMIS program (issue 32 item 3), read as a CMM would read it:
//! - **grammar**: every statement (continued lines joined) matches one of the ISO 22093
//!   statement forms of [`FORMS`], written from memory of DMIS 5.x / ISO 22093:2011 (its
//!   statements are defined one per subclause of the statement chapter, by name; the text was
//!   not at hand, so no subclause numbers are given and the argument orders below are as
//!   remembered, not as checked against the standard);
//! - **structure**: `DMISMN` first, `ENDFIL` last; each `MEAS/…,F(x),n` follows the definition
//!   of `F(x)` and holds exactly `n` `PTMEAS` before its `ENDMES`; `DATDEF` and `OUTPUT` name
//!   measured features; `DATSET` names defined datums; `SNSLCT` defined sensors; every planned
//!   point output once;
//! - **characters**: ASCII only, every line at most 80 characters, `$` only as the last
//!   character of a continued line or in a `$$` comment;
//! - **replay**: the programmed part (after `MODE/PROG,MAN`) re-read from the text (the
//!   `GOTO`s, the `SNSLCT`s with the tilt and azimuth of their `SNSDEF`, each `PTMEAS`'s
//!   straight move to its approach point) and replayed against the walls and plate: no move
//!   comes within 2 mm of them (the sampled distance less the sampling bound); the smallest
//!   distance is printed.

use std::collections::{HashMap, HashSet};

use nalgebra::Vector3;
use testpiece::plan::dmis::MAX_LINE;
use testpiece::plan::probe_path::{
    Obstacles, APPROACH_DISTANCE, INDEX_Z, PROBE_CLEARANCE, SAFE_Z, TIP_DIAMETER,
};
use testpiece::plan::stylus::Stylus;
use testpiece::plan::{dmis_statements, plan, read_dmis_points, PlanOptions};

/// The statement forms checked: `{n}` a number (`[+-]digits[.digits]`), `{i}` an unsigned
/// integer, `{l}` a label (letters, digits, `_`, at most 16), `{d}` a datum letter, `{s}` a
/// quoted text without `'`.
const FORMS: [(&str, &str); 19] = [
    (
        "DMISMN/'{s}',{n}",
        "DMISMN: program start, title and DMIS version",
    ),
    ("UNITS/MM,ANGDEC", "UNITS: millimetres, decimal degrees"),
    (
        "S({l})=SNSDEF/PROBE,INDEX,POL,{n},{n},{n},{n},{n},{n},{n}",
        "SNSDEF: indexable probe, tilt, rotation, stylus vector i,j,k, length, tip diameter",
    ),
    ("SNSLCT/S({l})", "SNSLCT: select a defined sensor"),
    ("SNSET/APPRCH,{n}", "SNSET: approach distance"),
    ("SNSET/RETRCT,{n}", "SNSET: retract distance"),
    ("MODE/MAN", "MODE: manual"),
    ("MODE/PROG,MAN", "MODE: programmed moves"),
    (
        "F({l})=FEAT/PLANE,CART,{n},{n},{n},{n},{n},{n}",
        "FEAT/PLANE: point and normal",
    ),
    (
        "F({l})=FEAT/POINT,CART,{n},{n},{n},{n},{n},{n}",
        "FEAT/POINT: point and vector",
    ),
    ("MEAS/PLANE,F({l}),{i}", "MEAS: plane, number of points"),
    ("MEAS/POINT,F({l}),{i}", "MEAS: point, number of points"),
    (
        "PTMEAS/CART,{n},{n},{n},{n},{n},{n}",
        "PTMEAS: nominal point and approach vector",
    ),
    ("ENDMES", "ENDMES: end of a measurement block"),
    (
        "DATDEF/FA({l}),DAT({d})",
        "DATDEF: a measured feature as a datum",
    ),
    (
        "D({l})=DATSET/DA({d}),ZDIR,ZORIG,DA({d}),YDIR,YORIG,DA({d}),XORIG",
        "DATSET: alignment from datums",
    ),
    (
        "D({l})=TRANS/XORIG,{n},YORIG,{n},ZORIG,{n}",
        "TRANS: origin moved in the current frame",
    ),
    (
        "GOTO/{n},{n},{n}",
        "GOTO: move of the probe tip (cartesian)",
    ),
    ("OUTPUT/FA({l})", "OUTPUT: report a measured feature"),
];

/// The captures of `text` against `form` (module docs), or `None`.
fn matches(form: &str, text: &str) -> Option<Vec<String>> {
    let mut caps = Vec::new();
    let (mut f, mut t) = (form, text);
    while !f.is_empty() {
        if let Some(rest) = f.strip_prefix('{') {
            let (kind, after) = rest.split_once('}')?;
            let len = match kind {
                "n" => {
                    let sign = usize::from(t.starts_with(['+', '-']));
                    let int = t[sign..].bytes().take_while(u8::is_ascii_digit).count();
                    if int == 0 {
                        return None;
                    }
                    let mut len = sign + int;
                    if t[len..].starts_with('.') {
                        let frac = t[len + 1..].bytes().take_while(u8::is_ascii_digit).count();
                        if frac == 0 {
                            return None;
                        }
                        len += 1 + frac;
                    }
                    len
                }
                "i" => t.bytes().take_while(u8::is_ascii_digit).count(),
                "l" => {
                    let l = t
                        .bytes()
                        .take_while(|b| b.is_ascii_alphanumeric() || *b == b'_')
                        .count();
                    if l > 16 {
                        return None;
                    }
                    l
                }
                "d" => usize::from(t.starts_with(|c: char| c.is_ascii_uppercase())),
                "s" => t.find('\'')?,
                _ => return None,
            };
            if len == 0 && kind != "s" {
                return None;
            }
            caps.push(t[..len].to_string());
            t = &t[len..];
            f = after;
        } else {
            let lit = f.find('{').unwrap_or(f.len());
            t = t.strip_prefix(&f[..lit])?;
            f = &f[lit..];
        }
    }
    t.is_empty().then_some(caps)
}

fn program_text() -> (testpiece::plan::Plan, testpiece::plan::DmisProgram) {
    let opts = PlanOptions::default();
    let p = plan(&opts.prepare().unwrap(), &opts).unwrap();
    let d = p.dmis().unwrap();
    (p, d)
}

#[test]
fn every_statement_has_a_form_of_iso_22093() {
    let (p, d) = program_text();
    let stmts = dmis_statements(&d.text);
    let mut used: HashSet<usize> = HashSet::new();
    let (mut features, mut measured) = (HashSet::new(), HashSet::new());
    let (mut datums, mut sensors, mut outputs) = (HashSet::new(), HashSet::new(), Vec::new());
    let mut block: Option<(String, usize, usize)> = None;
    let last = stmts.len() - 1;
    for (k, (line, s)) in stmts.iter().enumerate() {
        if k == 0 {
            assert!(s.starts_with("DMISMN/"), "line {line}: {s}");
        }
        if s == "ENDFIL" {
            assert_eq!(k, last, "line {line}: ENDFIL before the end");
            continue;
        }
        let (f, caps) = FORMS
            .iter()
            .enumerate()
            .find_map(|(f, (form, _))| matches(form, s).map(|c| (f, c)))
            .unwrap_or_else(|| panic!("line {line}: no ISO 22093 form matches `{s}`"));
        used.insert(f);
        let head = s.split('/').next().unwrap();
        match (head, s.contains("=FEAT/")) {
            (_, true) => {
                features.insert(caps[0].clone());
            }
            ("MEAS", _) => {
                assert!(block.is_none(), "line {line}: MEAS inside a block");
                assert!(features.contains(&caps[0]), "line {line}: {s}: not defined");
                block = Some((caps[0].clone(), caps[1].parse().unwrap(), 0));
            }
            ("PTMEAS", _) => block.as_mut().expect("PTMEAS outside MEAS").2 += 1,
            ("ENDMES", _) => {
                let (f, n, got) = block.take().expect("ENDMES outside MEAS");
                assert_eq!(
                    n, got,
                    "line {line}: MEAS of {f} announces {n} points, has {got}"
                );
                measured.insert(f);
            }
            ("DATDEF", _) => {
                assert!(measured.contains(&caps[0]), "line {line}: {s}");
                datums.insert(caps[1].clone());
            }
            (h, _) if h.ends_with("=DATSET") => {
                for c in &caps[1..] {
                    assert!(datums.contains(c), "line {line}: datum {c} not defined");
                }
            }
            (h, _) if h.ends_with("=SNSDEF") => {
                sensors.insert(caps[0].clone());
            }
            ("SNSLCT", _) => assert!(sensors.contains(&caps[0]), "line {line}: {s}"),
            ("OUTPUT", _) => {
                assert!(measured.contains(&caps[0]), "line {line}: {s}");
                outputs.push(caps[0].clone());
            }
            _ => {}
        }
    }
    assert_eq!(stmts[last].1, "ENDFIL");
    let labels: Vec<String> = p
        .points
        .iter()
        .map(testpiece::plan::dmis::point_label)
        .collect();
    assert_eq!(outputs, labels, "every point output once, in order");
    println!(
        "DMIS: {} statements checked against {} forms ({} used)",
        stmts.len(),
        FORMS.len(),
        used.len()
    );
    assert_eq!(used.len(), FORMS.len(), "every form used");
    for (form, what) in FORMS {
        assert!(!what.is_empty() && form.is_ascii());
    }
}

#[test]
fn ascii_and_lines_within_80_characters() {
    let (_, d) = program_text();
    assert!(d.text.is_ascii());
    let mut longest = 0;
    for (k, l) in d.text.lines().enumerate() {
        longest = longest.max(l.len());
        assert!(
            l.len() <= MAX_LINE,
            "line {}: {} characters",
            k + 1,
            l.len()
        );
        assert!(
            l.bytes().all(|b| (b' '..=b'~').contains(&b)),
            "line {}: control character",
            k + 1
        );
        if !l.starts_with("$$") {
            let inner = l.strip_suffix('$').unwrap_or(l);
            assert!(!inner.contains('$'), "line {}: `$` inside: {l}", k + 1);
        }
    }
    println!("DMIS: longest line {longest} characters");
    let read = read_dmis_points(&d.text).unwrap();
    assert_eq!(read.len(), 100);
}

/// The sensors' orientations by label, from their `SNSDEF`.
fn sensors(stmts: &[(usize, String)]) -> HashMap<String, Stylus> {
    stmts
        .iter()
        .filter_map(|(_, s)| {
            let caps = matches(FORMS[2].0, s)?;
            let n = |k: usize| caps[k].parse::<f64>().unwrap();
            assert_eq!(n(7), TIP_DIAMETER);
            Some((
                caps[0].clone(),
                Stylus {
                    tilt_deg: n(1),
                    azimuth_deg: n(2),
                },
            ))
        })
        .collect()
}

#[test]
fn the_probe_path_keeps_2_mm_from_the_part() {
    let (_, d) = program_text();
    let stmts = dmis_statements(&d.text);
    let styli = sensors(&stmts);
    let obs = Obstacles::s_shape_on_plate();
    let start = stmts
        .iter()
        .position(|(_, s)| s == "MODE/PROG,MAN")
        .unwrap();
    let mut stylus = Stylus::VERTICAL;
    let mut at: Option<Vector3<f64>> = None;
    let (mut min, mut worst_line, mut moves) = (f64::INFINITY, 0, 0);
    let mut go = |from: &Option<Vector3<f64>>, to: Vector3<f64>, st: &Stylus, line: usize| {
        if let Some(a) = from {
            let (dist, _) = obs.move_distance(a, &to, st);
            moves += 1;
            if dist < min {
                min = dist;
                worst_line = line;
            }
        }
    };
    for (line, s) in &stmts[start..] {
        let num = |c: &[String]| -> Vec<f64> { c.iter().map(|x| x.parse().unwrap()).collect() };
        if let Some(c) = matches(FORMS[17].0, s) {
            let g = num(&c);
            let to = Vector3::new(g[0], g[1], g[2]);
            if at.is_none() {
                assert!(
                    to.z >= SAFE_Z,
                    "line {line}: first GOTO below the safe height"
                );
            }
            go(&at, to, &stylus, *line);
            at = Some(to);
        } else if let Some(c) = matches(FORMS[3].0, s) {
            let z = at.expect("SNSLCT before a GOTO").z;
            assert!(z >= INDEX_Z - 1e-9, "line {line}: head indexed at Z = {z}");
            stylus = styli[&c[0]];
        } else if let Some(c) = matches(FORMS[12].0, s) {
            let v = num(&c);
            let (p, n) = (
                Vector3::new(v[0], v[1], v[2]),
                Vector3::new(v[3], v[4], v[5]),
            );
            let approach = p + n * (0.5 * TIP_DIAMETER + APPROACH_DISTANCE);
            go(&at, approach, &stylus, *line);
            at = Some(approach);
        }
    }
    let certain = min - obs.sampling_bound();
    println!(
        "DMIS replay: {moves} moves, smallest distance {min:.3} mm sampled (line {worst_line}), \
         {certain:.3} mm less the sampling bound {:.3} mm",
        obs.sampling_bound()
    );
    assert!(moves >= 99, "{moves} moves");
    assert!(
        certain >= PROBE_CLEARANCE,
        "line {worst_line}: {certain:.3} mm < {PROBE_CLEARANCE} mm"
    );
    assert!(
        (min - d.replay.min_distance).abs() < 0.05,
        "{min} vs {}",
        d.replay.min_distance
    );
}

/// Without the clearance moves, the straight moves between consecutive touches do cross the
/// part (the finding): the replay's check is not vacuous.
#[test]
fn straight_moves_alone_would_cross_the_part() {
    let (p, _) = program_text();
    let obs = Obstacles::s_shape_on_plate();
    let (mut crossing, mut near) = (0, 0);
    for w in p.points.windows(2) {
        let a = testpiece::plan::probe_path::Touch::new(w[0].point, w[0].normal);
        let b = testpiece::plan::probe_path::Touch::new(w[1].point, w[1].normal);
        let (d, _) = obs.move_distance(&a.approach_point(), &b.approach_point(), &a.stylus);
        if d < 0.0 {
            crossing += 1;
        }
        if d < PROBE_CLEARANCE {
            near += 1;
        }
    }
    println!(
        "without GOTOs: {crossing} of 99 straight moves through the part, {near} within \
         {PROBE_CLEARANCE} mm of it (sampled)"
    );
    assert!(crossing >= 3, "{crossing}");
}

/// The fixture's plate is the program's: the same top.
#[test]
fn the_plate_is_the_programs() {
    assert_eq!(
        testpiece::plan::fixture::PLATE_TOP_Z,
        testpiece::program::motion::PLATE_TOP_Z
    );
}

/// `identify` reads the DMIS output of a measured part (`FA(P<id>_<curve>)=FEAT/POINT,CART,…`,
/// the form of `src/cmm/dmis_output.rs`, long statements continued with `$`) with the same
/// result as the CSV `id,curve,x,y,z,nx,ny,nz` of the same measured points: the example part
/// `backlash_c` (its deviations along the normals of `testpiece points`).
#[test]
fn the_dmis_output_identifies_as_the_csv() {
    let points = crate::cli_common::testpiece_ok(&["points"]);
    let devs: Vec<f64> = include_str!("../../src/examples/backlash_c.deviation")
        .split_whitespace()
        .map(|d| d.parse().unwrap())
        .collect();
    let mut csv = String::from("id,curve,x,y,z,nx,ny,nz\n");
    let mut dmo = String::from("DMISMN/'testpiece measured S-shape',05.3\nUNITS/MM,ANGDEC\n");
    for (row, d) in points.lines().skip(1).zip(&devs) {
        let f: Vec<&str> = row.split(',').collect();
        let v = |k: usize| f[k].parse::<f64>().unwrap();
        let (p, n) = (
            Vector3::new(v(4), v(5), v(6)),
            Vector3::new(v(7), v(8), v(9)),
        );
        let m = p + n * *d;
        let nums = format!(
            "{:.9},{:.9},{:.9},{:.9},{:.9},{:.9}",
            m.x, m.y, m.z, n.x, n.y, n.z
        );
        csv.push_str(&format!("{},{},{nums}\n", f[0], f[1]));
        let stmt = format!("FA(P{}_{})=FEAT/POINT,CART,{nums}", f[0], f[1]);
        for l in testpiece::plan::dmis::statement_lines(&stmt) {
            dmo.push_str(&l);
            dmo.push('\n');
        }
    }
    dmo.push_str("ENDFIL\n");
    assert!(dmo.contains("$\n"), "some statements continued");
    let dir = std::env::temp_dir().join(format!("testpiece-dmo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (fc, fd) = (dir.join("part.csv"), dir.join("part.dmo"));
    std::fs::write(&fc, csv).unwrap();
    std::fs::write(&fd, dmo).unwrap();
    let id = |f: &std::path::Path| {
        let out = crate::cli_common::testpiece_ok(&["identify", f.to_str().unwrap(), "--json"]);
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let (a, b) = (id(&fc), id(&fd));
    assert_eq!(a["points_used"], 100);
    assert_eq!(a, b, "identify on the DMIS output differs from the CSV");
    let file = testpiece::cmm::read_cmm(&std::fs::read(&fd).unwrap(), "part.dmo").unwrap();
    assert_eq!(file.format.kind, testpiece::cmm::FormatKind::DmisOutput);
    assert_eq!(file.points.len(), 100);
}
