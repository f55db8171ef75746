#!/usr/bin/env bash
# `npm run bench`: native medians (cargo bench) beside the release wasm under Node, as a table.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
bash scripts/build-wasm.sh >/dev/null
native=$(cargo bench --quiet --bench stages -- "$@" 2>/dev/null | grep -P '^\w+\t')
wasm=$(node scripts/bench-wasm.mjs "$@")
printf '| stage | native median (µs) | wasm median (µs) | wasm / native |\n|---|---|---|---|\n'
join -t $'\t' -a 1 -e '' -o 0,1.2,2.2 <(sort <<<"$native") <(sort <<<"$wasm") |
  awk -F'\t' '{ r = ($3 != "" && $2 > 0) ? sprintf("%.2f", $3 / $2) : "—"; printf "| %s | %s | %s | %s |\n", $1, $2, ($3 == "" ? "—" : $3), r }'
