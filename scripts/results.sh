#!/usr/bin/env bash
# Regenerates docs/benchmarks/results.md and its plots (docs/benchmarks/results/) from one run
# of `dualspectra bench --all` on every dev set under $DUALSPECTRA_DATA (default:
# ../shared/datasets beside the clone), with the default options.
#   bash scripts/results.sh               # every pair of every set (~6 min on 2 idle cores)
#   bash scripts/results.sh --limit 1     # any extra `bench` argument: a smoke run (one pair a set)
# The JSON stays in target/results/all.json; the page names the date, the commit (with
# "+changes" when rust/ differs from it) and the machine.
set -euo pipefail
cd "$(dirname "$0")/.."
DATA="${DUALSPECTRA_DATA:-$(cd .. && pwd)/shared/datasets}"
[ -d "$DATA" ] || { echo "results: no datasets at $DATA (set DUALSPECTRA_DATA)" >&2; exit 1; }
mkdir -p target/results docs/benchmarks/results
cargo build --locked --release -p dualspectra-cli
target/release/dualspectra bench --all "$DATA" --quiet \
  --json target/results/all.json --svg docs/benchmarks/results/cumulative.svg "$@"
python3 scripts/results_page.py target/results/all.json docs/benchmarks/results.md \
  --commit "$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- rust || echo '+changes')" \
  --args "$*"
echo "results: wrote docs/benchmarks/results.md"
