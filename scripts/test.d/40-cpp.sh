#!/usr/bin/env bash
# C/C++: build the CMake project, run CTest, install it to a temporary prefix (the library
# stripped of debug info), and build + run the outside consumer project tests/cmake_consumer
# twice: find_package(dualspectra) alone (dualspectra::dualspectra: C and C++ API, options by
# name, typed exceptions, one Localizer locating two partials as the one-call form does; CGAL
# and OpenMesh not looked up), then with COMPONENTS cgal (the same through dualspectra::cgal).
# The Rust library is built by the Rust test stage's own command (scripts/test.d/10-rust.sh,
# through -DDUALSPECTRA_CARGO_TEST_ARGS), so after that stage cargo has nothing to rebuild; the
# CMake build tree persists in target/cpp-build (incremental reruns).
set -euo pipefail
cd "$(dirname "$0")/../.."
command -v cmake >/dev/null || { echo "cmake missing: run scripts/setup.d/40-cpp.sh" >&2; exit 1; }
build=target/cpp-build
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
t0=$(date +%s)
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release "-DDUALSPECTRA_CARGO_TEST_ARGS=--workspace;--exclude;dualspectra-py"
cmake --build "$build" --target dualspectra_cargo
t1=$(date +%s)
echo "cpp: cargo step $((t1 - t0)) s"
cmake --build "$build" -j2
if [ -f "$build/CTestTestfile.cmake" ]; then ctest --test-dir "$build" --output-on-failure; fi
cmake --install "$build" --prefix "$tmp/prefix"
echo "cpp: libdualspectra.a $(du -m target/debug/deps/libdualspectra_ffi.a | cut -f1) MB built," \
  "$(du -m "$(find "$tmp/prefix" -name libdualspectra.a -print -quit)" | cut -f1) MB installed"
for components in "" cgal; do
  echo "== consumer: find_package(dualspectra${components:+ COMPONENTS $components})"
  cmake -S tests/cmake_consumer -B "$tmp/consumer-$components" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$tmp/prefix" "-DDS_CONSUMER_COMPONENTS=$components"
  cmake --build "$tmp/consumer-$components" -j2
  "$tmp/consumer-$components/app"
done
