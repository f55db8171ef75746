//! The `cmm` stage compiled to wasm and run under Node (the page reaches it through `analyse`):
//! the core (`read_cmm`, `read_and_match`) gives the native numbers: the reference example read
//! exactly and matched, and a broken file rejected with the same message.

use testpiece::cmm::{read_and_match, read_cmm, ReadOptions};
use wasm_bindgen_test::*;

const CLEAN: &[u8] = include_bytes!("../data/reference/examples/example_clean.csv");
const SEMICOLON: &[u8] = include_bytes!("../data/cmm/formats/clean_semicolon_decimal_comma.csv");
const NAN: &[u8] = include_bytes!("../data/cmm/broken/nan.csv");

#[wasm_bindgen_test]
fn example_reads_and_matches_under_wasm() {
    let f = read_cmm(CLEAN, "example_clean.csv").expect("reads");
    assert_eq!(f.points.len(), 100);
    // Line 2 of the file: 1,A_Z11,-133.091145,-62.701728,11.000000,...,0.001110
    assert_eq!(f.points[0].nominal, Some([-133.091145, -62.701728, 11.0]));
    assert_eq!(f.points[0].deviation, Some(0.001110));
    let g = read_cmm(SEMICOLON, "semicolon.csv").expect("reads");
    assert_eq!(f.points, g.points);
    let m = read_and_match(CLEAN, "example_clean.csv", &ReadOptions::default()).expect("matches");
    assert_eq!(m.points.len(), 100);
    assert!(m.warnings.is_empty());
}

#[wasm_bindgen_test]
fn broken_file_message_under_wasm() {
    let msg = read_cmm(NAN, "nan.csv").unwrap_err().to_string();
    assert!(
        msg.contains("line 7, column 9 'deviation': not a finite number: found 'NaN'"),
        "{msg}"
    );
}
