#!/usr/bin/env bash
# `npm run bench [-- FILTER]`: native medians (cargo bench, written to target/bench-native.json)
# beside the same stages through the release wasm under Node, printed as a Markdown table.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
# Both builds carry the `bench` feature (the stage list and its inputs, src/bench.rs).
TESTPIECE_WASM_FEATURES=bench bash scripts/build-wasm.sh
cargo bench --quiet --features bench --bench stages -- "$@"
node scripts/bench-wasm.mjs "$@"
# peak memory of diagnose on scans, one process each (issue 31)
bash scripts/bench-memory.sh
