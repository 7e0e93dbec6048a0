#!/usr/bin/env bash
# The main job: RS side by side with FCL's trees. Installs the few Debian packages it needs when missing (sudo when
# not root), builds fcl_rs_compare and the core library for double only in build/ (scripts/setup.sh --for compare),
# then runs it; progress and tables on stdout. scripts/test.sh builds the rest (and float).
# Usage: scripts/compare.sh [--with-coal[=PREFIX]] [fcl_rs_compare options] [MESH_FILE ...]
#   --with-coal[=PREFIX]  also measure Coal 3.0's trees (Coal installed in PREFIX, default /opt/coal; Coal is not
#                         packaged in Debian 12, README's comparison section says how to build it). Then
#                         build/benchmarks/fcl_rs_bench_distance measures Coal's distance queries too.
#   MESH_FILE ...         compare on these meshes (any format assimp reads), each against itself
#   fcl_rs_compare's options: --queries N (poses per pair, default 200), --seed N, --pairs, --csv FILE, --verify,
#                         --wall-clock; with the program built, --help prints its full help below this one.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
compare="$root/build/benchmarks/fcl_rs_compare"
for arg in "$@"; do
  case "$arg" in
    -h | --help)
      sed -n '2,11p' "${BASH_SOURCE[0]}" | cut -c3-
      if [ -x "$compare" ]; then echo; "$compare" --help; fi
      exit 0 ;;
  esac
done
coal=""
case "${1:-}" in
  --with-coal) coal=/opt/coal; shift ;;
  --with-coal=*) coal="${1#--with-coal=}"; shift ;;
esac
if [ -n "$coal" ] && ! ls "$coal"/lib*/cmake/coal/coalConfig.cmake > /dev/null 2>&1; then
  echo "compare.sh: no Coal in $coal (lib*/cmake/coal/coalConfig.cmake); see README, 'Comparison'" >&2
  exit 1
fi
bash "$root/scripts/setup.sh" --for compare "$root/build"
if [ -n "$coal" ]; then
  echo "== fcl_rs compare: adding Coal from $coal"
  cmake -S "$root" -B "$root/build" -DFCL_RS_WITH_COAL=ON -DCMAKE_PREFIX_PATH="$coal" > /dev/null
  cmake --build "$root/build" -j2 --target fcl_rs_compare fcl_rs_bench_distance
fi
echo "== fcl_rs compare: running build/benchmarks/fcl_rs_compare $* (a table per mesh pair as it finishes)"
exec "$compare" "$@"
