//! wasm exports of the benchmark stages ([`crate::bench`]) for `scripts/bench-wasm.mjs`: the same
//! core calls on the same inputs as `cargo bench --bench stages`.

use wasm_bindgen::prelude::*;

use crate::bench::Stage;

thread_local! {
    static PREPARED: std::cell::RefCell<Option<(String, Stage)>> = const { std::cell::RefCell::new(None) };
}

/// Prepares stage `name` for [`bench_run`] (keeps one prepared stage).
#[wasm_bindgen(js_name = benchPrepare)]
pub fn bench_prepare(name: &str) -> Result<(), JsError> {
    let stage = Stage::prepare(name).map_err(|m| JsError::new(&m.to_string()))?;
    PREPARED.with(|p| *p.borrow_mut() = Some((name.to_string(), stage)));
    Ok(())
}

/// Runs the prepared stage `name` once (the timed call of `scripts/bench-wasm.mjs`).
#[wasm_bindgen(js_name = benchRun)]
pub fn bench_run(name: &str) -> Result<f64, JsError> {
    PREPARED.with(|p| match &*p.borrow() {
        Some((n, stage)) if n == name => stage.run().map_err(|m| JsError::new(&m.to_string())),
        _ => Err(JsError::new(&format!(
            "stage `{name}` is not prepared (call benchPrepare first)"
        ))),
    })
}
