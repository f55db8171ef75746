//! wasm exports of the `machine` stage.
