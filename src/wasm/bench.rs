//! wasm exports of the benchmark stages ([`crate::bench`]) for `scripts/bench-wasm.mjs`: the same
//! core calls on the same inputs as `cargo bench --bench stages`.

use wasm_bindgen::prelude::*;

use crate::bench::Stage;

/// One benchmark stage with its input built (and what it keeps between its calls): the script
/// holds it, times [`BenchStage::run`], then frees it.
#[wasm_bindgen]
pub struct BenchStage {
    stage: Stage,
}

#[wasm_bindgen]
impl BenchStage {
    /// Builds the input of stage `name` (one of [`crate::bench::STAGES`]).
    #[wasm_bindgen(constructor)]
    pub fn new(name: &str) -> Result<BenchStage, JsError> {
        let stage = Stage::prepare(name).map_err(|m| JsError::new(&m.to_string()))?;
        Ok(BenchStage { stage })
    }

    /// Runs the stage once (the timed call of `scripts/bench-wasm.mjs`).
    pub fn run(&self) -> Result<f64, JsError> {
        self.stage.run().map_err(|m| JsError::new(&m.to_string()))
    }
}
