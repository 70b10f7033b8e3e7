#!/usr/bin/env bash
# C/C++: build the CMake project (cargo dev profile, sharing the Rust stage's cache), install it
# to a temporary prefix, and build + run the outside consumer project tests/cmake_consumer
# (find_package(dualspectra) + dualspectra::dualspectra, C and C++ API, typed exceptions).
set -euo pipefail
command -v cmake >/dev/null || { echo "cmake missing: run scripts/setup.d/40-cpp.sh" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cmake -S . -B "$tmp/build" -DDUALSPECTRA_CARGO_PROFILE=dev -DCMAKE_BUILD_TYPE=Release
cmake --build "$tmp/build" -j2
if [ -f "$tmp/build/CTestTestfile.cmake" ]; then ctest --test-dir "$tmp/build" --output-on-failure; fi
cmake --install "$tmp/build" --prefix "$tmp/prefix"
cmake -S tests/cmake_consumer -B "$tmp/consumer" -DCMAKE_PREFIX_PATH="$tmp/prefix"
cmake --build "$tmp/consumer" -j2
"$tmp/consumer/app"
