#!/usr/bin/env bash
# `npm test`: set up, then run every test: format, lints, native tests, the wasm tests under
# Node (which build the library for wasm32: no separate wasm32 debug build), the release wasm
# and the browser end-to-end tests in headless Debian Chromium. Each step's time is printed at
# the end.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
t0=$(date +%s)
times=()
step() {
  local name=$1; shift
  printf '\n\033[1m== %s\033[0m\n' "$name"
  local s; s=$(date +%s)
  "$@"
  times+=("$(printf '%5d s  %s' $(( $(date +%s) - s )) "$name")")
}

step "setup"                        bash scripts/setup.sh
step "cargo fmt --check"            cargo fmt --check
step "cargo clippy"                 cargo clippy --all-targets -- -D warnings
step "cargo test"                   cargo test
step "wasm-pack test --node"        wasm-pack test --node --mode no-install -- --test wasm_node
step "release wasm for the page"    bash scripts/build-wasm.sh
step "browser end-to-end tests"     node --test tests/e2e/
printf '\n\033[1m== time per step\033[0m\n'
printf '%s\n' "${times[@]}"
echo "all tests passed in $(( $(date +%s) - t0 )) s"
