#!/usr/bin/env bash
# Builds the release wasm and its JS glue into www/pkg/ (ES module for the page, --target web).
# Usage: scripts/build-wasm.sh [--dev]
#
# Each step after cargo is skipped when its inputs are unchanged (issue 33 item 1):
# - wasm-bindgen writes into a staging directory in the build directory,
#   ${CARGO_TARGET_DIR:-target}/wasm-bindgen/<profile>/, with a key file beside its output: the
#   sha256 of cargo's wasm, wasm-bindgen's version and arguments, and of each file it wrote. It
#   is run again only when that key or one of those files differs.
# - wasm-opt's result is kept in ${CARGO_TARGET_DIR:-target}/wasm-opt-cache/<key>.wasm, the key
#   the sha256 of wasm-bindgen's output wasm, the exact wasm-opt flags and wasm-opt's version;
#   a hit is copied, a miss runs wasm-opt and stores its result (the newest few kept).
# www/pkg/ is then brought up to date from those files (a file is written only when it
# differs), so any change to the Rust code that changes cargo's wasm gives a new optimised wasm.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
# Release: the `wasm-release` profile of Cargo.toml (the release profile at opt-level 3).
profile=wasm-release; flag="--profile wasm-release"
if [ "${1:-}" = "--dev" ]; then profile=debug; flag=; fi
# TESTPIECE_WASM_FEATURES: extra cargo features (scripts/bench.sh: `bench`).
features=${TESTPIECE_WASM_FEATURES:+--features $TESTPIECE_WASM_FEATURES}
cargo build --lib --target wasm32-unknown-unknown $flag $features
target=${CARGO_TARGET_DIR:-target}
input="$target/wasm32-unknown-unknown/$profile/testpiece.wasm"
out=www/pkg
hash() { sha256sum | cut -d' ' -f1; }
ms() { date +%s%3N; }

# 1. wasm-bindgen, into the staging directory, unless its key file matches.
stage="$target/wasm-bindgen/$profile"
bindgen_args=(--target web --no-typescript)
bindgen_key=$( { sha256sum < "$input"; wasm-bindgen --version; echo "${bindgen_args[*]}"; } | hash)
stamp="$stage/.key"
# The key file: the key on its first line, then `sha256sum` lines of the files written.
if [ -f "$stamp" ] && [ "$(head -n1 "$stamp")" = "$bindgen_key" ] \
  && (cd "$stage" && tail -n +2 .key | sha256sum --check --quiet --status 2>/dev/null); then
  echo "[build-wasm] wasm-bindgen skipped: its input and version are unchanged ($stage)"
else
  t=$(ms)
  rm -rf "$stage"; mkdir -p "$stage"
  wasm-bindgen "${bindgen_args[@]}" --out-dir "$stage" "$input"
  sums=$(cd "$stage" && find . -type f -print0 | sort -z | xargs -0 sha256sum)
  printf '%s\n%s\n' "$bindgen_key" "$sums" > "$stamp"
  echo "[build-wasm] wasm-bindgen ran in $(( $(ms) - t )) ms"
fi

# 2. The page's wasm: wasm-opt's result from the cache, or wasm-opt run and cached (release).
# Optimisation step (release only): wasm-opt -Oz from the npm package binaryen (a devDependency,
# runs offline under Node); skipped with a note when `npm install` has not been run. Always from
# wasm-bindgen's output, never from an optimised wasm.
opt=node_modules/.bin/wasm-opt
# -Oz, not -O3: speed-neutral on the bench stages and smaller (the figures: BENCHMARKS.md);
# --converge: the passes repeated until the size stops falling;
# rustc's own level for this crate is in Cargo.toml [profile.wasm-release].
opt_flags=(-Oz --converge --strip-debug --strip-producers
  --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext
  --enable-mutable-globals --enable-reference-types --enable-multivalue)
cache="$target/wasm-opt-cache"
keep=4   # cache entries kept (the newest used)
wasm="$stage/testpiece_bg.wasm"
if [ "$profile" = wasm-release ]; then
  if [ -x "$opt" ]; then
    opt_key=$( { sha256sum < "$wasm"; echo "${opt_flags[*]}"; "$opt" --version; } | hash)
    entry="$cache/$opt_key.wasm"
    before=$(stat -c %s "$wasm")
    if [ -f "$entry" ]; then
      touch "$entry"
      echo "[build-wasm] wasm-opt skipped: cached result for this input, flags and version ($entry)"
    else
      t=$(ms)
      mkdir -p "$cache"
      "$opt" "${opt_flags[@]}" "$wasm" -o "$entry.tmp.$$"
      mv "$entry.tmp.$$" "$entry"
      echo "[build-wasm] wasm-opt -Oz ran in $(( $(ms) - t )) ms: $before -> $(stat -c %s "$entry") bytes (cached as $entry)"
      # Prune: only the $keep newest entries are kept (and no half-written file of a stopped run).
      ls -1t "$cache"/*.wasm | tail -n +$(( keep + 1 )) | xargs -r rm -f
      find "$cache" -name '*.tmp.*' -mmin +60 -delete
    fi
    wasm="$entry"
  else
    echo "[build-wasm] $opt not found (run npm install): the wasm is not optimised by wasm-opt"
  fi
fi

# 3. www/pkg/ from the staging directory and the page's wasm; a file is written only when it differs.
put() { if ! cmp -s "$1" "$2"; then mkdir -p "$(dirname "$2")"; cp "$1" "$2.tmp.$$" && mv "$2.tmp.$$" "$2"; fi; }
mkdir -p "$out"
(cd "$stage" && find . -type f ! -name .key ! -name testpiece_bg.wasm) | while read -r f; do put "$stage/$f" "$out/$f"; done
put "$wasm" "$out/testpiece_bg.wasm"
# The build id versions the service worker's cache: a hash of the core and its glue.
build=$(cat "$out/testpiece_bg.wasm" "$out/testpiece.js" | sha256sum | cut -c1-16)
printf "// Generated by scripts/build-wasm.sh\nexport const BUILD = '%s';\n" "$build" > "$stage.build.js"
put "$stage.build.js" "$out/build.js"
size=$(stat -c %s "$out/testpiece_bg.wasm")
gz=$(gzip -9 -c "$out/testpiece_bg.wasm" | wc -c)
echo "[build-wasm] $out/testpiece_bg.wasm: $size bytes, $gz gzipped ($profile)"
# The cap of the release wasm (issue 21): 1.5 MB raw. Speed matters more than bytes to an
# offline lab tool, so this crate is compiled for speed (opt-level 2, Cargo.toml) and wasm-opt -Oz
# (the sizes measured: BENCHMARKS.md); a build over the cap fails here, not in a browser.
cap=1500000
if [ "$profile" = wasm-release ] && [ "$size" -gt "$cap" ]; then
  echo "[build-wasm] $size bytes is over the cap of $cap bytes" >&2
  exit 1
fi
