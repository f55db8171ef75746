//! wasm exports of the `geometry` stage.
