#!/usr/bin/env bash
# Refresh apt lists once per machine-day (apt-cache and install need them).
set -euo pipefail
stamp=/var/lib/apt/periodic/dualspectra-update-stamp
if [ ! -f "$stamp" ] || [ -n "$(find "$stamp" -mmin +720 2>/dev/null)" ]; then
  ${SUDO:-} apt-get update -qq
  ${SUDO:-} mkdir -p "$(dirname "$stamp")" && ${SUDO:-} touch "$stamp"
fi
