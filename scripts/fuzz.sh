#!/usr/bin/env bash
# Fuzzes the CMM reader and the whole analysis with cargo-fuzz (libFuzzer, nightly toolchain).
#
#   scripts/fuzz.sh [seconds] [target...]
#
# seconds: time per target (default 60); targets: `cmm_reader` (cmm::read_and_match on arbitrary
# bytes) and `analysis` (analysis::analyse: reader → projection → identification → refinement →
# diagnosis; the first byte of an input picks the settings), both by default.
# Installs cargo-fuzz if missing (`cargo install cargo-fuzz`). Seeds: every file of
# tests/data/cmm/{formats,broken,fuzz} and tests/data/reference/examples/*.csv, copied into
# fuzz/corpus/<target>/ (kept between runs, not committed); fuzz/cmm.dict gives header words.
# Crashes and hangs (-timeout, FUZZ_TIMEOUT) are written to fuzz/artifacts/<target>/;
# each one becomes a file in tests/data/cmm/fuzz/ and a test in tests/it/edge_fuzz_regressions.rs.
# The final libFuzzer stats (executions, cov, ft) are in fuzz/logs/<target>.log.
# Env: FUZZ_SANITIZER (default `none`: safe Rust, 2-3x more executions than `address`),
# FUZZ_TIMEOUT (seconds per input, default 600: on a shared, loaded machine a 1.5 s input took 121 s of wall time under nice 19).
# Not part of `npm test` (too long).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
secs="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(cmm_reader analysis)

command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz
rustup toolchain list | grep -q '^nightly' || { echo "needs the nightly toolchain: rustup toolchain install nightly" >&2; exit 1; }

seeds=(tests/data/cmm/formats/* tests/data/cmm/broken/* tests/data/reference/examples/*.csv)
[ -d tests/data/cmm/fuzz ] && seeds+=(tests/data/cmm/fuzz/*)

mkdir -p fuzz/logs
for t in "${targets[@]}"; do
  corpus="fuzz/corpus/$t"
  mkdir -p "$corpus"
  for f in "${seeds[@]}"; do
    [ -f "$f" ] || continue
    b=$(basename "$f")
    case "$t" in
      # The analysis target reads its settings from the first byte: seed the strict default (0)
      # and "exclude bad rows + tool radius" (3).
      analysis)
        { printf '\x00'; cat "$f"; } > "$corpus/seed0_$b"
        { printf '\x03'; cat "$f"; } > "$corpus/seed3_$b" ;;
      *) cp "$f" "$corpus/seed_$b" ;;
    esac
  done
  echo "== fuzzing $t for $secs s ($(ls "$corpus" | wc -l) corpus files)"
  cargo +nightly fuzz run --fuzz-dir fuzz -s "${FUZZ_SANITIZER:-none}" "$t" "$corpus" -- \
    -max_total_time="$secs" -timeout="${FUZZ_TIMEOUT:-600}" -report_slow_units=600 -max_len=65536 \
    -dict=fuzz/cmm.dict -print_final_stats=1 2>&1 | tee "fuzz/logs/$t.log" | grep -E 'DONE|stat::|crash|panicked|Test unit written' || true
  if ls "fuzz/artifacts/$t"/* >/dev/null 2>&1; then
    echo "!! $t: artifacts in fuzz/artifacts/$t (crashes or hangs): turn each into a regression test"
  fi
done
