//! wasm exports of the `cmm` stage.
