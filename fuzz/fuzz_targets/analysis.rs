//! Fuzz target: the whole path file → reader → projection → sensitivity → identification →
//! exact-model refinement → gap diagnosis (`analysis::analyse`) on arbitrary bytes.
//!
//! The first byte picks the settings (bad rows excluded or not, tool-radius term, mode, branch),
//! the rest is the file. Every outcome must be a clean `AnalysisError` with a message or an
//! `Analysis` whose identified values and standard deviations are finite or explicitly not
//! separable; it must also serialise to JSON (what the page receives).
#![no_main]

use libfuzzer_sys::fuzz_target;
use testpiece::analysis::{analyse, AnalysisOptions};
use testpiece::machine::Branch;
use testpiece::sensitivity::Mode;

fuzz_target!(|data: &[u8]| {
    let Some((&flags, file)) = data.split_first() else {
        return;
    };
    let opts = AnalysisOptions {
        exclude_bad_rows: flags & 1 != 0,
        tool_radius: flags & 2 != 0,
        mode: if flags & 4 != 0 {
            Mode::Paper
        } else {
            Mode::Physical
        },
        branch: if flags & 8 != 0 {
            Branch::Positive
        } else {
            Branch::Signed
        },
        ..AnalysisOptions::default()
    };
    match analyse(file, "fuzz.csv", &opts) {
        Ok(a) => {
            for p in &a.identification.parameters.0 {
                assert!(p.value.is_finite(), "{}: value {}", p.name, p.value);
            }
            serde_json::to_string(&a).expect("the analysis serialises to JSON");
        }
        Err(e) => assert!(!e.to_string().is_empty(), "empty error message"),
    }
});
