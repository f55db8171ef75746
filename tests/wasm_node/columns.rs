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
