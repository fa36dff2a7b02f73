#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (unit, end to end, rendering, bad input).
# Tests that need ../shared/models or OpenSCAD skip with a message when those are absent.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
cd build
ctest --output-on-failure -j"$jobs" "$@"
