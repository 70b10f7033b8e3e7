#!/usr/bin/env bash
# Blender add-on tests: Debian's Blender 3.4 (system Python 3.11 + numpy), and optionally
# the PyPI `bpy` 4.5 LTS module in a Python 3.11 venv (~370 MB download, ~1.3 GB on disk).
#   DUALSPECTRA_BPY=0 skips the venv; DUALSPECTRA_BPY_VENV sets where it goes.
set -euo pipefail
need=()
for pkg in blender python3-numpy python3.11-venv; do
  dpkg -s "$pkg" >/dev/null 2>&1 || need+=("$pkg")
done
if [ "${#need[@]}" -gt 0 ]; then
  ${SUDO:-} apt-get install -y -o DPkg::Lock::Timeout=900 "${need[@]}"
fi

if [ "${DUALSPECTRA_BPY:-1}" != 0 ]; then
  venv="${DUALSPECTRA_BPY_VENV:-$HOME/.cache/dualspectra/bpy-4.5-venv}"
  if ! "$venv/bin/python" -c "import bpy" >/dev/null 2>&1; then
    rm -rf "$venv"
    /usr/bin/python3.11 -m venv "$venv"
    "$venv/bin/pip" install -q --disable-pip-version-check "bpy>=4.5,<4.6"
  fi
fi
