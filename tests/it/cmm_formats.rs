//! The three reference examples read exactly, and `example_clean.csv` rewritten in every format
//! of `shared/spec/cmm-csv.md` (files made by `tests/data/cmm/make_formats.py`, independent of
//! the reader) gives the same points.
//!
//! Tolerances: formats that keep the canonical text (semicolon + decimal comma, tab, spaces,
//! BOM, PowerInspect, XYZIJK METRIC) must give bit-identical numbers; µm columns differ by the
//! rounding of one division by 1000 (≤ 1e-15 mm, asserted 1e-12); inch columns by the rounding
//! of /25.4 in the writer and ·25.4 in the reader (≤ 1e-13 mm, asserted 1e-12).

use std::path::PathBuf;

use testpiece::cmm::{read_cmm, CmmFile, FormatKind, LengthUnit, ReadOptions, Separator};

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

fn read(rel: &str) -> CmmFile {
    let path = data(rel);
    let bytes = std::fs::read(&path).unwrap();
    read_cmm(&bytes, path.file_name().unwrap().to_str().unwrap())
        .unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// The canonical file parsed naively (split on ',' and `str::parse`), as the truth.
struct Row {
    id: String,
    curve: String,
    nominal: [f64; 3],
    normal: [f64; 3],
    deviation: f64,
}

fn naive(rel: &str) -> Vec<Row> {
    let text = std::fs::read_to_string(data(rel)).unwrap();
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let n = |k: usize| f[k].parse::<f64>().unwrap();
            Row {
                id: f[0].to_string(),
                curve: f[1].to_string(),
                nominal: [n(2), n(3), n(4)],
                normal: [n(5), n(6), n(7)],
                deviation: n(8),
            }
        })
        .collect()
}

impl Row {
    /// `x y z nx ny nz deviation` joined by `sep`.
    fn fields(&self, sep: &str) -> String {
        let v = [self.nominal, self.normal].concat();
        let mut f: Vec<String> = v.iter().map(|x| x.to_string()).collect();
        f.push(self.deviation.to_string());
        f.join(sep)
    }
}

/// Exact nominal points and normals of `reference/points.csv` (full double precision).
fn exact_points() -> Vec<([f64; 3], [f64; 3])> {
    let text = std::fs::read_to_string(data("reference/points.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l.split(',').skip(4).map(|t| t.parse().unwrap()).collect();
            ([f[0], f[1], f[2]], [f[3], f[4], f[5]])
        })
        .collect()
}

const CLEAN: &str = "reference/examples/example_clean.csv";

#[test]
fn reference_examples_read_exactly() {
    for name in [
        "example_clean.csv",
        "example_tool_radius.csv",
        "example_backlash_c.csv",
    ] {
        let rel = format!("reference/examples/{name}");
        let file = read(&rel);
        let truth = naive(&rel);
        assert_eq!(file.points.len(), 100, "{name}");
        assert_eq!(truth.len(), 100);
        assert!(file.warnings.is_empty(), "{name}: {:?}", file.warnings);
        assert!(file.excluded.is_empty());
        assert_eq!(file.format.kind, FormatKind::Delimited);
        assert_eq!(file.format.separator, Some(Separator::Comma));
        for (p, t) in file.points.iter().zip(&truth) {
            assert_eq!(p.id, t.id);
            assert_eq!(p.curve.as_deref(), Some(t.curve.as_str()));
            assert_eq!(p.nominal, Some(t.nominal), "{name} line {}", p.line);
            assert_eq!(p.normal, Some(t.normal));
            assert_eq!(p.deviation, Some(t.deviation));
            assert_eq!(p.measured, None);
            assert!(p.extra.is_empty());
        }
        assert_eq!(file.points[0].line, 2);
        assert_eq!(file.points[99].line, 101);
    }
}

/// Compares a variant with the canonical rows: ids (where the format has them), nominal,
/// normal and deviation, to `tol` mm.
fn same_as_canonical(rel: &str, tol: f64, has_ids: bool) -> CmmFile {
    let file = read(rel);
    let truth = naive(CLEAN);
    assert_eq!(file.points.len(), truth.len(), "{rel}");
    for (k, (p, t)) in file.points.iter().zip(&truth).enumerate() {
        if has_ids {
            assert!(
                p.id == t.id || p.id == format!("P{}", t.id),
                "{rel}: id {}",
                p.id
            );
        } else {
            assert_eq!(p.id, (k + 1).to_string());
        }
        let nom = p.nominal.unwrap_or_else(|| panic!("{rel}: no nominal"));
        let n = p.normal.unwrap();
        for i in 0..3 {
            assert!(
                (nom[i] - t.nominal[i]).abs() <= tol,
                "{rel} line {}: nominal {i} {} vs {}",
                p.line,
                nom[i],
                t.nominal[i]
            );
            assert_eq!(n[i], t.normal[i], "{rel} line {}", p.line);
        }
        let d = p.deviation.unwrap();
        assert!(
            (d - t.deviation).abs() <= tol,
            "{rel} line {}: deviation {d} vs {}",
            p.line,
            t.deviation
        );
    }
    file
}

#[test]
fn semicolon_decimal_comma() {
    let f = same_as_canonical("cmm/formats/clean_semicolon_decimal_comma.csv", 0.0, true);
    assert_eq!(f.format.separator, Some(Separator::Semicolon));
    assert!(f.format.decimal_comma);
    assert!(
        f.format.description.contains("decimal comma"),
        "{}",
        f.format.description
    );
}

#[test]
fn tab_spaces_bom_powerinspect_xyzijk_metric_bit_identical() {
    let f = same_as_canonical("cmm/formats/clean_tab.tsv", 0.0, true);
    assert_eq!(f.format.separator, Some(Separator::Tab));
    let f = same_as_canonical("cmm/formats/clean_spaces.txt", 0.0, true);
    assert_eq!(f.format.separator, Some(Separator::Spaces));
    let f = same_as_canonical("cmm/formats/clean_bom_crlf.csv", 0.0, true);
    assert_eq!(f.format.encoding, "UTF-8 with BOM");
    let f = same_as_canonical("cmm/formats/clean_powerinspect.txt", 0.0, true);
    assert_eq!(f.format.kind, FormatKind::PowerInspect);
    assert_eq!(f.extra_columns, ["lowTol", "highTol"]);
    assert_eq!(f.points[0].extra, ["-0.050", "0.050"]);
    let f = same_as_canonical("cmm/formats/clean_xyzijk_metric.txt", 0.0, false);
    assert_eq!(f.format.kind, FormatKind::Xyzijk);
}

#[test]
fn micrometre_columns() {
    let f = same_as_canonical("cmm/formats/clean_um_extra_columns.csv", 1e-12, true);
    assert_eq!(f.extra_columns, ["Tol", "Comment"]);
    assert_eq!(f.points[0].extra, ["0.05", "check"]);
    assert_eq!(f.comment_lines, 2);
    let dev_col = f
        .format
        .columns
        .iter()
        .find(|c| c.header == "Dev [um]")
        .unwrap();
    assert_eq!(dev_col.unit, Some(LengthUnit::Um));
    let f = same_as_canonical("cmm/formats/clean_windows1252_german.csv", 1e-12, true);
    assert_eq!(f.format.encoding, "Windows-1252");
    assert!(f.format.decimal_comma);
    assert!(f.format.columns[8].header.contains('µ'));
}

#[test]
fn inch_formats() {
    let f = same_as_canonical("cmm/formats/clean_xyzijk_inch.txt", 1e-12, false);
    assert!(
        f.format.description.contains("INCH"),
        "{}",
        f.format.description
    );
    same_as_canonical("cmm/formats/clean_inch_header.csv", 1e-12, true);
}

#[test]
fn measured_positions_read() {
    let truth = naive(CLEAN);
    let exact = exact_points();
    let expect = |k: usize| -> [f64; 3] {
        let (p, n) = exact[k];
        let d = truth[k].deviation;
        [p[0] + d * n[0], p[1] + d * n[1], p[2] + d * n[2]]
    };
    for rel in [
        "cmm/formats/clean_measured_only.csv",
        "cmm/formats/clean_nominal_measured.csv",
        "cmm/formats/clean_nominal_measured_dev.csv",
    ] {
        let f = read(rel);
        assert_eq!(f.points.len(), 100);
        for (k, p) in f.points.iter().enumerate() {
            assert_eq!(p.measured, Some(expect(k)), "{rel} line {}", p.line);
            if rel.ends_with("only.csv") {
                assert_eq!(p.nominal, None);
            } else {
                assert_eq!(p.nominal, Some(exact[k].0));
            }
            if rel.ends_with("dev.csv") {
                assert_eq!(p.deviation, Some(truth[k].deviation));
            } else {
                assert_eq!(p.deviation, None);
            }
        }
    }
}

#[test]
fn lone_xyz_read_as_measured_with_warning() {
    let mut text = String::from("x,y,z\n");
    for r in naive(CLEAN) {
        text.push_str(&format!(
            "{},{},{}\n",
            r.nominal[0], r.nominal[1], r.nominal[2]
        ));
    }
    let f = read_cmm(text.as_bytes(), "xyz.csv").unwrap();
    assert!(f
        .points
        .iter()
        .all(|p| p.measured.is_some() && p.nominal.is_none()));
    assert!(f.warnings[0].message.contains("read as measured"));
}

#[test]
fn explicit_unit_option_skips_inch_guess() {
    // Inch data without a unit are refused, but accepted when the caller says "inch".
    let mut text = String::from("id,x,y,z,dev\n");
    for r in naive(CLEAN) {
        text.push_str(&format!(
            "{},{},{},{},{}\n",
            r.id,
            r.nominal[0] / 25.4,
            r.nominal[1] / 25.4,
            r.nominal[2] / 25.4,
            r.deviation / 25.4
        ));
    }
    let err = read_cmm(text.as_bytes(), "in.csv").unwrap_err().to_string();
    assert!(err.contains("inch"), "{err}");
    let opts = ReadOptions::default().with_length_unit(LengthUnit::Inch);
    let f = testpiece::cmm::read_cmm_with(text.as_bytes(), "in.csv", &opts).unwrap();
    let truth = naive(CLEAN);
    for (p, t) in f.points.iter().zip(&truth) {
        assert!((p.nominal.unwrap()[0] - t.nominal[0]).abs() < 1e-12);
        assert!((p.deviation.unwrap() - t.deviation).abs() < 1e-12);
    }
}

#[test]
fn ids_repeating_per_curve_are_not_duplicates() {
    // Ids 1-25 on each curve: (curve, id) identifies a point.
    let mut text = String::from("id,curve,x,y,z,nx,ny,nz,deviation\n");
    for (k, r) in naive(CLEAN).iter().enumerate() {
        text.push_str(&format!("{},{},{}\n", k % 25 + 1, r.curve, r.fields(",")));
    }
    let f = read_cmm(text.as_bytes(), "per_curve.csv").unwrap();
    assert_eq!(f.points.len(), 100);
    // Without the curve column they are duplicates.
    let no_curve: String = text
        .lines()
        .map(|l| {
            let mut v: Vec<&str> = l.split(',').collect();
            v.remove(1);
            v.join(",") + "\n"
        })
        .collect();
    let err = read_cmm(no_curve.as_bytes(), "ids.csv").unwrap_err();
    assert_eq!(err.row_problems().len(), 75);
    assert!(
        err.to_string()
            .contains("line 27, column 1 'id': duplicate id: found '1'"),
        "{err}"
    );
}

#[test]
fn powerinspect_with_numeric_names() {
    let text: String = naive(CLEAN)
        .iter()
        .map(|r| format!("{} {} -0.05 0.05\n", r.id, r.fields(" ")))
        .collect();
    let f = read_cmm(text.as_bytes(), "pi.txt").unwrap();
    assert_eq!(f.format.kind, FormatKind::PowerInspect);
    assert_eq!(f.points.len(), 100);
    assert_eq!(f.points[99].id, "100");
}
