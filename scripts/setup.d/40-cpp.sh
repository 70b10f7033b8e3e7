#!/usr/bin/env bash
# C/C++ side: CMake, a C++17 compiler, CGAL 5.5 (header-only), OpenMesh and Eigen3
# (references for the cpp/tests and the adapters/examples). cbindgen is not needed:
# the C header is hand-written and checked against the Rust side by a cargo test.
set -euo pipefail
pkgs="cmake g++ make libcgal-dev libopenmesh-dev libeigen3-dev"
missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  ${SUDO:-} apt-get install -y --no-install-recommends -o DPkg::Lock::Timeout=900 $missing
fi
