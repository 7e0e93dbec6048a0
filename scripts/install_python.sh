#!/usr/bin/env bash
# Installs the Python module fcl_rs for Debian's python3 (/usr/bin/python3): installs the Debian packages it
# needs when they are missing (scripts/setup.sh --packages-only; sudo when not root), builds only the module in
# build-python/ (Release, -j2) and installs it with its type stub into the interpreter's site-packages
# (/usr/local/lib/python3.11/dist-packages on Debian 12). Nothing else is downloaded.
# Usage: scripts/install_python.sh [CMAKE_OPTION...]   e.g. -DFCL_RS_PYTHON_INSTALL_DIR=DIR
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case "${1:-}" in -h | --help) sed -n '2,6p' "${BASH_SOURCE[0]}" | cut -c3-; exit 0 ;; esac
bash "$root/scripts/setup.sh" --packages-only
build="$root/build-python"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DFCL_RS_BUILD_PYTHON=ON "$@" >/dev/null
cmake --build "$build" -j2 --target fcl_rs_python
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
$sudo cmake --install "$build" --component python
cached() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
python="$(cached Python3_EXECUTABLE)"
dir="$(cached FCL_RS_PYTHON_INSTALL_DIR)"
[ "${dir#/}" = "$dir" ] && dir="$(cached CMAKE_INSTALL_PREFIX)/$dir"
if ! (cd / && "$python" -c 'import fcl_rs; print("fcl_rs", fcl_rs.__version__, "installed at", fcl_rs.__file__)'); then
  echo "fcl_rs installed into $dir, which $python does not search: add it to PYTHONPATH" >&2
  (cd / && PYTHONPATH="$dir" "$python" -c 'import fcl_rs; print("fcl_rs", fcl_rs.__version__, "imports from", fcl_rs.__file__)')
fi
