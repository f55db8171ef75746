//! Tests of the core compiled to wasm and run under Node: `wasm-pack test --node -- --test wasm_node`.
//! One file per stage; each asserts the exported calls give the core's numbers.
#![cfg(target_arch = "wasm32")]

mod budget;
mod cmm;
mod cmm_broken;
mod gap;
mod machine;
mod page;
mod parity;
mod workflow;

use testpiece::wasm::prepared::PreparedSettings;

/// The prepared settings of the default analysis settings, as the page's worker builds them.
pub fn prepared() -> PreparedSettings {
    PreparedSettings::new(wasm_bindgen::JsValue::UNDEFINED)
        .ok()
        .expect("prepared settings")
}
