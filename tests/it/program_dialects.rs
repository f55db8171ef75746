//! The part program in the controllers' dialects (issue 32 item 1), read by others and
//! replayed:
//! - ISO, Fanuc and LinuxCNC programs parsed by two kept PyPI parsers (`scripts/check_gcode.py`:
//!   pygcode 0.2.1, RS274/NGC's words and modal groups, and its interpreter; gcodeparser 0.3.0),
//!   installed by `scripts/setup.sh` into `target/gcode-venv`: no unknown word (Fanuc's TCP
//!   `G43.4` allowed), the safe start, tool call, length offset, spindle, coolant, G93, G53 and
//!   M05/M09 before M30 all recognised, and pygcode's interpreted axis values after every motion
//!   block equal testpiece's own reading;
//! - SINUMERIK and Heidenhain programs (no kept parser exists) checked line by line against
//!   the statement forms of their manuals;
//! - every program: ASCII, no word over 8 significant digits, no `;` inside `( … )`, the first
//!   motion a rotary-only rapid after Z went home;
//! - every program read back and replayed through the machine model with the tool (Ø20 x 60
//!   mm) and holder (Ø50 x 100 mm) swept between positions: every rapid keeps 2 mm from the
//!   walls and the base plate (after the sampling bound), no long feed move crosses the part;
//! - the CL: no feed move through the part, its rapids the same moves.

use std::path::PathBuf;
use std::process::Command;

use testpiece::machine::direct::nominal;
use testpiece::program::clearance::{replay, waypoints, Interpolation, PartGrid, CHECK_CLEARANCE};
use testpiece::program::dialect::significant_digits;
use testpiece::program::read::waypoints_of;
use testpiece::program::{program, read_program, Dialect, ProgramOptions, StepKind};
use testpiece::settings::MachineChoice;

const CASES: [(Dialect, bool); 8] = [
    (Dialect::Iso, false),
    (Dialect::Fanuc, false),
    (Dialect::Linuxcnc, false),
    (Dialect::Sinumerik, false),
    (Dialect::Heidenhain, false),
    (Dialect::Fanuc, true),
    (Dialect::Sinumerik, true),
    (Dialect::Heidenhain, true),
];

fn text_of(machine: MachineChoice, dialect: Dialect, tcp: bool) -> (ProgramOptions, String) {
    let opts = ProgramOptions {
        machine,
        dialect,
        tcp,
        ..ProgramOptions::default()
    };
    let p = program(&opts).unwrap();
    (opts, p.gcode())
}

/// ASCII, 8 significant digits at most per word, comments without `;` or nested parentheses.
fn check_words(text: &str, what: &str) {
    assert!(text.is_ascii(), "{what}: non-ASCII text");
    for (n, line) in text.lines().enumerate() {
        if let Some(i) = line.find('(') {
            let inner = &line[i + 1..line.rfind(')').unwrap()];
            assert!(
                !inner.contains(';') && !inner.contains('('),
                "{what} line {}: {line}",
                n + 1
            );
            continue;
        }
        let code = line.split(';').next().unwrap();
        for w in code.split_whitespace() {
            let mut c = w.chars();
            if c.next().is_some_and(|l| "XYZABCFSTHD".contains(l))
                && c.clone()
                    .next()
                    .is_some_and(|d| d.is_ascii_digit() || d == '-' || d == '+')
            {
                let digits = significant_digits(c.as_str());
                assert!(
                    digits <= 8,
                    "{what} line {}: {w} has {digits} digits",
                    n + 1
                );
            }
        }
    }
}

fn venv_python() -> PathBuf {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/gcode-venv/bin/python");
    assert!(
        p.exists(),
        "{} missing: run scripts/setup.sh (installs pygcode and gcodeparser from PyPI)",
        p.display()
    );
    p
}

/// ISO, Fanuc, LinuxCNC (machine axes, and Fanuc's TCP): parsed by pygcode and gcodeparser,
/// every word known, the statements a machinist needs present and in order, and pygcode's
/// interpreter reads the same axis values as testpiece after every motion block (1e-9).
#[test]
fn iso_fanuc_linuxcnc_parse_in_pygcode_and_gcodeparser() {
    let py = venv_python();
    let dir = std::env::temp_dir().join(format!("testpiece-dialects-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (d, tcp) in CASES
        .into_iter()
        .filter(|(d, _)| matches!(d, Dialect::Iso | Dialect::Fanuc | Dialect::Linuxcnc))
    {
        let (opts, text) = text_of(MachineChoice::Paper000, d, tcp);
        let what = format!("{} tcp {tcp}", d.id());
        check_words(&text, &what);
        let f = dir.join(format!("{}-{tcp}.nc", d.id()));
        std::fs::write(&f, &text).unwrap();
        let mut cmd = Command::new(&py);
        cmd.arg(format!(
            "{}/scripts/check_gcode.py",
            env!("CARGO_MANIFEST_DIR")
        ))
        .arg(&f);
        let out = cmd.output().unwrap();
        assert!(
            out.status.success(),
            "{what}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let unknown = v["unknown"].as_array().unwrap();
        let allowed = unknown.iter().all(|u| tcp && u[1] == "G43.4");
        assert!(allowed, "{what}: words pygcode does not know: {unknown:?}");
        let gcodes: Vec<&str> = v["gcodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|g| g.as_str().unwrap())
            .collect();
        let mut needed = vec![
            "GCodeUseMillimeters",
            "GCodeSelectXYPlane",
            "GCodeAbsoluteDistanceMode",
            "GCodeCutterRadiusCompOff",
            "GCodeCancelToolLengthOffset",
            "GCodeMoveInMachineCoords",
            "GCodeSelectTool",
            "GCodeToolChange",
            "GCodeSpindleSpeed",
            "GCodeStartSpindleCW",
            "GCodeCoolantFloodOn",
            "GCodeStopSpindle",
            "GCodeCoolantOff",
            "GCodeEndProgramPalletShuttle",
        ];
        if !tcp {
            needed.extend(["GCodeToolLengthOffset", "GCodeInverseTimeMode"]);
        }
        for n in needed {
            assert!(gcodes.contains(&n), "{what}: no {n} in {gcodes:?}");
        }
        let at = |s: &str| text.find(s).unwrap_or_else(|| panic!("{what}: no {s}"));
        assert!(
            at("\nM05") < at("\nM30") && at("\nM09") < at("\nM30"),
            "{what}"
        );
        assert!(
            at("G53 G00 Z0") < at("\nG00 "),
            "{what}: Z home before any move"
        );
        // pygcode's interpreter against testpiece's reading, block by block.
        let chain = opts.chain();
        let ours = read_program(&text, d, &chain).unwrap();
        let ours: Vec<_> = ours.iter().filter(|b| !b.machine).collect();
        let theirs = v["moves"].as_array().unwrap();
        let first = ours.first().unwrap();
        assert_eq!(
            first.named,
            [false, false, false, false, true, true],
            "{what}: the first move turns the rotary axes alone"
        );
        if !tcp {
            assert_eq!(ours.len(), theirs.len(), "{what}");
            let mut worst = 0.0f64;
            for (a, t) in ours.iter().zip(theirs) {
                assert_eq!(a.line as u64, t[0].as_u64().unwrap(), "{what}");
                assert_eq!(a.rapid, t[1].as_bool().unwrap(), "{what} line {}", a.line);
                let q = a.words;
                let mine = [
                    q.x,
                    q.y,
                    q.z,
                    q.a.to_degrees(),
                    q.b.to_degrees(),
                    q.c.to_degrees(),
                ];
                for (k, m) in mine.iter().enumerate() {
                    if a.named[k] || t[2 + k].as_f64().unwrap() != 0.0 {
                        worst = worst.max((m - t[2 + k].as_f64().unwrap()).abs());
                    }
                }
            }
            assert!(worst <= 1e-9, "{what}: pygcode reads {worst:e} apart");
            println!(
                "{what}: {} lines, {} motion blocks read alike by pygcode {} and testpiece; gcodeparser: {} G00/G01",
                v["lines"], theirs.len(), v["pygcode"], v["gcodeparser_moves"]
            );
        } else {
            println!(
                "{what}: {} lines parsed by pygcode (G43.4 its only unknown word, as RS274/NGC has no TCP)",
                v["lines"]
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// One SINUMERIK block against the statement forms of the 840D sl programming manual
/// (Fundamentals): `; comment`, `G17 G71 G90 G94 G40` (plane, metric, absolute, feed per
/// minute, radius compensation off), `TRAFOOF` / `TRAORI` (5-axis transformation off / on),
/// `G0 SUPA Z0` (rapid in machine coordinates, all frames suppressed), `T1 M6` (tool change),
/// `D1` (tool offset: length compensation), `S6000 M3`, `M8`, `M5`, `M9`, `M30`, `G93` /
/// `G94` (inverse-time / per-minute feed), `G0|G1 <axis words> [F<value>]`.
fn sinumerik_block(line: &str) -> bool {
    let fixed = [
        "G17 G71 G90 G94 G40",
        "TRAFOOF",
        "TRAORI",
        "G0 SUPA Z0",
        "M8",
        "M5",
        "M9",
        "M30",
        "G93",
        "G94",
    ];
    if line.starts_with("; ") || fixed.contains(&line) {
        return true;
    }
    let w: Vec<&str> = line.split_whitespace().collect();
    match w.as_slice() {
        [t, "M6"] => integer(t, 'T'),
        [d] if d.starts_with('D') => integer(d, 'D'),
        [s, "M3"] => integer(s, 'S'),
        [g, rest @ ..] if *g == "G0" || *g == "G1" => {
            let (axes, f) = match rest.last() {
                Some(f) if f.starts_with('F') && *g == "G1" => (&rest[..rest.len() - 1], Some(f)),
                _ => (rest, None),
            };
            !axes.is_empty()
                && axes.iter().all(|a| axis_word(a, false))
                && f.is_none_or(|f| decimal(&f[1..], false))
        }
        _ => false,
    }
}

/// One Klartext block (TNC 640 user's manual): `n BEGIN PGM name MM`, `n ; comment`,
/// `n TOOL CALL t Z S rpm`, `n L <axis words with sign> R0 FMAX|F<value> [M<n> …]`,
/// `n FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS`, `n FUNCTION RESET TCPM`, `n END PGM name MM`;
/// `n` the block number, from 0 by one.
fn klartext_block(line: &str, n: usize) -> bool {
    let Some(body) = line.strip_prefix(&format!("{n} ")) else {
        return false;
    };
    if body.starts_with("; ")
        || body == "BEGIN PGM SSHAPE MM"
        || body == "END PGM SSHAPE MM"
        || body == "FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS"
        || body == "FUNCTION RESET TCPM"
    {
        return true;
    }
    let w: Vec<&str> = body.split_whitespace().collect();
    match w.as_slice() {
        ["TOOL", "CALL", t, "Z", s] => t.parse::<u32>().is_ok() && integer(s, 'S'),
        ["L", rest @ ..] => {
            let Some(r) = rest.iter().position(|x| *x == "R0") else {
                return false;
            };
            let (axes, tail) = (&rest[..r], &rest[r + 1..]);
            let Some((feed, ms)) = tail.split_first() else {
                return false;
            };
            !axes.is_empty()
                && axes.iter().all(|a| axis_word(a, true))
                && (*feed == "FMAX" || (feed.starts_with('F') && decimal(&feed[1..], false)))
                && ms.iter().all(|m| integer(m, 'M'))
        }
        _ => false,
    }
}

fn integer(w: &str, letter: char) -> bool {
    w.strip_prefix(letter)
        .is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()))
}

/// `[sign]digits[.digits]`; `signed`: the sign is required (Klartext).
fn decimal(v: &str, signed: bool) -> bool {
    let body = match v.strip_prefix(['+', '-']) {
        Some(b) => b,
        None if signed => return false,
        None => v,
    };
    let mut parts = body.split('.');
    let int = parts.next().unwrap_or("");
    let frac = parts.next();
    parts.next().is_none()
        && !int.is_empty()
        && int.chars().all(|c| c.is_ascii_digit())
        && frac.is_none_or(|f| !f.is_empty() && f.chars().all(|c| c.is_ascii_digit()))
}

fn axis_word(w: &str, signed: bool) -> bool {
    let mut c = w.chars();
    c.next().is_some_and(|l| "XYZABC".contains(l)) && decimal(c.as_str(), signed)
}

/// SINUMERIK and Heidenhain programs, machine axes and TCP: every line one of the manual's
/// statement forms; the tool call, spindle, coolant, machine-coordinate retract, feed mode and
/// TCP statements present.
#[test]
fn sinumerik_and_heidenhain_follow_the_manuals_statement_forms() {
    for (d, tcp) in CASES
        .into_iter()
        .filter(|(d, _)| matches!(d, Dialect::Sinumerik | Dialect::Heidenhain))
    {
        let (_, text) = text_of(MachineChoice::Paper000, d, tcp);
        let what = format!("{} tcp {tcp}", d.id());
        check_words(&text, &what);
        for (n, line) in text.lines().enumerate() {
            let ok = match d {
                Dialect::Sinumerik => sinumerik_block(line),
                _ => klartext_block(line, n),
            };
            assert!(ok, "{what} line {}: `{line}` is no statement form", n + 1);
        }
        let needed: &[&str] = match (d, tcp) {
            (Dialect::Sinumerik, false) => &[
                "G0 SUPA Z0",
                "T1 M6",
                "D1",
                "S6000 M3",
                "M8",
                "G93",
                "M5",
                "M9",
                "M30",
            ],
            (Dialect::Sinumerik, true) => {
                &["G0 SUPA Z0", "T1 M6", "D1", "TRAORI", "TRAFOOF", "M30"]
            }
            (_, false) => &[
                "M91",
                "TOOL CALL 1 Z S6000",
                " M3",
                " M8",
                " M5",
                " M9",
                " M30",
                "END PGM",
            ],
            (_, true) => &["FUNCTION TCPM F TCP", "FUNCTION RESET TCPM", " M30"],
        };
        for n in needed {
            assert!(text.contains(n), "{what}: no `{n}`");
        }
        println!(
            "{what}: {} lines, each a statement form of the manual",
            text.lines().count()
        );
    }
}

/// Every dialect (machine axes and TCP) on the three machines, read back and replayed with the
/// tool and holder swept between positions: every rapid keeps at least 2 mm from the walls and
/// the base plate after the sampling bound; no feed move longer than 5 mm crosses the part
/// (the moves at feed outside the pass go along the tool axis); the outer ends of those keep
/// 2 mm too.
#[test]
fn replayed_programs_keep_their_clearance() {
    let grid = PartGrid::s_shape();
    let mut least = f64::INFINITY;
    for machine in [
        MachineChoice::Paper000,
        MachineChoice::Paper001,
        MachineChoice::Paper002,
    ] {
        for (d, tcp) in CASES {
            if machine != MachineChoice::Paper000
                && !matches!(d, Dialect::Iso | Dialect::Heidenhain)
            {
                continue;
            }
            let (opts, text) = text_of(machine, d, tcp);
            let chain = opts.chain();
            let p = program(&opts).unwrap();
            let blocks = read_program(&text, d, &chain).unwrap();
            let path = waypoints_of(&blocks, &chain, &p.motion.start).unwrap();
            if tcp {
                assert!(path
                    .iter()
                    .any(|w| w.interpolation == Interpolation::TipPoint));
            }
            let c = replay(&chain, &p.motion.start, &path, &grid);
            let what = format!("{} {} tcp {tcp}", machine.describe(), d.id());
            assert!(
                c.min_rapid_certain >= CHECK_CLEARANCE,
                "{what}: a rapid comes within {:.3} mm (sampled {:.3} mm, move {}): {c:?}",
                c.min_rapid_certain,
                c.min_rapid,
                c.worst_rapid
            );
            assert_eq!(c.long_feed_moves_across, 0, "{what}");
            assert!(
                c.min_axial_end - c.sampling_bound >= CHECK_CLEARANCE,
                "{what}: {c:?}"
            );
            assert!(c.rapid_moves >= 8, "{what}");
            least = least.min(c.min_rapid_certain);
            println!(
                "{what}: {} rapids, {} feed moves; rapids at least {:.3} mm from part and plate ({:.3} sampled, bound {:.3}); axial ends {:.3} mm; plate {:.3} mm below the tool at the lowest",
                c.rapid_moves, c.feed_moves, c.min_rapid_certain, c.min_rapid, c.sampling_bound, c.min_axial_end, c.min_plate
            );
        }
    }
    println!("least clearance of a rapid over every program: {least:.3} mm");
}

/// The CL: every feed move is a step of the pass (at most 5 mm) or a move along the tool axis
/// (into or out of a pass), never a move between surfaces; its RAPID positions are the
/// program's positioning moves (tip and axis of the nominal kinematics to 1e-9 mm), and those
/// moves, replayed with the tip interpolated linearly, keep 2 mm.
#[test]
fn cl_has_no_feed_move_through_the_part() {
    let opts = ProgramOptions::default();
    let p = program(&opts).unwrap();
    let cl = p.cl_apt();
    let mut rapid_next = false;
    let mut gotos: Vec<([f64; 6], bool)> = Vec::new();
    for line in cl.lines() {
        if line == "RAPID" {
            rapid_next = true;
        } else if let Some(v) = line.strip_prefix("GOTO/") {
            let v: Vec<f64> = v.split(',').map(|x| x.parse().unwrap()).collect();
            gotos.push((v.try_into().unwrap(), rapid_next));
            rapid_next = false;
        }
    }
    let mut feed_across = 0;
    let mut longest_step = 0.0f64;
    for w in gotos.windows(2) {
        let ((a, _), (b, rapid)) = (w[0], w[1]);
        if rapid {
            continue;
        }
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let cross = [
            d[1] * a[5] - d[2] * a[4],
            d[2] * a[3] - d[0] * a[5],
            d[0] * a[4] - d[1] * a[3],
        ];
        let off_axis = (cross[0].powi(2) + cross[1].powi(2) + cross[2].powi(2)).sqrt();
        if len > 5.0 && off_axis > 1e-6 * len {
            feed_across += 1;
        }
        if off_axis > 1e-6 * len {
            longest_step = longest_step.max(len);
        }
    }
    assert_eq!(feed_across, 0, "feed moves across the part in the CL");
    let rapids: Vec<_> = p
        .motion
        .steps
        .iter()
        .filter(|s| s.kind == StepKind::Rapid)
        .collect();
    let cl_rapids: Vec<_> = gotos.iter().filter(|g| g.1).collect();
    assert_eq!(rapids.len(), cl_rapids.len());
    let chain = opts.chain();
    for (s, (g, _)) in rapids.iter().zip(cl_rapids) {
        let t = nominal(&chain, &s.q, 0.0).to_array();
        for k in 0..6 {
            assert!((t[k] - g[k]).abs() <= 1e-9, "{t:?} vs {g:?}");
        }
    }
    let path: Vec<_> = waypoints(&p.motion)
        .into_iter()
        .map(|mut w| {
            w.interpolation = Interpolation::TipPoint;
            w
        })
        .collect();
    let c = replay(&chain, &p.motion.start, &path, &PartGrid::s_shape());
    assert!(c.min_rapid_certain >= CHECK_CLEARANCE, "{c:?}");
    println!(
        "CL: {} GOTO, {} after RAPID; longest feed step off the tool axis {longest_step:.4} mm; rapids (tip interpolated) at least {:.3} mm from part and plate",
        gotos.len(),
        rapids.len(),
        c.min_rapid_certain
    );
}
