//! wasm exports of the `identify` stage.
