#!/usr/bin/env bash
# Rust unit and integration tests of the core, CLI and FFI crates (warnings as errors).
set -euo pipefail
RUSTFLAGS="${RUSTFLAGS:-} -D warnings" cargo test --workspace --exclude dualspectra-py 2>&1
