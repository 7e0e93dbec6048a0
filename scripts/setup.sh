#!/usr/bin/env bash
# Installs the Debian packages fcl_rs needs (only those missing), then configures and builds (Release, -j2, Ninja).
# Usage: scripts/setup.sh [BUILD_DIR]   (default: build)
#        scripts/setup.sh --packages-only   (install the packages, configure and build nothing)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
packages_only=0
[ "${1:-}" = --packages-only ] && packages_only=1 && shift
build="${1:-$root/build}"

packages=(cmake g++ make ninja-build libfcl-dev libccd-dev libeigen3-dev libassimp-dev assimp-testmodels
          libgtest-dev libbenchmark-dev libqhull-dev liburdfdom-dev libtinyxml2-dev nlohmann-json3-dev
          gnuplot-nox clang libclang-rt-14-dev pkg-config libcli11-dev libtbb-dev pybind11-dev python3-dev
          python3-numpy python3-pytest python3-dask python3-distributed libcgal-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "fcl_rs: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi
[ "$packages_only" = 1 ] && exit 0

# Ninja: the test and tool sources compile while the library is still compiling (Makefiles wait for the
# library's link first), so -j2 keeps both cores busy. An existing build directory keeps its generator.
generator=()
[ -f "$build/CMakeCache.txt" ] || generator=(-G Ninja)
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2
