#!/usr/bin/env bash
# `npm test`: set up, then run every test: format, lints, native tests, the wasm build, the wasm
# tests under Node, and the browser end-to-end tests in headless Debian Chromium.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
step() { printf '\n\033[1m== %s\033[0m\n' "$*"; }
t0=$(date +%s)

step "setup";                        bash scripts/setup.sh
step "cargo fmt --check";            cargo fmt --check
step "cargo clippy";                 cargo clippy --all-targets -- -D warnings
step "cargo test";                   cargo test
step "cargo build (wasm32)";         cargo build --lib --target wasm32-unknown-unknown
step "wasm-pack test --node";        wasm-pack test --node --mode no-install -- --test wasm_node
step "release wasm for the page";    bash scripts/build-wasm.sh
step "browser end-to-end tests";     node --test tests/e2e/
echo "all tests passed in $(( $(date +%s) - t0 )) s"
