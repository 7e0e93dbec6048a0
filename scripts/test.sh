#!/usr/bin/env bash
# Builds and runs every test, then fuzzes for a bounded time. Sets everything up first. CI runs exactly this on
# 2 cores (its time and the budget of 35 minutes: docs/robustness.md); each stage prints its start and minutes elapsed.
# Usage: scripts/test.sh [--quick | --sanitizers]
#   (none)        what CI runs: --quick, then each libFuzzer target under AddressSanitizer +
#                 UndefinedBehaviorSanitizer (build-asan, clang -O1) for FCL_RS_FUZZ_SECONDS s (default: 120 s
#                 divided by their number) from seed FCL_RS_FUZZ_SEED (default 1), two targets at a time
#   --quick       the Release build of everything (build/) and every CTest test there: the GoogleTest cases, tools,
#                 examples, benchmarks, Python and packaging
#   --sanitizers  every GoogleTest case compiled and run with assertions and sanitizers on (about twice CI's time):
#     build       Release: everything but the GoogleTest executables, and the CTest tests of the rest
#     build-asan  every GoogleTest case under AddressSanitizer + UndefinedBehaviorSanitizer, then the fuzzing
#     build-tsan  tests/test_concurrency and tests/test_batch under ThreadSanitizer (the batch on std::threads)
#   Details and how to run one stage alone: docs/robustness.md.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mode=ci
for arg in "$@"; do
  case "$arg" in
    --quick) mode=quick ;;
    --sanitizers) mode=sanitizers ;;
    -h | --help) sed -n '2,14p' "${BASH_SOURCE[0]}" | cut -c3-; exit 0 ;;
    *) echo "scripts/test.sh: unknown option '$arg' (see --help)" >&2; exit 2 ;;
  esac
done

# Each stage's start and the minutes since the run began, so a CI log shows where the time went.
stage() { echo "== fcl_rs: $* ($(date +%T), $((SECONDS / 60)) min $((SECONDS % 60)) s in)"; }

# The sanitizer run compiles the GoogleTest cases once, in build-asan below, where they run with assertions,
# AddressSanitizer and UndefinedBehaviorSanitizer on; its Release tree builds and tests what is shipped.
if [ "$mode" = sanitizers ]; then
  stage "setup and Release build of all but the GoogleTest executables (build)"
  bash "$root/scripts/setup.sh" --no-unit-tests "$root/build"
  stage "Release: every CTest test of tools, examples, benchmarks, Python and packaging (build)"
else
  stage "setup and Release build (build)"
  bash "$root/scripts/setup.sh" "$root/build"
  stage "Release: every CTest test (build)"
fi
(cd "$root/build" && ctest --output-on-failure -j2)
# ctest's summary names the skipped tests; here each with its reason (README.md, 'Data': CI=true fails them).
awk '/^[0-9]+\/[0-9]+ Testing: / { name = $3 }
     /shared data .* is missing/ && !/^Command: / && name != done { sub(/^.*shared data/, "shared data"); print "   skipped " name ": " $0; done = name }' \
  "$root/build/Testing/Temporary/LastTest.log"
[ "$mode" = quick ] && { stage "quick stages passed"; exit 0; }

# Test executables (test_*) of a configured build directory; only these are built there.
test_targets() { cmake --build "$1" --target help | sed -nE 's/^(\.\.\. )?(test_[A-Za-z0-9_]+)(:.*)?$/\2/p' | sort -u; }

# FCL, libccd and assimp come from Debian uninstrumented: the sanitizers check fcl_rs and the FCL templates it
# instantiates on its own types (FCL's narrow phase for float, compiled into fcl_rs, stays uninstrumented too:
# CMakeLists.txt). The fuzz targets share build-asan's instrumented library (a second sanitized build of the
# library would cost CI ~15 min); FCL_RS_FUZZ adds libFuzzer's coverage counters to the core library's sources only.
# alloc_dealloc_mismatch=0: FCL 0.7's getMotionBase (continuous collision, a header template) creates motions with
# the global operator new and its shared_ptr deletes them through Eigen's class operator delete (free). Harmless
# with glibc; fcl_rs keeps calling it so that its motions round exactly as fcl::continuousCollide's.
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:check_initialization_order=1:alloc_dealloc_mismatch=0"
# assimp leaks while failing on some corrupt files (tests feed it such files on purpose); leaks of ours still fail.
export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"
# Ninja for a new build directory (why: scripts/setup.sh); an existing one keeps the generator it was made with.
generator() { [ -f "$1/CMakeCache.txt" ] || echo "-GNinja"; }
sanitized=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1")

asan="$root/build-asan"
fuzz_targets=(fuzz_mesh_load fuzz_rs fuzz_triangle_intersection fuzz_mesh_shape fuzz_api)
if [ "$mode" = ci ]; then
  stage "AddressSanitizer + UndefinedBehaviorSanitizer: the libFuzzer targets (build-asan)"
else
  stage "AddressSanitizer + UndefinedBehaviorSanitizer: every test (build-asan)"
fi
cmake -S "$root" -B "$asan" $(generator "$asan") -DCMAKE_CXX_COMPILER=clang++ "${sanitized[@]}" -DFCL_RS_FUZZ=ON \
  -DFCL_RS_SANITIZE=address,undefined > /dev/null
tests=()
[ "$mode" = sanitizers ] && mapfile -t tests < <(test_targets "$asan")
cmake --build "$asan" -j2 --target "${tests[@]}" "${fuzz_targets[@]}"
if [ "$mode" = sanitizers ]; then
  # The GoogleTest cases (label unit); the other CTest tests run the examples and tools, not built here.
  (cd "$asan" && ctest --output-on-failure -j2 -L unit)

  stage "ThreadSanitizer: test_concurrency and test_batch (build-tsan)"
  # The batch runs on std::threads here (FCL_RS_BATCH_STD_THREADS): Debian's oneTBB is not instrumented, so TSan
  # would report races inside it (docs/batch.md). The Concurrency cases of both tests, and test_batch's Batch
  # cases (errors thrown on worker threads). clang, as for ASan: it compiles this tree in about two thirds of g++'s
  # CPU time (docs/robustness.md, 'In CI').
  tsan="$root/build-tsan"
  cmake -S "$root" -B "$tsan" $(generator "$tsan") -DCMAKE_CXX_COMPILER=clang++ "${sanitized[@]}" -DFCL_RS_SANITIZE=thread \
    -DFCL_RS_BATCH_STD_THREADS=ON > /dev/null
  cmake --build "$tsan" -j2 --target test_concurrency test_batch
  (cd "$tsan" && ctest --output-on-failure -j2 -L unit -R '^(Concurrency|Batch)\.')
fi

# Each target fuzzes for 120 s divided by their number (five: 24 s each), two at a time: libFuzzer runs one
# process per target and CI has two cores, so the stage takes three rounds of 24 s.
seconds="${FCL_RS_FUZZ_SECONDS:-$((120 / ${#fuzz_targets[@]}))}"
seed="${FCL_RS_FUZZ_SEED:-1}"
stage "libFuzzer: ${fuzz_targets[*]}, ${seconds} s each, two at a time, seed ${seed} (build-asan/fuzz)"
# fuzz_target NAME: fuzzes NAME for the stage's seconds; prints one summary line, or the failure and exits 1.
fuzz_target() {
  local target="$1" corpus log status frame input starved leaks deadline runs executions in_assimp i ext f
  corpus="$asan/fuzz/corpus/$target"
  mkdir -p "$corpus"
  [ -d "$root/fuzz/corpus/$target" ] && cp -n "$root/fuzz/corpus/$target"/* "$corpus/" 2> /dev/null || true
  if [ "$target" = fuzz_mesh_load ]; then
    # More seeds: Debian's assimp test models under 3 KB, each behind its format byte (kFormats' order).
    i=0
    for ext in stl obj ply off dae 3ds gltf glb x ac; do
      while IFS= read -r f; do
        { printf "\\x$(printf %02x "$i")"; cat "$f"; } > "$corpus/assimp_$(basename "$f")"
      done < <(find /usr/share/assimp/models -iname "*.$ext" -size -3k 2> /dev/null)
      i=$((i + 1))
    done
  fi
  # Per-input leak checks cut fuzz_mesh_load from ~100 to ~1 input/s: assimp's leaks on corrupt input (suppressed
  # above) still trigger a full scan after every input. fuzz_rs keeps them.
  leaks=1
  [ "$target" = fuzz_mesh_load ] && leaks=0
  # Runs until the time is used. A failure whose first stack frame in either assimp or fcl_rs is assimp's is one
  # of Debian assimp's own bugs: its input is kept in build-asan/fuzz/assimp/ and fuzzing resumes with the next
  # seed. Any other failure (fcl_rs code, a broken loader contract) stops CI; its input is in build-asan/fuzz/.
  mkdir -p "$asan/fuzz/assimp"
  deadline=$((SECONDS + seconds)) runs=0 executions=0 in_assimp=0
  while [ "$SECONDS" -lt "$deadline" ]; do
    log="$asan/fuzz/$target.$runs.log"
    status=0
    (cd "$asan/fuzz" && "./$target" -max_total_time=$((deadline - SECONDS)) -seed=$((seed + runs)) -max_len=4096 \
      -timeout=30 -detect_leaks="$leaks" -rss_limit_mb=2048 -print_final_stats=1 "$corpus" > "$log" 2>&1) || status=$?
    runs=$((runs + 1))
    executions=$((executions + $(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)))
    [ "$status" = 0 ] && break
    frame=$(grep -m1 -E '^ *#[0-9]+ .*(libassimp\.so|'"$root"'/(src|fcl_rs|fuzz)/)' "$log" || true)
    input=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n 1)
    # Out-of-memory (RSS limit) and timeout reports carry no culprit stack; in fuzz_mesh_load, where assimp
    # does all the parsing, one without any fcl_rs frame is counted as assimp's too.
    starved=$(grep -m1 -oE 'SUMMARY: libFuzzer: (out-of-memory|timeout)' "$log" || true)
    if [[ -n "$input" && ( "$frame" == *libassimp.so* || ( -z "$frame" && -n "$starved" && "$target" == fuzz_mesh_load ) ) ]]; then
      in_assimp=$((in_assimp + 1))
      mv "$asan/fuzz/$input" "$asan/fuzz/assimp/"
      echo "   $target: assimp failed on $asan/fuzz/assimp/$(basename "$input") ($(grep -m1 -E 'ERROR|SUMMARY|ai_assert' "$log"))"
    else
      echo "FAILED $target (full log: $log)"
      tail -n 60 "$log"
      exit 1
    fi
  done
  echo "   $target: $executions executions in $runs runs, $in_assimp inputs assimp failed on, corpus $(ls "$corpus" | wc -l) inputs"
}
for ((first = 0; first < ${#fuzz_targets[@]}; first += 2)); do
  pids=() names=()
  for target in "${fuzz_targets[@]:first:2}"; do
    fuzz_target "$target" > "$asan/fuzz/$target.summary" 2>&1 &
    pids+=($!) names+=("$target")
  done
  failed=0
  for i in "${!pids[@]}"; do
    wait "${pids[$i]}" || failed=1
    cat "$asan/fuzz/${names[$i]}.summary"
  done
  [ "$failed" = 0 ] || exit 1
done
stage "all stages passed"
