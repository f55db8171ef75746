#!/usr/bin/env bash
# Builds the page's two wasm modules and their JS glue into www/pkg/ (ES modules, --target web).
# Usage: scripts/build-wasm.sh [--dev]
#
# Each step after cargo is skipped when its inputs are unchanged (issue 33 item 1):
# - wasm-bindgen writes into a staging directory in the build directory,
#   ${CARGO_TARGET_DIR:-target}/wasm-bindgen/<profile>/ (one per module), with a key file beside its output: the
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
# The page's two modules (issue 33 item 2), each the crate built with one feature of Cargo.toml
# and `--no-default-features`, in a cargo profile of its own (one profile for both would rebuild
# the crate at each switch of features):
# - the first module, `page-core` (www/pkg/testpiece.js, testpiece_bg.wasm): what the first view
#   calls, loaded with the page; the cap below is its cap;
# - the second module, `page-tools` (www/pkg/testpiece_tools.js, testpiece_tools_bg.wasm): the
#   Plan, Program, Error budget and Correction views, loaded by the worker when one is opened.
# Release: the profiles `wasm-release` and `wasm-tools` of Cargo.toml; --dev: `dev` and `wasm-tools-dev`.
release=true
if [ "${1:-}" = "--dev" ]; then release=false; fi
# TESTPIECE_WASM_FEATURES: extra cargo features of the first module (scripts/bench.sh: `bench`).
extra=${TESTPIECE_WASM_FEATURES:+,$TESTPIECE_WASM_FEATURES}
target=${CARGO_TARGET_DIR:-target}
out=www/pkg
hash() { sha256sum | cut -d' ' -f1; }
ms() { date +%s%3N; }
# wasm-opt: from the npm package binaryen (a devDependency, runs offline under Node); skipped
# with a note when `npm install` has not been run. Always from wasm-bindgen's output, never from
# an optimised wasm.
opt=node_modules/.bin/wasm-opt
# -Oz, not -O3: speed-neutral on the bench stages and smaller (the figures: BENCHMARKS.md);
# --converge (the passes repeated until the size stops falling): it had been left out for its
# time (35.6 s and 1,436,288 bytes against 75.2 s and 1,435,265, issue 33 item 5), and is back
# since the first module reached its cap (2 Dec 2026: 1,500,571 bytes in one pass, 1,499,416
# converged, 84 s against 152 s; the two modules are optimised side by side, BENCHMARKS.md);
# rustc's own level for this crate is in Cargo.toml [profile.wasm-release].
# --enable-simd: the dense scans' kernels are compiled for wasm's 128-bit SIMD (functions marked
# `simd128` in src/identify/ and src/numerics/products.rs; not the whole crate: 19 kB more,
# over the first module's cap), so the page needs a browser with it (Chrome/Edge 91, Firefox
# 89, Safari 16.4 and later).
opt_flags=(-Oz --converge --strip-debug --strip-producers
  --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext
  --enable-mutable-globals --enable-reference-types --enable-multivalue --enable-simd)
cache="$target/wasm-opt-cache"
keep=6   # cache entries kept (the newest used): both modules of a few builds
put() { if ! cmp -s "$1" "$2"; then mkdir -p "$(dirname "$2")"; cp "$1" "$2.tmp.$BASHPID" && mv "$2.tmp.$BASHPID" "$2"; fi; }
mkdir -p "$out"

# build_module NAME PROFILE FEATURES CAP: cargo, wasm-bindgen and wasm-opt for one module, into
# www/pkg/NAME.js and NAME_bg.wasm; fails when a release wasm is over CAP bytes.
build_module() {
  local name=$1 profile=$2 features=$3 cap=$4
  local flag="--profile $profile" dir=$profile
  if [ "$profile" = dev ]; then flag=; dir=debug; fi
  cargo build --lib --target wasm32-unknown-unknown $flag --no-default-features --features "$features"
  local input="$target/wasm32-unknown-unknown/$dir/testpiece.wasm"

  # 1. wasm-bindgen, into the staging directory, unless its key file matches.
  local stage="$target/wasm-bindgen/$dir"
  local bindgen_args=(--target web --no-typescript --out-name "$name")
  local bindgen_key
  bindgen_key=$( { sha256sum < "$input"; wasm-bindgen --version; echo "${bindgen_args[*]}"; } | hash)
  # The key file: the key on its first line, then `sha256sum` lines of the files written.
  if [ -f "$stage/.key" ] && [ "$(head -n1 "$stage/.key")" = "$bindgen_key" ] \
    && (cd "$stage" && tail -n +2 .key | sha256sum --check --quiet --status 2>/dev/null); then
    echo "[build-wasm] $name: wasm-bindgen skipped: its input and version are unchanged ($stage)"
  else
    local t; t=$(ms)
    rm -rf "$stage"; mkdir -p "$stage"
    wasm-bindgen "${bindgen_args[@]}" --out-dir "$stage" "$input"
    local sums; sums=$(cd "$stage" && find . -type f -print0 | sort -z | xargs -0 sha256sum)
    printf '%s\n%s\n' "$bindgen_key" "$sums" > "$stage/.key"
    echo "[build-wasm] $name: wasm-bindgen ran in $(( $(ms) - t )) ms"
  fi

  # 2. The module's wasm: wasm-opt's result from the cache, or wasm-opt run and cached (release).
  local wasm="$stage/${name}_bg.wasm"
  if $release; then
    if [ -x "$opt" ]; then
      local opt_key; opt_key=$( { sha256sum < "$wasm"; echo "${opt_flags[*]}"; "$opt" --version; } | hash)
      local entry="$cache/$opt_key.wasm" before; before=$(stat -c %s "$wasm")
      if [ -f "$entry" ]; then
        touch "$entry"
        echo "[build-wasm] $name: wasm-opt skipped: cached result for this input, flags and version ($entry)"
      else
        local t; t=$(ms)
        mkdir -p "$cache"
        "$opt" "${opt_flags[@]}" "$wasm" -o "$entry.tmp.$BASHPID"
        mv "$entry.tmp.$BASHPID" "$entry"
        echo "[build-wasm] $name: wasm-opt -Oz --converge ran in $(( $(ms) - t )) ms: $before -> $(stat -c %s "$entry") bytes (cached as $entry)"
        # Prune: only the $keep newest entries are kept (and no half-written file of a stopped run).
        ls -1t "$cache"/*.wasm | tail -n +$(( keep + 1 )) | xargs -r rm -f
        find "$cache" -name '*.tmp.*' -mmin +60 -delete
      fi
      wasm="$entry"
    else
      echo "[build-wasm] $opt not found (run npm install): the wasm is not optimised by wasm-opt"
    fi
  fi

  # 3. www/pkg/ from the staging directory and the module's wasm; a file is written only when it differs.
  (cd "$stage" && find . -type f ! -name .key ! -name "${name}_bg.wasm") | while read -r f; do put "$stage/$f" "$out/$f"; done
  put "$wasm" "$out/${name}_bg.wasm"
  local size gz; size=$(stat -c %s "$out/${name}_bg.wasm"); gz=$(gzip -9 -c "$out/${name}_bg.wasm" | wc -c)
  echo "[build-wasm] $out/${name}_bg.wasm: $size bytes, $gz gzipped ($profile, features $features)"
  if $release && [ "$size" -gt "$cap" ]; then
    if [ -n "$extra" ] && [ "$name" = testpiece ]; then
      # a build with extra features (the bench's stages) is not the page's module: told, not failed
      echo "[build-wasm] $name: $size bytes, over the page's cap of $cap bytes with the extra features$extra (not a page build)"
    else
      echo "[build-wasm] $name: $size bytes is over the cap of $cap bytes" >&2
      exit 1
    fi
  fi
}

# The caps of the release wasm (issue 21; issue 33 item 2: the cap stands for what the first
# view loads): 1.5 MB raw for the first module, and the same for the second. Speed matters more
# than bytes to an offline lab tool, so this crate is compiled for speed (opt-level 2,
# Cargo.toml) and wasm-opt -Oz (the sizes measured: BENCHMARKS.md); a build over a cap fails
# here, not in a browser.
#
# The two modules are built at the same time (issue 33 item 5): each profile has its own build
# directory and lock, and most of a release build is the crate's one codegen unit under LTO, one
# core each; their lines are labelled `[page-core]` / `[page-tools]`.
if $release; then
  core=(testpiece wasm-release "page-core$extra"); tools=(testpiece_tools wasm-tools page-tools)
else
  core=(testpiece dev "page-core$extra"); tools=(testpiece_tools wasm-tools-dev page-tools)
fi
build_module "${core[@]}" 1500000 2>&1 | sed -u 's/^/[page-core] /' &
core_pid=$!
build_module "${tools[@]}" 1500000 2>&1 | sed -u 's/^/[page-tools] /' &
tools_pid=$!
status=0
wait "$core_pid" || status=$?
wait "$tools_pid" || status=$?
if [ "$status" -ne 0 ]; then
  echo "[build-wasm] a module failed to build (its lines above)" >&2
  exit "$status"
fi
# The build id versions the service worker's cache: a hash of both modules and their glue.
build=$(cat "$out/testpiece_bg.wasm" "$out/testpiece.js" "$out/testpiece_tools_bg.wasm" "$out/testpiece_tools.js" | sha256sum | cut -c1-16)
printf "// Generated by scripts/build-wasm.sh\nexport const BUILD = '%s';\n" "$build" > "$target/wasm-bindgen/build.js"
put "$target/wasm-bindgen/build.js" "$out/build.js"
