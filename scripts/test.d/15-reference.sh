#!/usr/bin/env bash
# The numerical core against outside references from cargo test (rust/dualspectra-reference):
# laws, and CGAL 5.5 / Eigen 3 through autocxx. Here the C++ reference is required (the setup
# installs it), so a missing one fails instead of skipping.
set -euo pipefail
cd "$(dirname "$0")/../.."
DUALSPECTRA_REQUIRE_CPP_REFERENCE=1 cargo test -p dualspectra-reference --no-fail-fast 2>&1
