#!/usr/bin/env bash
# Python: a project venv at .venv (Debian's pip refuses system installs) with pinned
# numpy/scipy/libigl/pytest/maturin/mypy, dask.distributed (the batch search's cluster test: a
# LocalCluster), zig (maturin links with it) and auditwheel, then the
# dualspectra wheel as published (pyproject.toml: abi3, stripped, licence texts) built once into
# target/wheels: manylinux_2_28 (zig links against glibc 2.28's symbol versions), so that it
# also loads in Blender's and other distributions' Pythons. It is installed into .venv; the
# Python and Blender test stages use this file. Idempotent: pip skips satisfied pins.
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
  numpy==2.4.6 scipy==1.17.1 libigl==2.6.3 pytest==9.2.0 maturin==1.16.0 mypy==2.4.1 \
  ziglang==0.15.2 auditwheel==6.8.2 "dask[distributed]==2026.8.0"
rm -f target/wheels/dualspectra-*.whl
t0=$(date +%s)
PATH="$PWD/.venv/bin:$PATH" .venv/bin/maturin build --zig --compatibility manylinux_2_28 -o target/wheels
echo "python: wheel built in $(( $(date +%s) - t0 )) s: $(ls target/wheels/dualspectra-*.whl)"
.venv/bin/python -m pip install -q --disable-pip-version-check --force-reinstall --no-deps target/wheels/dualspectra-*.whl
