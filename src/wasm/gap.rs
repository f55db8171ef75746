//! wasm exports of the `gap` stage.
