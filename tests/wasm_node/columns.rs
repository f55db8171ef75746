//! The page's `analyse` writes an analysis's per-point arrays as packed columns
//! (src/wasm/columns.rs, the layout of www/columns.js): for the backlash example, the matched
//! points are a `table` of its 100 points whose columns hold the native analysis's values
//! exactly (the same wasm core, `analyse_once`: no tolerance), its ids and curves as text and
//! labels, its feet as lists of 3; `path_position` and each design column are `num` columns.

use js_sys::{Float64Array, Reflect};
use testpiece::analysis::{analyse_once, AnalysisOptions};
use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

const BACKLASH_C: &[u8] = include_bytes!("../data/reference/examples/example_backlash_c.csv");

fn get(v: &JsValue, path: &[&str]) -> JsValue {
    path.iter().fold(v.clone(), |o, k| {
        Reflect::get(&o, &JsValue::from_str(k)).unwrap_or_else(|_| panic!("{k} of {path:?}"))
    })
}

fn numbers(v: &JsValue) -> Vec<f64> {
    Float64Array::from(v.clone()).to_vec()
}

#[wasm_bindgen_test]
fn the_per_point_arrays_are_columns_of_the_core_values() {
    let name = "example_backlash_c.csv";
    let a = analyse_once(BACKLASH_C, name, &AnalysisOptions::default()).expect(name);
    let page = testpiece::wasm::analysis::analyse(
        &crate::prepared(),
        BACKLASH_C,
        name,
        JsValue::UNDEFINED,
        None,
    )
    .unwrap_or_else(|_| panic!("{name}: the export failed"));

    let file = get(&page, &["file", "points"]);
    assert_eq!(get(&file, &["$col"]).as_string().as_deref(), Some("table"));
    assert_eq!(get(&file, &["n"]).as_f64(), Some(100.0));
    let u: Vec<f64> = a.file.points.iter().map(|p| p.u).collect();
    assert_eq!(numbers(&get(&file, &["cols", "u", "v"])), u);
    let foot = get(&file, &["cols", "foot"]);
    assert_eq!(get(&foot, &["$col"]).as_string().as_deref(), Some("vec"));
    assert_eq!(get(&foot, &["k"]).as_f64(), Some(3.0));
    let feet: Vec<f64> = a.file.points.iter().flat_map(|p| p.foot).collect();
    assert_eq!(numbers(&get(&foot, &["v"])), feet);
    // the file's ids, end to end, and where each ends
    let ids = get(&file, &["cols", "file", "cols", "id"]);
    assert_eq!(get(&ids, &["$col"]).as_string().as_deref(), Some("text"));
    let joined: String = a.file.points.iter().map(|p| p.file.id.as_str()).collect();
    assert_eq!(get(&ids, &["s"]).as_string(), Some(joined));

    let fit = get(&page, &["identification", "points"]);
    let residual: Vec<f64> = a.identification.points.iter().map(|p| p.residual).collect();
    assert_eq!(numbers(&get(&fit, &["cols", "residual", "v"])), residual);
    let curve = get(&fit, &["cols", "curve"]);
    assert_eq!(get(&curve, &["$col"]).as_string().as_deref(), Some("label"));

    let path = a.path_position.as_ref().expect("path_position");
    assert_eq!(numbers(&get(&page, &["path_position", "v"])), *path);
    let first = Reflect::get(&get(&page, &["design", "columns"]), &JsValue::from(0)).unwrap();
    assert_eq!(numbers(&get(&first, &["v"])), a.design.columns[0]);
}

/// An item of the packing test below: a number sometimes null, a number, a list of three and a
/// list whose length is its own.
#[derive(serde::Serialize)]
struct Item {
    maybe: Option<f64>,
    x: f64,
    foot: [f64; 3],
}

fn bytes(v: &JsValue) -> Vec<u8> {
    js_sys::Uint8Array::from(v.clone()).to_vec()
}

/// The packed layout of www/columns.js by hand: a number null at the first two items, at the
/// fourth and nowhere after the fifth is a `numnull` column (NaN and `nul` 1 at the nulls, `nul`
/// as long as the items); one never null is `num` (no `nul`); lists of 3 are a `vec` of k 3,
/// item after item; lists of two lengths in one field are refused (the list then travels as
/// JSON). Tolerance: none (the values are copied).
#[wasm_bindgen_test]
fn nulls_numbers_and_lists_pack_by_hand() {
    use testpiece::wasm::columns::packed;
    let maybe = [
        None,
        None,
        Some(1.5),
        None,
        Some(-2.0),
        Some(3.0),
        Some(4.0),
    ];
    let items: Vec<Item> = maybe
        .iter()
        .enumerate()
        .map(|(i, &m)| Item {
            maybe: m,
            x: i as f64,
            foot: [i as f64, 10.0 + i as f64, -(i as f64)],
        })
        .collect();
    let t = packed(&items).expect("columns");
    assert_eq!(get(&t, &["$col"]).as_string().as_deref(), Some("table"));
    let m = get(&t, &["cols", "maybe"]);
    assert_eq!(get(&m, &["$col"]).as_string().as_deref(), Some("numnull"));
    assert_eq!(bytes(&get(&m, &["nul"])), vec![1, 1, 0, 1, 0, 0, 0]);
    let v = numbers(&get(&m, &["v"]));
    assert_eq!(v.len(), 7);
    for (got, want) in v.iter().zip(&maybe) {
        match want {
            Some(w) => assert_eq!(got, w),
            None => assert!(got.is_nan()),
        }
    }
    let x = get(&t, &["cols", "x"]);
    assert_eq!(get(&x, &["$col"]).as_string().as_deref(), Some("num"));
    assert!(get(&x, &["nul"]).is_undefined());
    assert_eq!(
        numbers(&get(&x, &["v"])),
        vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    );
    let foot = get(&t, &["cols", "foot"]);
    assert_eq!(get(&foot, &["$col"]).as_string().as_deref(), Some("vec"));
    assert_eq!(get(&foot, &["k"]).as_f64(), Some(3.0));
    let want: Vec<f64> = items.iter().flat_map(|i| i.foot).collect();
    assert_eq!(numbers(&get(&foot, &["v"])), want);
    // lists of 2 and of 3 numbers in one field
    let uneven: Vec<Vec<f64>> = vec![vec![1.0, 2.0], vec![1.0, 2.0, 3.0]];
    assert!(packed(&uneven).is_err());
    // a list holding a null
    let holed: Vec<Vec<Option<f64>>> = vec![vec![Some(1.0)], vec![None]];
    assert!(packed(&holed).is_err());
}
