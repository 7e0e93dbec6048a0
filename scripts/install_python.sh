#!/usr/bin/env bash
# Installs the Python module fcl_rs from build/ (or FCL_RS_BUILD_DIR): installs the Debian packages it needs when
# missing (sudo when not root), turns the module on in that build directory and builds the target fcl_rs_python
# alone (nothing when scripts/test.sh or an earlier run built it; scripts/setup.sh --for python), then installs it
# with its type stub into the interpreter's site-packages (/usr/local/lib/python3.11/dist-packages for Debian 12's
# /usr/bin/python3, the default interpreter). Fails unless that interpreter then imports the installed module.
# Honours DESTDIR (staged install, imported from there). Nothing else is downloaded.
# Usage: scripts/install_python.sh [CMAKE_OPTION...]
#   -DPython3_EXECUTABLE=PYTHON   build for and install into another interpreter (its pybind11 and numpy needed)
#   -DFCL_RS_PYTHON_INSTALL_DIR=DIR   install there instead (DIR must then be on that interpreter's PYTHONPATH)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
case "${1:-}" in -h | --help) sed -n '2,10p' "${BASH_SOURCE[0]}" | cut -c3-; exit 0 ;; esac
build="${FCL_RS_BUILD_DIR:-$root/build}"
bash "$root/scripts/setup.sh" --for python "$build" "$@"
cached() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
python="$(cached Python3_EXECUTABLE)"
dir="$(cached FCL_RS_PYTHON_INSTALL_DIR)"
[ "${dir#/}" = "$dir" ] && dir="$(cached CMAKE_INSTALL_PREFIX)/$dir"
echo "== fcl_rs python: installing the module built for $python ($("$python" --version 2>&1)) into ${DESTDIR:-}$dir"
sudo=""
target="${DESTDIR:-}$dir"
while [ ! -e "$target" ]; do target="$(dirname "$target")"; done
[ "$(id -u)" -ne 0 ] && [ ! -w "$target" ] && sudo="sudo"
$sudo env ${DESTDIR:+DESTDIR="$DESTDIR"} cmake --install "$build" --component python
path=()
[ -n "${DESTDIR:-}" ] && path=(env PYTHONPATH="$DESTDIR$dir${PYTHONPATH:+:$PYTHONPATH}")
if ! (cd / && "${path[@]}" "$python" -c 'import fcl_rs; print("fcl_rs", fcl_rs.__version__, "imports from", fcl_rs.__file__)'); then
  echo "install_python.sh: $python cannot import fcl_rs from $dir: add that folder to PYTHONPATH" >&2
  exit 1
fi
on_path="$(command -v python3 || true)"
if [ -n "$on_path" ] && [ "$(readlink -f "$on_path")" != "$(readlink -f "$python")" ]; then
  echo "note: python3 on PATH is $on_path, not $python: run $python, or rerun with -DPython3_EXECUTABLE=$on_path"
fi
