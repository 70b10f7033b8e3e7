#!/usr/bin/env bash
# Rust unit and integration tests of the core, CLI and FFI crates; every test binary runs (--no-fail-fast).
set -euo pipefail
cargo test --workspace --exclude dualspectra-py --no-fail-fast 2>&1
