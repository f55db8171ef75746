//! wasm exports of the `machine` stage, run under Node.
