#!/usr/bin/env bash
# Installs what is needed (scripts/setup.sh) and runs every test stage in
# scripts/test.d/*.sh in name order. Exit status is non-zero if any stage failed.
#   bash scripts/test.sh            # setup + all tests
#   bash scripts/test.sh --no-setup # tests only
set -uo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" != "--no-setup" ]; then
  bash scripts/setup.sh || { echo "setup failed" >&2; exit 1; }
fi
export DUALSPECTRA_DATA="${DUALSPECTRA_DATA:-$(cd .. && pwd)/shared/datasets}"
[ -d "$DUALSPECTRA_DATA" ] || echo "note: dataset directory $DUALSPECTRA_DATA absent; dataset tests will skip"
passed=0; failed=0; failed_names=()
for stage in scripts/test.d/*.sh; do
  echo "== test stage: $stage"
  start=$(date +%s)
  if bash "$stage"; then
    passed=$((passed + 1)); echo "== stage passed: $stage ($(( $(date +%s) - start )) s)"
  else
    failed=$((failed + 1)); failed_names+=("$stage"); echo "== stage FAILED: $stage ($(( $(date +%s) - start )) s)"
  fi
done
echo
[ "$failed" -gt 0 ] && echo "failed stages: ${failed_names[*]}"
echo "stages: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
