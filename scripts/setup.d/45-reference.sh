#!/usr/bin/env bash
# rust/dualspectra-reference: libclang for autocxx's binding generator (bindgen loads it when
# the crate's build script runs). CGAL and Eigen come from 40-cpp.sh. libigl's C++ headers are
# in no Debian 12 package (the Python tests use the libigl wheel from 30-python.sh).
set -euo pipefail
pkgs="libclang-dev"
missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  ${SUDO:-} apt-get install -y --no-install-recommends -o DPkg::Lock::Timeout=900 $missing
fi
