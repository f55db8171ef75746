//! Every file of the reader's broken corpus (tests/data/cmm/broken) through the page's wasm
//! export `analyse` under Node: each must be an `Err` (never a panic across the boundary) whose
//! message is the native reader's, as recorded by the native test `it/edge_parity.rs` in
//! tests/data/parity/broken_messages.json (which also checks this list names every file), and
//! which carries `bad_rows` exactly when the reader refused rows that could be excluded.

use wasm_bindgen::JsCast;
use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

macro_rules! corpus {
    ($($name:literal,)*) => {
        [$(($name, include_bytes!(concat!("../data/cmm/broken/", $name)) as &[u8]),)*]
    };
}

const BROKEN: [(&str, &[u8]); 41] = corpus![
    "binary_nul.csv",
    "control_characters.csv",
    "decimal_comma_in_comma_file.csv",
    "duplicate_column.csv",
    "duplicate_ids.csv",
    "empty.csv",
    "empty_value.csv",
    "excel_xlsx_renamed.csv",
    "header_only.csv",
    "huge_number.csv",
    "inch_without_unit.csv",
    "infinite.csv",
    "micrometre_positions_without_unit.csv",
    "micrometres_without_unit.csv",
    "misaligned.csv",
    "missing_normal_k.csv",
    "missing_positions.csv",
    "missing_z.csv",
    "mixed_separators.csv",
    "mixed_separators_tab_spaces.tsv",
    "mm_labelled_inch.csv",
    "nan.csv",
    "no_header.csv",
    "not_numeric.csv",
    "only_comments.csv",
    "point_far_from_surface.csv",
    "point_in_inches.csv",
    "powerinspect_truncated.txt",
    "several_bad_rows.csv",
    "single_implausible_deviation.csv",
    "too_few_points.csv",
    "truncated_last_row.csv",
    "truncated_middle_row.csv",
    "unbalanced_quote.csv",
    "unknown_header.csv",
    "unknown_unit_header.csv",
    "utf16_binary_garbage.csv",
    "whitespace_only.csv",
    "xyzijk_not_numeric.txt",
    "xyzijk_without_unit.txt",
    "zero_normal.csv",
];

const MESSAGES: &str = include_str!("../data/parity/broken_messages.json");

#[wasm_bindgen_test]
fn every_broken_file_is_an_error_with_the_native_message() {
    let native: std::collections::BTreeMap<String, String> =
        serde_json::from_str(MESSAGES).expect("broken_messages.json");
    assert_eq!(
        native.len(),
        BROKEN.len(),
        "files in the corpus vs messages"
    );
    let prepared = crate::prepared();
    for (name, bytes) in BROKEN {
        let v = match testpiece::wasm::analysis::analyse(
            &prepared,
            bytes,
            name,
            JsValue::UNDEFINED,
            None,
        ) {
            Ok(_) => panic!("{name}: read without error under wasm"),
            Err(e) => e,
        };
        let bad_rows = js_sys::Reflect::get(&v, &JsValue::from_str("bad_rows"))
            .ok()
            .and_then(|r| r.as_f64());
        let msg = v
            .dyn_into::<js_sys::Error>()
            .map(|e| String::from(e.message()))
            .unwrap_or_else(|_| "not an Error".into());
        assert_eq!(Some(&msg), native.get(name), "{name}");
        // The core under wasm gives the same text as the export.
        let core =
            testpiece::cmm::read_and_match(bytes, name, &Default::default()).expect_err(name);
        assert_eq!(core.to_string(), msg, "{name}");
        let rows = core.row_problems().len();
        assert_eq!(bad_rows, (rows > 0).then_some(rows as f64), "{name}");
    }
}
