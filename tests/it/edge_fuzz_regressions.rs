//! Every input the fuzzers (`scripts/fuzz.sh`, fuzz/) flagged, kept in tests/data/cmm/fuzz/:
//! each must give a result or a clean error, through the reader and the whole analysis.
//!
//! - `slow_xyzijk_inch.txt` (cmm_reader, "timeout" on a loaded machine: 0.3 s of CPU, 13 s of
//!   wall time under `nice -n 19` with a load of 11 on 2 cores; not a hang): a mutated XYZIJK
//!   INCH file; the reader reports its bad rows.
//! - `slow_semicolon_analysis.csv` (analysis, same cause, 1.4 s of CPU): the seed
//!   `clean_semicolon_decimal_comma.csv` itself; analysed in full.
//!
//! - Later runs flagged more "slow units" and one analysis "timeout" (121 s wall time, 1.5 s of
//!   CPU): all were unmutated seeds (the example files, libFuzzer `MS: 0`) starved of CPU;
//!   they are in the seed corpus already and not repeated here.
//!
//! Any file added to the folder is covered by `every_fuzz_input_ends_cleanly`.

use std::time::{Duration, Instant};

use testpiece::analysis::{analyse_once, AnalysisOptions};
use testpiece::cmm::{read_and_match, CmmError, ReadOptions};

fn dir() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/cmm/fuzz")
}

fn bytes(name: &str) -> Vec<u8> {
    std::fs::read(dir().join(name)).unwrap()
}

/// Reader (strict, then with the bad rows excluded) and the whole analysis on every file: a
/// result or an error with a message, never a panic.
#[test]
fn every_fuzz_input_ends_cleanly() {
    let mut n = 0;
    for entry in std::fs::read_dir(dir()).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let b = std::fs::read(&path).unwrap();
        let t0 = Instant::now();
        for opts in [
            ReadOptions::default(),
            ReadOptions::default().with_exclude_bad_rows(true),
        ] {
            if let Err(e) = read_and_match(&b, &name, &opts) {
                assert!(!e.to_string().is_empty(), "{name}");
            }
        }
        for exclude in [false, true] {
            let o = AnalysisOptions {
                exclude_bad_rows: exclude,
                ..Default::default()
            };
            match analyse_once(&b, &name, &o) {
                Ok(a) => {
                    for p in &a.identification.parameters.0 {
                        assert!(p.value.is_finite(), "{name}: {}", p.name());
                    }
                }
                Err(e) => assert!(!e.to_string().is_empty(), "{name}"),
            }
        }
        // Debug build (opt-level 1): generous; a hang would run for ever.
        assert!(
            t0.elapsed() < Duration::from_secs(120),
            "{name}: {:?}",
            t0.elapsed()
        );
        n += 1;
    }
    assert!(n >= 2, "{n} files");
}

#[test]
fn slow_xyzijk_inch_reports_its_bad_rows() {
    let e = read_and_match(
        &bytes("slow_xyzijk_inch.txt"),
        "slow_xyzijk_inch.txt",
        &ReadOptions::default(),
    )
    .unwrap_err();
    eprintln!("{e}");
    assert!(matches!(e, CmmError::BadRows { .. }), "{e}");
}

#[test]
fn slow_semicolon_seed_is_analysed() {
    let a = analyse_once(
        &bytes("slow_semicolon_analysis.csv"),
        "slow_semicolon_analysis.csv",
        &AnalysisOptions::default(),
    )
    .unwrap();
    assert_eq!(a.points.len(), 100);
}
