#!/usr/bin/env bash
# The Rust toolchain comes from rustup (Debian's cargo is too old for faer 0.24).
set -euo pipefail
if ! command -v cargo >/dev/null; then
  echo "cargo not found: install Rust >= 1.87 with rustup (https://rustup.rs), then re-run" >&2
  exit 1
fi
cargo fetch --locked 2>/dev/null || cargo fetch
