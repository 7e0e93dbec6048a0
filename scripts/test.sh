#!/usr/bin/env bash
# Builds and runs every test (CTest). Sets everything up first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup.sh" "$root/build"
cd "$root/build"
ctest --output-on-failure -j2
