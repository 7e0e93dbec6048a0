#!/usr/bin/env bash
# The main job: RS side by side with FCL's trees. Sets everything up first.
# Usage: scripts/compare.sh [fcl_rs_compare options] [MESH_FILE ...]   (scripts/compare.sh --help)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup.sh" "$root/build" >&2
exec "$root/build/benchmarks/fcl_rs_compare" "$@"
