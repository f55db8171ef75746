//! Tests of the core compiled to wasm and run under Node: `wasm-pack test --node -- --test wasm_node`.
//! One file per stage; each asserts the exported calls give the core's numbers.
//! The exports of the page's first module (feature `page-core`) and of its second (`page-tools`)
//! are tested under the default features (both); `-- --no-default-features --features F` runs
//! the files of one module alone.
#![cfg(target_arch = "wasm32")]

#[cfg(feature = "page-tools")]
mod budget;
mod cmm;
#[cfg(feature = "page-core")]
mod cmm_broken;
#[cfg(feature = "page-core")]
mod columns;
#[cfg(feature = "page-core")]
mod gap;
mod machine;
#[cfg(feature = "page-core")]
mod page;
#[cfg(feature = "page-core")]
mod parity;
#[cfg(feature = "page-tools")]
mod workflow;

use testpiece::wasm::prepared::PreparedSettings;

/// The prepared settings of the default analysis settings, as the page's worker builds them.
pub fn prepared() -> PreparedSettings {
    PreparedSettings::new(wasm_bindgen::JsValue::UNDEFINED)
        .ok()
        .expect("prepared settings")
}
