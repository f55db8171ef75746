//! The broken-file corpus (`tests/data/cmm/broken/`, made by `tests/data/cmm/make_broken.py`):
//! each file gives its specific person-readable error (key words and line number), never a
//! panic; files with bad rows are usable with the explicit exclusion option, which then lists
//! the excluded rows. The size and row limits are checked on generated input.

use std::path::PathBuf;

use proptest::prelude::*;
use testpiece::cmm::{
    read_and_match, read_cmm, read_cmm_with, CmmError, ReadOptions, RowProblemKind,
};

fn broken(name: &str) -> Vec<u8> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/cmm/broken")
        .join(name);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// (file, words the message must contain, line the message must name (`line N`) if any).
const CASES: &[(&str, &[&str], Option<usize>)] = &[
    ("empty.csv", &["empty", "0 bytes"], None),
    ("only_comments.csv", &["empty", "only comment"], None),
    ("whitespace_only.csv", &["empty", "white space"], None),
    (
        "header_only.csv",
        &["empty", "header on line 1", "no data rows"],
        None,
    ),
    (
        "binary_nul.csv",
        &["binary data", "0x00", "expected text"],
        None,
    ),
    (
        "excel_xlsx_renamed.csv",
        &["binary data", "xlsx", "save it as CSV"],
        None,
    ),
    ("utf16_binary_garbage.csv", &["binary data"], None),
    (
        "control_characters.csv",
        &["binary data", "control bytes"],
        None,
    ),
    (
        "no_header.csv",
        &["no recognisable header", "header row is missing", "1,A_Z11"],
        Some(1),
    ),
    (
        "unknown_header.csv",
        &["no recognisable header", "foo,bar,baz,qux"],
        Some(1),
    ),
    (
        "missing_z.csv",
        &[
            "required column missing",
            "nominal z",
            "found columns",
            "'nx'",
        ],
        Some(1),
    ),
    (
        "missing_positions.csv",
        &["required column missing", "a position", "found columns"],
        Some(1),
    ),
    (
        "missing_normal_k.csv",
        &["required column missing", "normal k", "'ny' (normal j)"],
        Some(1),
    ),
    (
        "duplicate_column.csv",
        &["both mean nominal x", "'x'", "'X nom'"],
        Some(1),
    ),
    (
        "unknown_unit_header.csv",
        &["unknown unit 'ft'", "column 3 'x [ft]'", "expected mm"],
        Some(1),
    ),
    (
        "xyzijk_without_unit.txt",
        &["XYZIJK", "without a unit", "METRIC or INCH"],
        Some(1),
    ),
    (
        "not_numeric.csv",
        &[
            "not a number",
            "column 3 'x'",
            "found 'abc'",
            "expected a number in mm",
        ],
        Some(5),
    ),
    (
        "nan.csv",
        &["not a finite number", "column 9 'deviation'", "found 'NaN'"],
        Some(7),
    ),
    (
        "infinite.csv",
        &["not a finite number", "column 5 'z'", "found 'inf'"],
        Some(9),
    ),
    (
        "huge_number.csv",
        &["not a finite number", "found '1e400'"],
        Some(10),
    ),
    (
        "empty_value.csv",
        &["empty value", "column 7 'ny'"],
        Some(11),
    ),
    (
        "truncated_last_row.csv",
        &["truncated row", "expected 9 fields", "found only 5"],
        Some(101),
    ),
    (
        "truncated_middle_row.csv",
        &["truncated row", "found only 5"],
        Some(31),
    ),
    (
        "decimal_comma_in_comma_file.csv",
        &["too many fields", "found 10", "decimal comma"],
        Some(14),
    ),
    (
        "mixed_separators.csv",
        &["mixed separators", "comma ','", "semicolon ';'"],
        Some(20),
    ),
    (
        "mixed_separators_tab_spaces.tsv",
        &["mixed separators", "tab", "runs of spaces"],
        Some(41),
    ),
    (
        "duplicate_ids.csv",
        &[
            "duplicate id",
            "found '5'",
            "'5' in curve 'A_Z11' is already used on line 6",
        ],
        Some(12),
    ),
    (
        "zero_normal.csv",
        &["zero-length normal", "(0, 0, 0)"],
        Some(15),
    ),
    (
        "single_implausible_deviation.csv",
        &["implausible deviation", "5.25 mm", "±2 mm", "wrong unit"],
        Some(25),
    ),
    (
        "several_bad_rows.csv",
        &[
            "3 bad row(s)",
            "rejected as a whole",
            "line 33",
            "12.3.4",
            "line 66",
            "duplicate id",
            "'60' in curve 'B_Z11' is already used on line 61",
            "line 80",
            "truncated",
        ],
        Some(33),
    ),
    (
        "powerinspect_truncated.txt",
        &[
            "truncated row",
            "name X Y Z I J K offset lowTol highTol",
            "found only 7",
        ],
        Some(50),
    ),
    (
        "xyzijk_not_numeric.txt",
        &["not a number", "found '11.0x'", "column 3 'z'"],
        Some(11),
    ),
    (
        "unbalanced_quote.csv",
        &[
            "unbalanced quote",
            "lines 8 to 10 were read as one row",
            "probe slipped",
            "line 9",
            "line 10",
        ],
        Some(8),
    ),
    (
        "point_far_from_surface.csv",
        &[
            "point far from the nominal surfaces",
            "2.9258 mm from surface A",
            "within 2 mm",
            "alignment",
        ],
        Some(30),
    ),
    (
        "point_in_inches.csv",
        &[
            "point far from the nominal surfaces",
            "multiplied by 25.4",
            "inches read as mm",
        ],
        Some(45),
    ),
    (
        "too_few_points.csv",
        &["too few points", "5 usable point(s)", "at least 10"],
        None,
    ),
    (
        "inch_without_unit.csv",
        &["inch data without a unit", "25.4", "x [in]"],
        None,
    ),
    (
        "micrometres_without_unit.csv",
        &[
            "wrong units",
            "column 9 'deviation'",
            "µm",
            "deviation [µm]",
        ],
        None,
    ),
    (
        "micrometre_positions_without_unit.csv",
        &["wrong units", "multiplied by 1/1000", "µm read as mm"],
        None,
    ),
    (
        "mm_labelled_inch.csv",
        &[
            "wrong units",
            "multiplied by 1/25.4",
            "mm labelled as inches",
            "read as in",
        ],
        None,
    ),
    (
        "misaligned.csv",
        &["not aligned", "x 366.909..626.921", "no unit conversion"],
        None,
    ),
];

#[test]
fn corpus_has_one_file_per_case_and_at_least_30() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/cmm/broken");
    let mut files: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    let mut cases: Vec<String> = CASES.iter().map(|c| c.0.to_string()).collect();
    cases.sort();
    assert_eq!(
        files, cases,
        "every corpus file has an expectation and vice versa"
    );
    assert!(files.len() >= 30);
}

#[test]
fn each_broken_file_gives_its_message() {
    for &(name, words, line) in CASES {
        let bytes = broken(name);
        // Matching (slow in debug builds) only where the error comes from it.
        let result = if name.starts_with("point_") {
            read_and_match(&bytes, name, &ReadOptions::default()).map(|m| m.points.len())
        } else {
            read_cmm(&bytes, name).map(|f| f.points.len())
        };
        let err = match result {
            Ok(n) => panic!("{name}: read without error: {n} points"),
            Err(e) => e,
        };
        let msg = err.to_string();
        for w in words {
            assert!(msg.contains(w), "{name}: message lacks '{w}':\n{msg}");
        }
        if let Some(l) = line {
            assert!(
                msg.contains(&format!("line {l}")),
                "{name}: message lacks 'line {l}':\n{msg}"
            );
        }
    }
}

#[test]
fn bad_rows_list_line_column_found_expected() {
    let err = read_cmm(&broken("several_bad_rows.csv"), "f").unwrap_err();
    let rows = err.row_problems();
    let summary: Vec<(usize, RowProblemKind)> = rows.iter().map(|r| (r.line, r.kind)).collect();
    assert_eq!(
        summary,
        [
            (33, RowProblemKind::NotNumeric),
            (66, RowProblemKind::DuplicateId),
            (80, RowProblemKind::Truncated)
        ]
    );
    assert_eq!(rows[0].column.as_ref().unwrap().number, 4);
    assert_eq!(rows[0].found, "12.3.4");
    assert!(rows[0].expected.contains("nominal y"));
}

#[test]
fn exclusion_is_explicit_and_reported() {
    let opts = ReadOptions::default().with_exclude_bad_rows(true);
    for (name, lines) in [
        ("several_bad_rows.csv", vec![33, 66, 80]),
        ("not_numeric.csv", vec![5]),
        ("nan.csv", vec![7]),
        ("truncated_last_row.csv", vec![101]),
        ("mixed_separators.csv", vec![20]),
        ("duplicate_ids.csv", vec![12]),
        ("single_implausible_deviation.csv", vec![25]),
        ("zero_normal.csv", vec![15]),
        ("point_far_from_surface.csv", vec![30]),
        ("point_in_inches.csv", vec![45]),
        ("powerinspect_truncated.txt", vec![50]),
        ("unbalanced_quote.csv", vec![8, 9, 10]),
    ] {
        let (excluded, point_lines, warnings) = if name.starts_with("point_") {
            let m = read_and_match(&broken(name), name, &opts)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let l: Vec<usize> = m.points.iter().map(|p| p.file.line).collect();
            (m.excluded_lines(), l, m.warnings)
        } else {
            let f =
                read_cmm_with(&broken(name), name, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
            let l: Vec<usize> = f.points.iter().map(|p| p.line).collect();
            (f.excluded_lines(), l, f.warnings)
        };
        assert_eq!(excluded, lines, "{name}");
        assert_eq!(point_lines.len(), 100 - lines.len(), "{name}");
        assert!(point_lines.iter().all(|l| !lines.contains(l)));
        let f = (warnings,);
        assert!(
            f.0.iter()
                .any(|w| w.message.contains("excluded at your request")),
            "{name}: {:?}",
            f.0
        );
    }
    // Exclusion does not rescue a file-level error.
    assert!(read_cmm_with(&broken("missing_z.csv"), "f", &opts).is_err());
}

#[test]
fn too_few_points_after_exclusion_says_so() {
    let opts = ReadOptions::default()
        .with_exclude_bad_rows(true)
        .with_min_points(99);
    let err = read_cmm_with(&broken("several_bad_rows.csv"), "f", &opts).unwrap_err();
    let msg = err.to_string();
    assert!(
        matches!(
            err,
            CmmError::TooFewPoints {
                found: 97,
                needed: 99,
                ..
            }
        ),
        "{msg}"
    );
    assert!(msg.contains("after excluding 3 bad row(s)"), "{msg}");
}

#[test]
fn size_limit_50_mb() {
    let limit = 50 * 1024 * 1024;
    let bytes = vec![b' '; limit + 1];
    let msg = read_cmm(&bytes, "big.csv").unwrap_err().to_string();
    assert!(msg.contains(&format!("{} bytes", limit + 1)), "{msg}");
    assert!(msg.contains("limit of 52428800 bytes (50 MB)"), "{msg}");
}

#[test]
fn row_limit_1_000_000() {
    let mut text = String::with_capacity(9_000_000);
    text.push_str("x,y,z\n");
    for _ in 0..1_000_001 {
        text.push_str("1,2,3\n");
    }
    let msg = read_cmm(text.as_bytes(), "rows.csv")
        .unwrap_err()
        .to_string();
    assert!(msg.contains("more than 1000000 data rows"), "{msg}");
    assert!(msg.contains("limit of 1000000 rows"), "{msg}");
    // The limit is an option.
    let opts = ReadOptions::default().with_max_rows(3);
    let msg = read_cmm_with(b"x,y,z\n1,2,3\n1,2,3\n1,2,3\n1,2,3\n", "f", &opts)
        .unwrap_err()
        .to_string();
    assert!(msg.contains("limit of 3 rows"), "{msg}");
}

fn example() -> Vec<u8> {
    std::fs::read(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/reference/examples/example_clean.csv"),
    )
    .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Truncating, overwriting bytes or inserting separators anywhere never panics.
    #[test]
    fn mangled_files_never_panic(cut in 0usize..9000, pos in proptest::collection::vec((0usize..9000, any::<u8>()), 0..8)) {
        let mut bytes = example();
        bytes.truncate(cut.min(bytes.len()));
        for (p, b) in pos {
            if !bytes.is_empty() {
                let k = p % bytes.len();
                bytes[k] = b;
            }
        }
        let _ = read_cmm(&bytes, "mangled.csv");
        let _ = read_cmm_with(&bytes, "mangled.csv", &ReadOptions::default().with_exclude_bad_rows(true));
    }

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let _ = read_cmm(&bytes, "random.bin");
    }
}
