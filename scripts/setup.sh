#!/usr/bin/env bash
# Installs the Debian packages a job needs (only those missing; sudo when not root), then configures and builds
# what it runs (Release, -j2, Ninja), printing each step on stdout.
# Usage: scripts/setup.sh [--for JOB] [--packages-only] [--no-unit-tests] [BUILD_DIR] [-DOPTION=VALUE...]
#   --for all      (default) every package; BUILD_DIR (default build) configured with every part on, all built
#   --no-unit-tests  with --for all: every part but the GoogleTest executables (scripts/test.sh builds those in its
#                  sanitized tree)
#   --for compare  the core's packages; a new BUILD_DIR gets the core for double only and fcl_rs_compare (an existing
#                  one keeps its options); builds the target fcl_rs_compare alone (scripts/compare.sh)
#   --for python   the module's packages; BUILD_DIR gets the robot, batch and Python parts on (the rest as they
#                  are, or off in a new one); builds the target fcl_rs_python alone (scripts/install_python.sh)
#   --packages-only  install the packages, configure and build nothing
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
job=all packages_only=0 unit_tests=ON build="$root/build" cmake_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --for) job="$2"; shift ;;
    --for=*) job="${1#--for=}" ;;
    --packages-only) packages_only=1 ;;
    --no-unit-tests) unit_tests=OFF ;;
    -D*) cmake_args+=("$1") ;;
    *) build="$1" ;;
  esac
  shift
done

# What the core and fcl_rs_compare need; the Python module adds its parts' packages; the tests, tools and other
# benchmarks the rest. zlib1g-dev: Debian's assimp CMake targets link libz.so, which libassimp-dev does not pull in.
compare_packages=(cmake g++ ninja-build libfcl-dev libccd-dev libeigen3-dev libassimp-dev zlib1g-dev
                  assimp-testmodels libcli11-dev)
python_packages=("${compare_packages[@]}" liburdfdom-dev libtinyxml2-dev libtbb-dev pybind11-dev python3-dev
                 python3-numpy)
all_packages=("${python_packages[@]}" make libgtest-dev libbenchmark-dev libqhull-dev nlohmann-json3-dev
              gnuplot-nox clang libclang-rt-14-dev pkg-config python3-pytest python3-dask python3-distributed
              libcgal-dev f3d xvfb imagemagick)
# Parts a new build directory leaves off for compare and python (scripts/compare.sh, scripts/install_python.sh).
parts_off=(-DBUILD_TESTING=OFF -DFCL_RS_BUILD_TOOLS=OFF -DFCL_RS_BUILD_EXAMPLES=OFF
           -DFCL_RS_BUILD_EXPERIMENTS=OFF -DFCL_RS_BUILD_HULL=OFF)
case "$job" in
  compare)
    packages=("${compare_packages[@]}") target=(--target fcl_rs_compare)
    options=("${parts_off[@]}" -DFCL_RS_BUILD_ROBOT=OFF -DFCL_RS_BUILD_BATCH=OFF -DFCL_RS_BUILD_BENCHMARKS=ON
             -DFCL_RS_FLOAT=OFF) ;;
  python)
    packages=("${python_packages[@]}") target=(--target fcl_rs_python)
    options=("${parts_off[@]}" -DFCL_RS_BUILD_BENCHMARKS=OFF) ;;
  all)
    packages=("${all_packages[@]}") target=() options=() ;;
  *) echo "scripts/setup.sh: unknown job '$job' (all, compare or python)" >&2; exit 2 ;;
esac

step() { echo "== fcl_rs setup: $* ($((SECONDS / 60)) min $((SECONDS % 60)) s in)"; }
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  step "installing ${#missing[@]} Debian packages and what they depend on: ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi
[ "$packages_only" = 1 ] && exit 0

# Ninja: the test and tool sources compile while the library is still compiling (Makefiles wait for the
# library's link first), so -j2 keeps both cores busy. An existing build directory keeps its generator and, for
# compare, its options; all turns every part on, python the parts the module needs.
generator=()
if [ -f "$build/CMakeCache.txt" ]; then
  case "$job" in
    compare) options=() ;;
    python) options=(-DFCL_RS_BUILD_ROBOT=ON -DFCL_RS_BUILD_BATCH=ON) ;;
  esac
else
  generator=(-G Ninja)
fi
[ "$job" = all ] && options=(-DFCL_RS_FLOAT=ON -DBUILD_TESTING=ON -DFCL_RS_BUILD_HULL=ON -DFCL_RS_BUILD_EXPORT=ON
  -DFCL_RS_BUILD_ROBOT=ON -DFCL_RS_BUILD_BATCH=ON -DFCL_RS_BUILD_TOOLS=ON -DFCL_RS_BUILD_EXAMPLES=ON
  -DFCL_RS_BUILD_BENCHMARKS=ON -DFCL_RS_BUILD_EXPERIMENTS=ON -DFCL_RS_BUILD_PYTHON=ON
  -DFCL_RS_BUILD_UNIT_TESTS=$unit_tests)
[ "$job" = python ] && options+=(-DFCL_RS_BUILD_PYTHON=ON)
# An existing build directory already holding every value asked for is not configured again (the build step
# re-runs CMake itself when a CMakeLists.txt changed).
configured=0
if [ -f "$build/CMakeCache.txt" ]; then
  configured=1
  for option in -DCMAKE_BUILD_TYPE=Release "${options[@]}" "${cmake_args[@]}"; do
    name="${option#-D}" && name="${name%%=*}" && name="${name%%:*}"
    [ "$(sed -n "s/^$name:[A-Z]*=//p" "$build/CMakeCache.txt")" = "${option#*=}" ] || configured=0
  done
fi
if [ "$configured" = 0 ]; then
  step "configuring $build (Release${options[*]:+, ${options[*]}}${cmake_args[*]:+ ${cmake_args[*]}})"
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${options[@]}" "${cmake_args[@]}" >/dev/null
fi
step "building ${target[1]:-everything} in $build (-j2)"
cmake --build "$build" -j2 "${target[@]}"
step "built ${target[1]:-everything}"
