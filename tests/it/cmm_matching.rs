//! Matching to the nominal part (cmm-csv.md rules 1-4): every format variant of
//! `example_clean.csv` (tests/data/cmm/formats/) gives the canonical deviations, and the
//! projection lands on the reference points (`reference/points.csv`: surface, u, v).
//!
//! Tolerances: rule 1 formats carry the file's deviation (bit-identical, or 1e-12 mm after a µm
//! or inch conversion). Rules 2-4 use measured points written with 17 significant digits from the
//! exact nominal points: deviations agree to 1e-9 mm (asserted), limited by the projection's
//! convergence and double rounding. `u, v` agree with points.csv to 1e-9 (projection of the
//! 6-decimal canonical coordinates moves the foot by < 1e-6 mm, i.e. < 1e-8 in u).

use std::path::PathBuf;

use testpiece::assert_near;
use testpiece::cmm::{
    match_points, read_and_match, read_cmm, CmmError, DeviationRule, MatchedPart, ReadOptions,
    RowProblemKind,
};
use testpiece::part::{SShape, Surface};

fn path(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

fn matched(rel: &str) -> MatchedPart {
    let bytes = std::fs::read(path(rel)).unwrap();
    read_and_match(&bytes, rel, &ReadOptions::default()).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// Canonical deviations of example_clean.csv.
fn canonical_devs() -> Vec<f64> {
    std::fs::read_to_string(path("reference/examples/example_clean.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect()
}

/// (surface, u, v) of reference/points.csv.
fn reference_uv() -> Vec<(Surface, f64, f64)> {
    std::fs::read_to_string(path("reference/points.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let s = if f[1].starts_with('A') {
                Surface::A
            } else {
                Surface::B
            };
            (s, f[2].parse().unwrap(), f[3].parse().unwrap())
        })
        .collect()
}

#[test]
fn reference_examples_match_the_builtin_points() {
    let uv = reference_uv();
    for name in [
        "example_clean.csv",
        "example_tool_radius.csv",
        "example_backlash_c.csv",
    ] {
        let m = matched(&format!("reference/examples/{name}"));
        assert_eq!(m.points.len(), 100);
        assert!(m.warnings.is_empty(), "{name}: {:?}", m.warnings);
        for (p, &(s, u, v)) in m.points.iter().zip(&uv) {
            assert_eq!(p.rule, DeviationRule::FileDeviation);
            assert_eq!(Some(p.deviation), p.file.deviation);
            assert_eq!(p.surface, s, "{name} line {}", p.file.line);
            assert_near!(p.u, u, 1e-7);
            assert_near!(p.v, v, 1e-7);
            // Nominal positions are written with 6 decimals: on the surface to < 1 µm.
            assert!(
                p.distance.abs() < 1e-6,
                "line {}: {}",
                p.file.line,
                p.distance
            );
            // File normals have 9 decimals, positions 6: within 1e-3° (3.6").
            assert!(
                p.normal_angle_deg.unwrap() < 1e-3,
                "{:?}",
                p.normal_angle_deg
            );
        }
    }
}

#[test]
fn every_format_gives_the_canonical_deviations() {
    let devs = canonical_devs();
    let uv = reference_uv();
    // Rule-1 formats read the file's deviation (tests/it/cmm_formats.rs checks every one of them
    // against the canonical text); matching is run here on two of them and on every format
    // whose deviation comes from positions (projection is slow in debug builds).
    for (file, tol, rule) in [
        ("clean_powerinspect.txt", 0.0, DeviationRule::FileDeviation),
        ("clean_xyzijk_inch.txt", 1e-12, DeviationRule::FileDeviation),
        ("clean_inch_header.csv", 1e-12, DeviationRule::FileDeviation),
        ("clean_measured_only.csv", 1e-9, DeviationRule::Projection),
        (
            "clean_nominal_measured.csv",
            1e-9,
            DeviationRule::MeasuredMinusNominal,
        ),
        (
            "clean_nominal_measured_dev.csv",
            0.0,
            DeviationRule::FileDeviation,
        ),
    ] {
        let m = matched(&format!("cmm/formats/{file}"));
        assert_eq!(m.points.len(), 100, "{file}");
        assert!(m.warnings.is_empty(), "{file}: {:?}", m.warnings);
        let mut worst: f64 = 0.0;
        for ((p, d), &(s, u, _)) in m.points.iter().zip(&devs).zip(&uv) {
            assert_eq!(p.rule, rule, "{file}");
            assert_eq!(p.surface, s, "{file}");
            assert_near!(p.u, u, 1e-7);
            worst = worst.max((p.deviation - d).abs());
        }
        assert!(
            worst <= tol,
            "{file}: deviations differ by {worst:e} > {tol:e}"
        );
        println!("{file}: max |deviation - canonical| = {worst:e} mm");
        if rule != DeviationRule::FileDeviation || file.contains("measured") {
            // Rule 4 file: positions agree with the deviation (no warning above).
            for p in &m.points {
                if let Some(pd) = p.position_deviation {
                    assert_near!(pd, p.deviation, 1e-9);
                }
            }
        }
    }
}

/// The header and the first 20 rows of `rel`, with `f` applied to the fields of `line`.
fn edit(rel: &str, line: usize, f: impl Fn(&mut Vec<String>)) -> Vec<u8> {
    let text = std::fs::read_to_string(path(rel)).unwrap();
    let mut lines: Vec<String> = text.lines().take(21).map(str::to_string).collect();
    let mut fields: Vec<String> = lines[line - 1].split(',').map(str::to_string).collect();
    f(&mut fields);
    lines[line - 1] = fields.join(",");
    (lines.join("\n") + "\n").into_bytes()
}

const CLEAN: &str = "reference/examples/example_clean.csv";

#[test]
fn file_normal_off_by_3_degrees_or_flipped_is_warned() {
    // Rotate the normal of line 14 (n_z = 0) by 3° about z.
    let bytes = edit(CLEAN, 14, |f| {
        let (nx, ny): (f64, f64) = (f[5].parse().unwrap(), f[6].parse().unwrap());
        let a = 3f64.to_radians();
        f[5] = format!("{}", nx * a.cos() - ny * a.sin());
        f[6] = format!("{}", nx * a.sin() + ny * a.cos());
    });
    let m = read_and_match(&bytes, "n.csv", &ReadOptions::default()).unwrap();
    let w: Vec<String> = m.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("line 14") && w[0].contains("3.00°") && w[0].contains("limit 2°"),
        "{w:?}"
    );
    // Flipped normal on line 20.
    let bytes = edit(CLEAN, 20, |f| {
        for v in f.iter_mut().skip(5).take(3) {
            *v = format!("{}", -v.parse::<f64>().unwrap());
        }
    });
    let m = read_and_match(&bytes, "n.csv", &ReadOptions::default()).unwrap();
    let w = m.warnings[0].to_string();
    assert!(
        w.contains("into the material") && w.contains("line 20") && w.contains("180.00°"),
        "{w}"
    );
}

#[test]
fn rule_4_disagreement_over_1_um_is_warned() {
    let rel = "cmm/formats/clean_nominal_measured_dev.csv";
    let bytes = edit(rel, 7, |f| {
        let d: f64 = f[7].parse().unwrap();
        f[7] = format!("{}", d + 0.005);
    });
    let m = read_and_match(&bytes, "d.csv", &ReadOptions::default()).unwrap();
    let w = m.warnings[0].to_string();
    assert!(
        w.contains("line 7") && w.contains("rule 4") && w.contains("limit 0.001 mm"),
        "{w}"
    );
    // The file's deviation is used.
    assert_eq!(m.points[5].deviation, m.points[5].file.deviation.unwrap());
}

#[test]
fn wrong_curve_label_is_warned() {
    let bytes = edit(CLEAN, 3, |f| f[1] = "B_Z11".into());
    let m = read_and_match(&bytes, "l.csv", &ReadOptions::default()).unwrap();
    let w = m.warnings[0].to_string();
    assert!(
        w.contains("label 'B_Z11' but on surface A") && w.contains("line 3"),
        "{w}"
    );
}

#[test]
fn far_point_rejected_then_excluded_on_request() {
    let rel = "cmm/formats/clean_measured_only.csv";
    // Move the measured point of line 20 by 3 mm along its normal (-0.568, 0.794, -0.218).
    let bytes = edit(rel, 20, |f| {
        for (k, n) in [(2, -0.568), (3, 0.794), (4, -0.218)] {
            f[k] = format!("{}", f[k].parse::<f64>().unwrap() + 3.0 * n);
        }
    });
    let err = read_and_match(&bytes, "far.csv", &ReadOptions::default()).unwrap_err();
    let CmmError::BadRows { problems, .. } = &err else {
        panic!("{err}")
    };
    assert_eq!(problems.len(), 1);
    assert_eq!(
        (problems[0].line, problems[0].kind),
        (20, RowProblemKind::FarFromSurface)
    );
    let opts = ReadOptions::default().with_exclude_bad_rows(true);
    let m = read_and_match(&bytes, "far.csv", &opts).unwrap();
    assert_eq!(m.points.len(), 19);
    assert_eq!(m.excluded_lines(), [20]);
    // A larger limit keeps it, with the projected deviation.
    let m = match_points(
        &SShape::iso(),
        read_cmm(&bytes, "far.csv").unwrap(),
        &ReadOptions::default().with_max_distance_mm(5.0),
    )
    .unwrap();
    assert_eq!(m.points.len(), 20);
}

/// A file of nominal positions alone (x, y, z and normals of the 100 built-in points, no
/// deviation and no measured column) is no measurement (issue 18): it is refused with the
/// columns found, where it used to be identified as a machine with every error zero. One point
/// 0.2 µm off the surface along its normal (above the 0.1 µm limit) makes it a measurement.
#[test]
fn nominal_positions_alone_are_refused_naming_the_columns() {
    use std::fmt::Write;
    let pts = testpiece::part::builtin_points(&SShape::iso());
    let file = |shift: f64| {
        let mut text = String::from("id,curve,x,y,z,nx,ny,nz\n");
        for (k, p) in pts.iter().enumerate() {
            let q = if k == 40 {
                p.point + p.normal * shift
            } else {
                p.point
            };
            let n = p.normal;
            writeln!(
                text,
                "{},{},{},{},{},{},{},{}",
                p.id,
                p.curve.name(),
                q.x,
                q.y,
                q.z,
                n.x,
                n.y,
                n.z
            )
            .unwrap();
        }
        text
    };
    let e = read_and_match(file(0.0).as_bytes(), "nominal.csv", &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("no measurement:")
            && e.contains("columns found: id, curve, x, y, z, nx, ny, nz")
            && e.contains("every one of its 100 points"),
        "{e}"
    );
    let m = read_and_match(
        file(2e-4).as_bytes(),
        "measured.csv",
        &ReadOptions::default(),
    )
    .unwrap();
    assert_near!(m.points[40].deviation, 2e-4, 1e-9);
}
