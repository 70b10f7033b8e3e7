#!/usr/bin/env bash
# MeshLab 2025.07 filter plugin, both builds of one CMake option (MESHLAB_SCALAR):
#  - double, for PyMeshLab 2025.7 (linked against its libmeshlab-common.so): loaded with
#    pymeshlab.load_plugin and run headless by tests/meshlab/test_pymeshlab_filter.py (pytest:
#    the parameters, the region's IoU on a generated cut, the result numbers, the score, and
#    the bad inputs as PyMeshLab exceptions carrying the library's message);
#  - float, for the MeshLab 2025.07 application (no GUI here): linked with --no-undefined
#    against the application's libmeshlab-common.so that scripts/setup.d/65-meshlab-2025.sh
#    took from Debian's package (when it could; else with MeshLab's symbols left undefined, as a
#    user builds it), then checked to export the Qt plugin entry points with MeshLab's filter
#    plugin IID and to use float scalars.
# Needs scripts/setup.d/65-meshlab-2025.sh. DUALSPECTRA_SKIP_MESHLAB=1 skips this stage.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ "${DUALSPECTRA_SKIP_MESHLAB:-0}" = 1 ] && { echo "pymeshlab: SKIPPED (DUALSPECTRA_SKIP_MESHLAB=1)"; exit 0; }
app_lib=target/meshlab-2025.07-src/app/libmeshlab-common.so

# The top-level project with the plugin enabled; the Rust library is built by the Rust test
# stage's command (see scripts/test.d/40-cpp.sh), so cargo reuses that stage's artefacts.
build_flavour() { # scalar, build dir, extra cmake arguments
  local scalar=$1 build=$2; shift 2
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DDUALSPECTRA_BUILD_MESHLAB=ON -DDUALSPECTRA_MESHLAB_TESTS=OFF \
        -DDUALSPECTRA_BUILD_TESTS=OFF -DDUALSPECTRA_BUILD_EXAMPLES=OFF \
        -DMESHLAB_VERSION=2025.07 "-DMESHLAB_SCALAR=$scalar" "$@" \
        "-DDUALSPECTRA_CARGO_TEST_ARGS=--workspace;--exclude;dualspectra-py" \
        >"$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
  local t0; t0=$(date +%s)
  cmake --build "$build" --target dualspectra_cargo
  cmake --build "$build" --target filter_dualspectra -j2
  echo "pymeshlab: $scalar build $(( $(date +%s) - t0 )) s"
}

build_flavour double target/meshlab-2025-double-build
double_plugin=target/meshlab-2025-double-build/meshlab_filter/plugins/libfilter_dualspectra.so

if [ -f "$app_lib" ]; then
  build_flavour float target/meshlab-2025-float-build "-DMESHLAB_COMMON_LIBRARY=$PWD/$app_lib"
  echo "pymeshlab: float build linked with --no-undefined against MeshLab $(cat target/meshlab-2025.07-src/app/version)'s libmeshlab-common.so"
else
  build_flavour float target/meshlab-2025-float-build -UMESHLAB_COMMON_LIBRARY
  echo "pymeshlab: float build linked with MeshLab's symbols undefined (no application library from setup)"
fi
float_plugin=target/meshlab-2025-float-build/meshlab_filter/plugins/libfilter_dualspectra.so
failed=0
set +e # each check reports its own status
check() { # description, status of the check
  if [ "$2" = 0 ]; then echo "  ok   float plugin: $1"; else echo "  FAIL float plugin: $1"; failed=1; fi
}
exports=$(nm -D --defined-only "$float_plugin" | awk '{ print $3 }')
imports=$(nm -D --undefined-only -C "$float_plugin")
grep -qx qt_plugin_instance <<<"$exports"; check "exports qt_plugin_instance" $?
grep -qx qt_plugin_query_metadata <<<"$exports"; check "exports qt_plugin_query_metadata" $?
grep -qa 'vcg.meshlab.FilterPlugin/1.0' "$float_plugin"; check "declares the IID vcg.meshlab.FilterPlugin/1.0" $?
# MeshLab's getMLVersion() returns meshlab_xstr(MESHLAB_VERSION) inlined into the plugin, which the
# optimiser stores as immediates rather than a string: check the definition the compiler got (the
# double build, the same sources, is loaded by PyMeshLab 2025.7, which refuses another version).
grep -q 'MESHLAB_VERSION=2025\.07' target/meshlab-2025-float-build/meshlab_filter/CMakeFiles/filter_dualspectra.dir/flags.make
check "built for MeshLab 2025.07 (MESHLAB_VERSION=2025.07)" $?
grep -qF 'RichFloat::RichFloat(QString const&, float,' <<<"$imports"; check "uses float scalars" $?
! grep -q '^ds_' <<<"$exports"; check "keeps the library's C ABI private (no ds_* export)" $?
set -e
[ "$failed" = 0 ] || exit 1

DUALSPECTRA_PYMESHLAB_PLUGIN="$double_plugin" DUALSPECTRA_FFI_LIB=target/debug/deps/libdualspectra_ffi.so \
  .venv/bin/python -m pytest -p no:cacheprovider -rs -s tests/meshlab/test_pymeshlab_filter.py
