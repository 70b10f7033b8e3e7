#!/usr/bin/env bash
# MeshLab filter plugin: build it against MeshLab 2020.09 (Debian) and run it in the real
# meshlabserver (under xvfb) on a generated mesh pair with a known answer, plus error paths.
# Needs scripts/setup.d/60-meshlab.sh. DUALSPECTRA_SKIP_MESHLAB=1 skips this stage;
# DUALSPECTRA_MESHLAB_LEVEL (3), DUALSPECTRA_MESHLAB_K (10), DUALSPECTRA_MESHLAB_TIMEOUT (900 s)
# size the region case.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ "${DUALSPECTRA_SKIP_MESHLAB:-0}" = 1 ] && { echo "meshlab: SKIPPED (DUALSPECTRA_SKIP_MESHLAB=1)"; exit 0; }

build=target/meshlab-build
# The top-level project with the plugin enabled; the Rust library is built by the Rust test
# stage's command (see scripts/test.d/40-cpp.sh), so cargo reuses that stage's artefacts.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDUALSPECTRA_BUILD_MESHLAB=ON -DMESHLAB_SCALAR=float \
      "-DDUALSPECTRA_CARGO_TEST_ARGS=--workspace;--exclude;dualspectra-py" \
      >"$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
t0=$(date +%s)
cmake --build "$build" --target dualspectra_cargo
echo "meshlab: cargo step $(( $(date +%s) - t0 )) s"
cmake --build "$build" --target filter_dualspectra meshlab_layer_arrays_test -j2
plugin=$(find "$build" -name libfilter_dualspectra.so -print -quit)
[ -n "$plugin" ] || { echo "meshlab: libfilter_dualspectra.so not built" >&2; exit 1; }

# vcg mesh <-> C arrays (deleted/unreferenced vertices, index map, selection mapping)
"$(find "$build" -name meshlab_layer_arrays_test -type f -print -quit)"

python3 tests/meshlab/test_meshlab_filter.py --plugin "$plugin" --ffi-lib target/debug/deps/libdualspectra_ffi.so
