//! wasm exports of the `identify` stage, run under Node.
