#!/usr/bin/env bash
# ctest (compare_job): the main job's own build, as scripts/compare.sh makes it in a new build directory
# (scripts/setup.sh --for compare: the core for double only and fcl_rs_compare, nothing else), configured in
# BUILD_DIR/compare_job, built, and run on one small mesh. The main build tree holds float as well, so without this
# test nothing would notice the double-only core or its benchmark failing to compile or link.
# Usage: tests/compare_job.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
root="$1" work="$2/compare_job"
rm -rf "$work"
bash "$root/scripts/setup.sh" --for compare "$work"
grep -qx "#define FCL_RS_FLOAT 0" "$work/include/fcl_rs/version.h" || { echo "the compare job's core holds float"; exit 1; }
if grep -E "^(test_[a-z_]+|fcl_rs_(robot|hull|batch|export|python|tradeoff)): " <(cmake --build "$work" --target help); then
  echo "the compare job's build has more than the core and fcl_rs_compare (above)"; exit 1
fi
if grep -q "src/fcl_float_" "$work/build.ninja"; then echo "the compare job compiles FCL's float narrow phase"; exit 1; fi
"$work/benchmarks/fcl_rs_compare" --queries 2 /usr/share/assimp/models/OBJ/box.obj | grep "box.obj x box.obj"
rm -rf "$work"
