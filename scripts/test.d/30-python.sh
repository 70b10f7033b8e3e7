#!/usr/bin/env bash
# Python bindings: pytest on tests/python (against libigl + scipy), mypy --strict and
# mypy.stubtest on the typed package, and no native module committed in the source tree.
# pytest's exit code 5 (no tests collected) is a failure here.
set -uo pipefail
cd "$(dirname "$0")/../.."
PY=.venv/bin/python
[ -x "$PY" ] || { echo "no .venv: run scripts/setup.d/30-python.sh" >&2; exit 1; }
# A build product in git (e.g. from `maturin develop`) would shadow the wheel for whoever checks out.
if command -v git >/dev/null && git rev-parse --git-dir >/dev/null 2>&1; then
  committed=$(git ls-files -- '*.so' '*.pyd' '*.dylib')
  [ -z "$committed" ] || { echo "native modules are committed: $committed" >&2; exit 1; }
fi
# Run from outside the source tree so the installed wheel is imported.
"$PY" -m pytest -rs -p no:cacheprovider tests/python
rc=$?
if [ "$rc" -eq 5 ]; then echo "pytest collected no tests" >&2; exit 1; fi
[ "$rc" -eq 0 ] || exit "$rc"
"$PY" -m mypy --strict rust/dualspectra-py/python/dualspectra || exit 1
( cd /tmp && "$OLDPWD/$PY" -m mypy.stubtest dualspectra --allowlist "$OLDPWD/tests/python/stubtest-allowlist.txt" ) || exit 1
