//! Limits of cmm-csv.md with clear messages: a file over 50 MB (50 MiB = 52 428 800 bytes,
//! `cmm::options::MAX_BYTES`) or over 1 000 000 data rows (`MAX_ROWS`) is refused before it is
//! parsed, with the size and the limit in the message, through the reader and the whole
//! analysis alike; files at the limit pass the check. (The 1 000 001-row case itself is in
//! cmm_broken.rs `row_limit_1_000_000`.)

use std::time::Instant;

use testpiece::analysis::{analyse_once, AnalysisOptions};
use testpiece::cmm::options::{MAX_BYTES, MAX_ROWS};
use testpiece::cmm::{read_cmm_with, CmmError, ReadOptions};

#[test]
fn the_limits_are_those_of_the_spec() {
    assert_eq!(MAX_BYTES, 52_428_800);
    assert_eq!(MAX_ROWS, 1_000_000);
    let d = ReadOptions::default();
    assert_eq!((d.max_bytes, d.max_rows), (MAX_BYTES, MAX_ROWS));
}

/// One byte over 50 MiB: refused at once (no decoding), message with both numbers; through
/// the whole analysis the message is the reader's.
#[test]
fn a_file_over_50_mb_is_refused_with_the_limit() {
    let mut big = vec![b' '; MAX_BYTES + 1];
    big[..6].copy_from_slice(b"x,y,z\n");
    let t0 = Instant::now();
    let e = analyse_once(&big, "big.csv", &AnalysisOptions::default()).unwrap_err();
    assert!(t0.elapsed().as_secs_f64() < 5.0, "{:?}", t0.elapsed());
    assert_eq!(
        e.to_string(),
        "the file is 52428801 bytes, over the limit of 52428800 bytes (50 MB)"
    );
}

/// At the limit (bytes == max_bytes) the size check passes; one byte more does not.
#[test]
fn the_size_limit_is_inclusive() {
    let text = b"x,y,z\n1,2,3\n";
    let at = ReadOptions::default().with_max_bytes(text.len());
    let e = read_cmm_with(text, "f.csv", &at).unwrap_err();
    assert!(!matches!(e, CmmError::TooLarge { .. }), "{e}");
    let under = ReadOptions::default().with_max_bytes(text.len() - 1);
    let e = read_cmm_with(text, "f.csv", &under).unwrap_err();
    assert!(
        matches!(
            e,
            CmmError::TooLarge {
                bytes: 12,
                limit: 11,
                ..
            }
        ),
        "{e}"
    );
}

/// Rows: `max_rows` data rows pass, one more is refused; comment and blank lines do not count.
#[test]
fn the_row_limit_counts_data_rows_only() {
    let opts = ReadOptions::default().with_max_rows(3).with_min_points(1);
    let three = "# comment\nx,y,z\n\n1,2,3\n# more\n1,2,3\n1,2,3\n";
    let e = read_cmm_with(three.as_bytes(), "f.csv", &opts);
    assert!(
        !matches!(e, Err(CmmError::TooManyRows { .. })),
        "{:?}",
        e.map(|f| f.points.len())
    );
    let four = format!("{three}1,2,3\n");
    let e = read_cmm_with(four.as_bytes(), "f.csv", &opts).unwrap_err();
    assert_eq!(
        e.to_string(),
        "the file has more than 3 data rows (4), over the limit of 3 rows"
    );
}
