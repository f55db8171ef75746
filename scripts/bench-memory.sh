#!/usr/bin/env bash
# Peak memory of `diagnose` on scans of 1,000, 20,000 and 200,000 points (issue 31), and on the
# 20,000-point scan of a part with a C backlash of 4e-4 rad, each in a process of its own: natively `testpiece diagnose FILE` (the file from `testpiece simulate
# --scan`, GNU time's maximum resident set size), and in the release wasm under Node the stage
# `diagnose_scan_N` of src/bench.rs (the same file, read and diagnosed by the same core call;
# Node's process.resourceUsage().maxRSS, which includes Node itself: ~45 MB). Prints a table.
# Usage: bash scripts/bench-memory.sh   (needs www/pkg built with the bench feature: npm run bench)
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
cargo build --release --quiet --bin testpiece
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo '| scan | points | native time | native peak RSS | wasm time | wasm peak RSS (Node) |'
echo '|---|---|---|---|---|---|'
for case in 20x25 40x250 100x1000 40x250+backlash_c; do
  layout=${case%+*}; h=${layout%x*}; r=${layout#*x}; n=$(( 2 * h * r ))
  stage=diagnose_scan_$n; effect=()
  if [[ $case == *+backlash_c ]]; then
    stage=${stage}_backlash_c; effect=(--effect backlash_c=4e-4)
  fi
  target/release/testpiece simulate --errors EX0B=0.01 --noise 0.0015 "${effect[@]}" --scan "$layout" > "$tmp/scan.csv"
  /usr/bin/time -f '%e %M' -o "$tmp/native" target/release/testpiece diagnose "$tmp/scan.csv" > /dev/null
  read -r nt nk < "$tmp/native"
  wasm=$(node --input-type=module -e "
    import fs from 'node:fs';
    const core = await import('$PWD/www/pkg/testpiece.js');
    core.initSync({ module: fs.readFileSync('$PWD/www/pkg/testpiece_bg.wasm') });
    const stage = new core.BenchStage('$stage');
    const t = performance.now();
    stage.run();
    console.log(((performance.now() - t) / 1000).toFixed(2), Math.round(process.resourceUsage().maxRSS / 1024));
  " 2>/dev/null || echo '— —')
  read -r wt wm <<< "$wasm"
  echo "| $case | $n | $nt s | $(( nk / 1024 )) MB | $wt s | $wm MB |"
done
