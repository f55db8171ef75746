//! The example parts built into the page (so a newcomer sees a result at once, and the
//! single-file build needs no fetch): the three synthetic measured parts of
//! `tests/data/reference/examples/` (canonical CSV; their answer keys stay in the tests).
//!
//! The three files share their first eight columns (ids, curves, positions, normals: the same
//! 100 points); only the deviation differs. To keep the wasm small, `example_clean.csv` is
//! embedded whole and the other two as their deviation column (`examples/*.deviation`, one
//! value per line as written in the file); [`example_text`] rebuilds each file byte for byte
//! (checked against the files in tests/wasm_examples.rs).

use wasm_bindgen::prelude::*;

const CLEAN: &str = include_str!("../../tests/data/reference/examples/example_clean.csv");

/// (file name, what it is, deviation column or `None` for the clean file itself), menu order.
pub const EXAMPLES: [(&str, &str, Option<&str>); 3] = [
    (
        "example_backlash_c.csv",
        "S-shape part machined with C-axis backlash (synthetic, σ = 1.5 µm)",
        Some(include_str!("examples/backlash_c.deviation")),
    ),
    (
        "example_tool_radius.csv",
        "S-shape part machined with an oversize tool (synthetic, σ = 1.5 µm)",
        Some(include_str!("examples/tool_radius.deviation")),
    ),
    (
        "example_clean.csv",
        "S-shape part with machine errors only (synthetic, σ = 1.5 µm)",
        None,
    ),
];

/// The text of a built-in example file, by name.
pub fn example_text(name: &str) -> Option<String> {
    let (_, _, deviation) = EXAMPLES.iter().find(|(n, _, _)| *n == name)?;
    let Some(dev) = deviation else {
        return Some(CLEAN.to_string());
    };
    let mut lines = CLEAN.lines();
    let mut out = String::with_capacity(CLEAN.len());
    out.push_str(lines.next()?);
    out.push('\n');
    let mut devs = dev.lines();
    for row in lines {
        let (head, _) = row.rsplit_once(',')?;
        out.push_str(head);
        out.push(',');
        out.push_str(devs.next()?);
        out.push('\n');
    }
    devs.next().is_none().then_some(out)
}

/// The built-in examples: `[{name, description}]`.
#[wasm_bindgen(js_name = exampleList)]
pub fn example_list() -> Result<JsValue, JsError> {
    let list: Vec<serde_json::Value> = EXAMPLES
        .iter()
        .map(|(n, d, _)| serde_json::json!({ "name": n, "description": d }))
        .collect();
    super::to_js(&list)
}

/// The bytes of a built-in example file, by name.
#[wasm_bindgen(js_name = exampleBytes)]
pub fn example_bytes(name: &str) -> Result<Vec<u8>, JsError> {
    example_text(name).map(String::into_bytes).ok_or_else(|| {
        let names: Vec<&str> = EXAMPLES.iter().map(|(n, _, _)| *n).collect();
        JsError::new(&format!(
            "no built-in example named {name:?}; the examples are {}",
            names.join(", ")
        ))
    })
}
