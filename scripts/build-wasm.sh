#!/usr/bin/env bash
# Builds the release wasm and its JS glue into www/pkg/ (ES module for the page, --target web).
# Usage: scripts/build-wasm.sh [--dev]
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
profile=release; flag=--release
if [ "${1:-}" = "--dev" ]; then profile=debug; flag=; fi
cargo build --lib --target wasm32-unknown-unknown $flag
wasm-bindgen --target web --no-typescript --out-dir www/pkg \
  "target/wasm32-unknown-unknown/$profile/testpiece.wasm"
size=$(stat -c %s www/pkg/testpiece_bg.wasm)
echo "[build-wasm] www/pkg/testpiece_bg.wasm: $size bytes ($profile)"
