//! Fuzz target: the CMM reader and matcher (`cmm::read_and_match`) on arbitrary bytes.
//!
//! Whatever the bytes, the reader must return (never panic, never hang) either a `CmmError`
//! whose message is not empty, or a matched part whose every number is finite. A file rejected
//! for bad rows is read again with the rows excluded (the page's "exclude the listed rows"),
//! which must also end cleanly.
#![no_main]

use libfuzzer_sys::fuzz_target;
use testpiece::cmm::{read_and_match, CmmError, MatchedPart, ReadOptions};

fn check(result: Result<MatchedPart, CmmError>) -> Option<CmmError> {
    match result {
        Ok(part) => {
            for p in &part.points {
                let finite = p.u.is_finite()
                    && p.v.is_finite()
                    && p.deviation.is_finite()
                    && p.distance.is_finite()
                    && p.foot.iter().all(|x| x.is_finite())
                    && p.normal.iter().all(|x| x.is_finite());
                assert!(finite, "non-finite matched point on line {}", p.file.line);
            }
            None
        }
        Err(e) => {
            assert!(!e.to_string().is_empty(), "empty error message");
            Some(e)
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let strict = ReadOptions::default();
    if let Some(CmmError::BadRows { .. }) = check(read_and_match(data, "fuzz.csv", &strict)) {
        let lenient = strict.with_exclude_bad_rows(true);
        check(read_and_match(data, "fuzz.csv", &lenient));
    }
});
