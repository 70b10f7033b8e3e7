#!/usr/bin/env bash
# Python bindings: pytest on tests/python (against libigl + scipy) and mypy.stubtest on the
# typed package. pytest's exit code 5 (no tests collected) is a failure here.
set -uo pipefail
cd "$(dirname "$0")/../.."
PY=.venv/bin/python
[ -x "$PY" ] || { echo "no .venv: run scripts/setup.d/30-python.sh" >&2; exit 1; }
# Run from outside the source tree so the installed wheel is imported.
"$PY" -m pytest -rs -p no:cacheprovider tests/python
rc=$?
if [ "$rc" -eq 5 ]; then echo "pytest collected no tests" >&2; exit 1; fi
[ "$rc" -eq 0 ] || exit "$rc"
( cd /tmp && "$OLDPWD/$PY" -m mypy.stubtest dualspectra --allowlist "$OLDPWD/tests/python/stubtest-allowlist.txt" ) || exit 1
