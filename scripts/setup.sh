#!/usr/bin/env bash
# Installs everything the tests need on a fresh Debian machine (apt, pip, crates).
# Runs every scripts/setup.d/*.sh in name order; each stage is idempotent.
set -euo pipefail
cd "$(dirname "$0")/.."
export DEBIAN_FRONTEND=noninteractive
SUDO=""; if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
export SUDO
for stage in scripts/setup.d/*.sh; do
  echo "== setup: $stage"
  bash "$stage"
done
