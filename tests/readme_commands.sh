#!/usr/bin/env bash
# ctest (readme_commands): runs README.md's commands. Each is first found verbatim in README.md, then run as shown
# with build/ standing for BUILD_DIR and written files going to BUILD_DIR/readme_commands; long benchmarks get a
# smaller workload appended (fewer poses, frames or meshes, one timed pass), placeholders (MESH, PREFIX) a real value.
# Run elsewhere: the C++ and Python quick starts and the Python environment example (example_quickstart, python:
# README shows those files verbatim), the find_package and pkg-config lines (find_package), the packaging command
# (core_alone), fcl_rs_selfcheck on a robot (selfcheck_panda) and scripts/test.sh itself (CI: .ci/run).
# Usage: tests/readme_commands.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
root="$1" build="$2"
work="$build/readme_commands"
rm -rf "$work" && mkdir -p "$work" && cd "$work"
assimp=/usr/share/assimp/models
cached() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
data="$(cached FCL_RS_SHARED_DATA_DIR)" python="$(cached Python3_EXECUTABLE)"

# shows 'README FORM' COMMAND...: fails unless README.md shows the form, then runs the command.
shows() {
  local form="$1"
  shift
  grep -qF -- "$form" "$root/README.md" || { echo "README.md no longer shows: $form"; exit 1; }
  echo "== README: $form"
  echo "   runs: $*"
  "$@"
}
# Whether ../shared/data/$1 is there; if not, a failure under CI=true (as the GoogleTest cases), else a skip.
have_data() {
  [ -e "$data/$1" ] && return 0
  [[ "${CI:-}" =~ ^(|0|false)$ ]] || { echo "shared data $data/$1 is missing; CI=true requires it"; exit 1; }
  echo "== README command left out: $data/$1 not found (shared data; CI=true fails here)"
  return 1
}

help="$(shows "bash scripts/compare.sh --help" bash "$root/scripts/compare.sh" --help)"
echo "$help" | head -n 3
grep -q "Usage: scripts/compare.sh" <<< "$help" && grep -q -- "--queries" <<< "$help"
if ! out="$(shows "bash scripts/compare.sh --with-coal=PREFIX" bash "$root/scripts/compare.sh" --with-coal="$work/no-coal" 2>&1)"; then
  grep -q "no Coal in $work/no-coal" <<< "$out" || { echo "$out"; exit 1; }
else
  echo "compare.sh --with-coal accepted a prefix without Coal"; exit 1
fi
# compare.sh builds and runs SOURCE_DIR/build's fcl_rs_compare: run here only when that is BUILD_DIR. Its default
# run (seven pairs, a minute or more) is too long for CI; one small mesh runs the same script and program.
if [ "$(cd "$build" && pwd -P)" = "$(cd "$root" && pwd -P)/build" ]; then
  shows "scripts/compare.sh MESH_FILE..." bash "$root/scripts/compare.sh" --queries 2 "$assimp/OBJ/box.obj" |
    grep "box.obj x box.obj"
fi
shows "build/benchmarks/fcl_rs_bench_distance --refits 1" "$build/benchmarks/fcl_rs_bench_distance" --refits 1 --queries 2 --quick > /dev/null
shows "build/benchmarks/fcl_rs_tradeoff --queries 50 --max-triangles 20000 --csv docs/plots/tradeoff.csv --plot" \
  "$build/benchmarks/fcl_rs_tradeoff" --quick --queries 2 --csv tradeoff.csv --plot tradeoff.svg "$assimp/OBJ/spider.obj" > /dev/null
test -s tradeoff.csv && test -s tradeoff.svg
shows "build/tools/fcl_rs_export --paper figures" "$build/tools/fcl_rs_export" --paper figures
ls figures/*.png > /dev/null
shows "fcl_rs_export MESH|--shape NAME --bv RS,OBB,KDOP18 --level 3 --out volumes.glb --png volumes.png" \
  "$build/tools/fcl_rs_export" --shape torus --bv RS,OBB,KDOP18 --level 3 --out volumes.glb --png volumes.png
test -s volumes.glb && test -s volumes.png
if have_data models/dragon.obj; then
  shows "build/experiments/nbody/fcl_rs_scene experiments/nbody/scenes/mixed20.json --plot mixed20.svg" \
    "$build/experiments/nbody/fcl_rs_scene" "$root/experiments/nbody/scenes/mixed20.json" --plot mixed20.svg --frames 3
  test -s mixed20.svg
fi
if have_data robots/panda/panda.urdf; then
  shows "python/examples/label_configurations.py ROBOT.urdf --srdf ROBOT.srdf -n 100000" \
    env PYTHONPATH="$build/python" "$python" "$root/python/examples/label_configurations.py" \
    "$data/robots/panda/panda.urdf" --srdf "$data/robots/panda/panda.srdf" -n 2000 --check
fi
shows "bash scripts/install_python.sh" env FCL_RS_BUILD_DIR="$build" DESTDIR="$work/stage" \
  bash "$root/scripts/install_python.sh"
echo "every README command above ran"
