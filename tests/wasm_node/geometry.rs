//! wasm exports of the `geometry` stage, run under Node.
