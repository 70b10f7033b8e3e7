#!/usr/bin/env bash
# Rust unit and integration tests of the core, CLI and FFI crates (workspace lints deny warnings).
set -euo pipefail
cargo test --workspace --exclude dualspectra-py 2>&1
