#!/usr/bin/env bash
# `npm run bench:process`: the whole-process cost of `testpiece identify FILE --json` and
# `testpiece diagnose FILE --json` beside a NumPy/SciPy identification of the same file
# (scripts/scipy_identify.py: least squares on the reference's Figure-19 design, no diagnosis),
# in one run, for the three example files (issue 21). Wall time per process, mean of RUNS runs.
# The SciPy side runs in a virtual environment made here (target/scipy-venv, numpy and scipy
# from the Python package registry), once.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
cargo build --release --quiet --bin testpiece
venv=target/scipy-venv
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c 'import numpy, scipy' 2>/dev/null; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet numpy scipy
fi
runs=${RUNS:-30}
design=tests/data/reference/sensitivity_physical.csv
# mean wall time of one run of the command, in ms
per_run() {
  local s e
  s=$(date +%s%N)
  for _ in $(seq "$runs"); do "$@" >/dev/null; done
  e=$(date +%s%N)
  echo "scale=2; ($e - $s) / $runs / 1000000" | bc
}
echo "| file | identify | diagnose | SciPy identification | SciPy / identify | SciPy / diagnose |"
echo "|---|---|---|---|---|---|"
for f in tests/data/reference/examples/example_*.csv; do
  id=$(per_run target/release/testpiece identify "$f" --json)
  dg=$(per_run target/release/testpiece diagnose "$f" --json)
  py=$(per_run "$venv/bin/python" scripts/scipy_identify.py "$f" "$design")
  printf '| %s | %s ms | %s ms | %s ms | %s | %s |\n' "$(basename "$f")" "$id" "$dg" "$py" \
    "$(echo "scale=1; $py / $id" | bc)" "$(echo "scale=1; $py / $dg" | bc)"
done
