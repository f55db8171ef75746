#!/usr/bin/env bash
# Installs, idempotently and only when missing, everything testpiece needs beyond Rust, Node and
# npm: the wasm32 target, wasm-bindgen-cli at exactly the wasm-bindgen version of Cargo.lock,
# wasm-pack, Debian's chromium, the npm dev dependencies, and the two G-code parsers the tests
# read the programs with (PyPI, in a venv under target/). Nothing is downloaded from GitHub:
# wasm-pack's own wasm-opt download is off in Cargo.toml and tools are found on PATH.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"

say() { printf '\033[1m[setup]\033[0m %s\n' "$*"; }

# 1. The wasm32 target.
if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  say "adding the wasm32-unknown-unknown target"
  rustup target add wasm32-unknown-unknown
fi

# 2. wasm-bindgen-cli pinned to Cargo.lock's wasm-bindgen.
want=$(awk '/^name = "wasm-bindgen"$/{getline; gsub(/version = |"/,""); print; exit}' Cargo.lock)
have=$(wasm-bindgen --version 2>/dev/null | awk '{print $2}' || true)
if [ "$have" != "$want" ]; then
  say "installing wasm-bindgen-cli $want (found: ${have:-none})"
  # Its own lock pins a webpki-roots the registry may not serve: retry without --locked.
  cargo install wasm-bindgen-cli --version "=$want" --locked \
    || cargo install wasm-bindgen-cli --version "=$want"
fi

# 3. wasm-pack (for `wasm-pack test --node`).
if ! command -v wasm-pack >/dev/null 2>&1; then
  say "installing wasm-pack"
  cargo install wasm-pack --locked || cargo install wasm-pack
fi

# 4. Debian's chromium for the browser tests (never a browser download of a test tool's own).
if [ ! -x /usr/bin/chromium ]; then
  say "installing Debian's chromium"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq chromium >/dev/null
fi

# 5. npm dev dependencies (playwright-core; no browser download).
if [ ! -d node_modules/playwright-core ] || [ package-lock.json -nt node_modules/.package-lock.json ]; then
  say "installing npm dev dependencies"
  PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund
fi
# 6. The independent G-code parsers of tests/it/program_parsers.rs (pygcode, gcodeparser) in
#    target/gcode-venv (PyPI; python3 with venv and pip is all a machine needs).
venv=target/gcode-venv
if ! "$venv/bin/python" -c 'import pygcode, gcodeparser' >/dev/null 2>&1; then
  say "installing pygcode and gcodeparser into $venv"
  mkdir -p target
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --disable-pip-version-check pygcode==0.2.1 gcodeparser==0.3.0
fi
say "ready: $(rustc --version), wasm-bindgen $(wasm-bindgen --version | awk '{print $2}'), $(wasm-pack --version), $(/usr/bin/chromium --version)"
