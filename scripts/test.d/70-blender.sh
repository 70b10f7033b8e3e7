#!/usr/bin/env bash
# The Blender add-on, headless, with the real dualspectra wheel:
#   1. Debian's Blender 3.4 (system Python 3.11), add-on installed the legacy way
#      ($BLENDER_USER_SCRIPTS/addons/dualspectra_blender + the package unzipped in it);
#   2. PyPI bpy 4.5 LTS (venv from scripts/setup.d/70-blender.sh), add-on installed as a
#      Blender 4.2+ extension (.zip with the wheel under wheels/), if the venv exists.
# Each writes only under a temporary HOME. Exit status: non-zero if any run failed.
set -uo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)

command -v blender >/dev/null || { echo "blender not installed: run scripts/setup.d/70-blender.sh" >&2; exit 1; }
# The manylinux wheel scripts/setup.d/30-python.sh built (the one the Python stage tested).
wheel=$(ls -t target/wheels/dualspectra-*-manylinux_2_28_x86_64.whl 2>/dev/null | head -1)
[ -n "$wheel" ] || { echo "no manylinux wheel in target/wheels: run scripts/setup.d/30-python.sh" >&2; exit 1; }
echo "wheel: $wheel"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 blender_addon/build_extension.py --wheel "$wheel" \
  --legacy "$tmp/scripts/addons" --extension "$tmp/dualspectra_blender.zip" || exit 1

status=0
args=(${DUALSPECTRA_BLENDER_TEST_ARGS:-})

echo "== Blender $(blender --version 2>/dev/null | head -1 | awk '{print $2}') (Debian), legacy add-on"
mkdir -p "$tmp/home34"
if ! HOME="$tmp/home34" BLENDER_USER_SCRIPTS="$tmp/scripts" \
    blender -b --factory-startup --python-exit-code 1 --python "$root/tests/blender/test_addon.py" -- "${args[@]}"; then
  status=1
fi

venv="${DUALSPECTRA_BPY_VENV:-$HOME/.cache/dualspectra/bpy-4.5-venv}"
if [ -x "$venv/bin/python" ]; then
  echo "== PyPI bpy $("$venv/bin/python" -c 'import bpy; print(bpy.app.version_string)' 2>/dev/null), extension"
  # Blender's own manifest check (what `blender --command extension validate` runs: the bpy
  # module has no blender binary), with Blender's list of valid tags.
  scripts=$("$venv/bin/python" -c 'import bpy; print(bpy.utils.system_resource("SCRIPTS"))' 2>/dev/null | tail -1)
  if ! "$venv/bin/python" "$scripts/addons_core/bl_pkg/cli/blender_ext.py" validate \
      --valid-tags "$scripts/modules/_bpy_internal/extensions/tags.py" "$tmp/dualspectra_blender.zip"; then
    echo "FAIL extension validate" >&2; status=1
  fi
  mkdir -p "$tmp/home45"
  if ! HOME="$tmp/home45" "$venv/bin/python" "$root/tests/blender/test_addon.py" \
      --extension "$tmp/dualspectra_blender.zip" "${args[@]}"; then
    status=1
  fi
else
  echo "SKIP PyPI bpy 4.5: no venv at $venv (scripts/setup.d/70-blender.sh creates it unless DUALSPECTRA_BPY=0)"
fi
exit $status
