#!/usr/bin/env bash
# Python: a project venv at .venv (Debian's pip refuses system installs) with pinned
# numpy/scipy/libigl/pytest/maturin/mypy, then the dualspectra wheel built by maturin
# (target/wheels) and installed into it. Idempotent: pip skips satisfied pins.
set -euo pipefail
cd "$(dirname "$0")/../.."
PY="${PYTHON:-python3}"
if ! "$PY" -c 'import venv, ensurepip' 2>/dev/null; then
  ${SUDO:-} apt-get install -y -o DPkg::Lock::Timeout=900 python3-venv python3-pip
fi
if [ ! -x .venv/bin/python ]; then
  "$PY" -m venv .venv
fi
.venv/bin/python -m pip install -q --disable-pip-version-check \
  numpy==2.4.6 scipy==1.17.1 libigl==2.6.3 pytest==9.2.0 maturin==1.16.0 mypy==2.4.1
rm -f target/wheels/dualspectra-*.whl
PATH="$PWD/.venv/bin:$PATH" .venv/bin/maturin build --release -m rust/dualspectra-py/Cargo.toml -o target/wheels
.venv/bin/python -m pip install -q --disable-pip-version-check --force-reinstall --no-deps target/wheels/dualspectra-*.whl
