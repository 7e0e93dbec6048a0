#!/usr/bin/env bash
# The main job: RS side by side with FCL's trees. Sets everything up first.
# Usage: scripts/compare.sh [--with-coal[=PREFIX]] [fcl_rs_compare options] [MESH_FILE ...]   (scripts/compare.sh --help)
#   --with-coal[=PREFIX]  also measure Coal 3.0's trees (Coal installed in PREFIX, default /opt/coal; Coal is not
#                         packaged in Debian 12, README's comparison section says how to build it). Then
#                         build/benchmarks/fcl_rs_bench_distance measures Coal's distance queries too.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
coal=""
case "${1:-}" in
  --with-coal) coal=/opt/coal; shift ;;
  --with-coal=*) coal="${1#--with-coal=}"; shift ;;
esac
bash "$root/scripts/setup.sh" "$root/build" >&2
if [ -n "$coal" ]; then
  if ! ls "$coal"/lib*/cmake/coal/coalConfig.cmake > /dev/null 2>&1; then
    echo "compare.sh: no Coal in $coal (lib*/cmake/coal/coalConfig.cmake); see README, 'Comparison'" >&2
    exit 1
  fi
  cmake -S "$root" -B "$root/build" -DFCL_RS_WITH_COAL=ON -DCMAKE_PREFIX_PATH="$coal" > /dev/null
  cmake --build "$root/build" -j2 --target fcl_rs_compare fcl_rs_bench_distance >&2
fi
exec "$root/build/benchmarks/fcl_rs_compare" "$@"
