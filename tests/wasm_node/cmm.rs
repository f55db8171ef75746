//! wasm exports of the `cmm` stage, run under Node.
