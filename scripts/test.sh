#!/usr/bin/env bash
# Installs what is needed (scripts/setup.sh) and runs every test stage in
# scripts/test.d/*.sh in name order, then prints a table: per stage, the tests passed,
# skipped and failed (read from the runners' own summary lines: cargo's "test result:",
# pytest's, CTest's "tests passed ... out of", and the "ok" / "FAIL" / "SKIP" lines of the
# MeshLab, consumer and Blender checks) and its seconds. Exit status is non-zero if any stage
# failed.
#   bash scripts/test.sh            # setup + all tests
#   bash scripts/test.sh --no-setup # tests only
set -uo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" != "--no-setup" ]; then
  bash scripts/setup.sh || { echo "setup failed" >&2; exit 1; }
fi
export DUALSPECTRA_DATA="${DUALSPECTRA_DATA:-$(cd .. && pwd)/shared/datasets}"
[ -d "$DUALSPECTRA_DATA" ] || echo "note: dataset directory $DUALSPECTRA_DATA absent; dataset tests will skip"

# Counts in a stage's output: prints "passed skipped failed". Rust tests that the run after
# the line "== dataset tests" executes were counted as ignored (skipped) before it.
count_tests() {
  awk '
    function n(pattern,   s) { s = $0; if (match(s, "[0-9]+ " pattern)) return substr(s, RSTART, RLENGTH) + 0; return 0 }
    /^== dataset tests/ { data = 1 }
    /test result: / {
      if (data) { ran = n("passed") + n("failed"); p += n("passed"); f += n("failed"); s -= ran }
      else { p += n("passed"); f += n("failed"); s += n("ignored") }
      next
    }
    /^=+ .* in [0-9.]+s.*=+$/ { p += n("passed"); f += n("failed") + n("error"); s += n("skipped"); next }
    /tests passed, [0-9]+ tests? failed out of [0-9]+/ {
      match($0, /failed out of [0-9]+/); total = substr($0, RSTART + 14, RLENGTH - 14) + 0
      p += total - n("tests? failed"); f += n("tests? failed"); next
    }
    /\(Skipped\)[[:space:]]*$/ { p -= 1; s += 1; next }
    /^[[:space:]]*ok[[:space:]][[:space:]]/ { p += 1; next }
    /^[[:space:]]*FAIL[[:space:]]/ { f += 1; next }
    /^[[:space:]]*SKIP[[:space:]]/ { s += 1; next }
    END { if (s < 0) s = 0; printf "%d %d %d\n", p, s, f }
  ' "$1"
}

logs=$(mktemp -d); trap 'rm -rf "$logs"' EXIT
passed=0; failed=0; failed_names=(); rows=()
tp=0; ts=0; tf=0
for stage in scripts/test.d/*.sh; do
  name=$(basename "$stage" .sh)
  echo "== test stage: $stage"
  start=$(date +%s)
  bash "$stage" 2>&1 | tee "$logs/$name.log"
  rc=${PIPESTATUS[0]}
  seconds=$(( $(date +%s) - start ))
  if [ "$rc" -eq 0 ]; then
    passed=$((passed + 1)); result=passed; echo "== stage passed: $stage ($seconds s)"
  else
    failed=$((failed + 1)); result=FAILED; failed_names+=("$stage"); echo "== stage FAILED: $stage ($seconds s)"
  fi
  read -r p s f < <(count_tests "$logs/$name.log")
  tp=$((tp + p)); ts=$((ts + s)); tf=$((tf + f))
  rows+=("$(printf '%-16s %7d %8d %7d %8d  %s' "$name" "$p" "$s" "$f" "$seconds" "$result")")
done
echo
printf '%-16s %7s %8s %7s %8s  %s\n' stage passed skipped failed seconds result
printf '%s\n' "${rows[@]}"
echo
[ "$failed" -gt 0 ] && echo "failed stages: ${failed_names[*]}"
echo "tests: $tp passed, $tf failed, $ts skipped"
echo "stages: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
