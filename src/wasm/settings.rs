//! What the page's settings offer, from the core (so that no label is copied into `www/`).

use wasm_bindgen::prelude::*;

use crate::analysis::MachineChoice;

/// The machines of the "Kinematic chain" setting: `[{id, name, uses_l0}]`, `id` being the
/// value of the analysis setting `machine`.
#[wasm_bindgen]
pub fn machines() -> Result<JsValue, JsError> {
    super::to_js(&MachineChoice::ALL.map(MachineChoice::info))
}
