#!/usr/bin/env bash
# The test suite under AddressSanitizer (leaks included) and UndefinedBehaviorSanitizer, in its own
# build folder (build-asan/, clang), then each libFuzzer target of fuzz/ for FUZZ_SECONDS seconds
# (default 20) from a seed corpus made from the sample scene. Any sanitizer report or fuzzer crash
# fails the run. docs/robustness.md says how to fuzz for longer.
# --suite-only: the sanitized suite without fuzzing; --help: this text.
set -euo pipefail
SUITE_ONLY=0
case "${1:-}" in
  "") ;;
  --suite-only) SUITE_ONLY=1 ;;
  -h | --help) sed -n '2,7s/^# \{0,1\}//p' "$0"; exit 0 ;;
  *) echo "usage: $0 [--suite-only | --help]" >&2; exit 2 ;;
esac
cd "$(dirname "$0")/../.."
ROOT=$PWD
BUILD=${BUILD:-build-asan}
FUZZ_SECONDS=${FUZZ_SECONDS:-20}
# A fixed seed by default: a CI run replays the same mutations (FUZZ_SEED=0: a random one each run).
FUZZ_SEED=${FUZZ_SEED:-1}
FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -gline-tables-only"

# Without the Python module: an AddressSanitizer runtime does not load into a Python interpreter.
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="$FLAGS" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DVKNERF_FUZZ=ON -DVKNERF_PYTHON=OFF
cmake --build "$BUILD" -j2

# halt_on_error: the first report fails the test. Libraries stay loaded until exit
# (tools/dev/keep_libraries_loaded.c says why), so a leak report always names its allocation stack; the
# leak suppressions cover third-party code only (tools/dev/lsan.supp says why for each entry).
cc -shared -fPIC -O2 tools/dev/keep_libraries_loaded.c -o "$BUILD/keep_libraries_loaded.so"
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export LSAN_OPTIONS=suppressions=$ROOT/tools/dev/lsan.supp:print_suppressions=0
export LD_PRELOAD=$ROOT/$BUILD/keep_libraries_loaded.so
# The install.consumer test configures a project of its own against the sanitized libvknerf.a:
# CMake takes its initial flags from these.
export CXXFLAGS="$FLAGS" LDFLAGS="-fsanitize=address,undefined"
# The amd-rdna2 profile's host paths (staging copies, the fallbacks' kernels) are a subset of the
# minimum profile's, which also flushes and invalidates: sanitized once is enough.
ctest --test-dir "$BUILD" -j2 --output-on-failure -E '^amd-rdna2\.'

if [ "$SUITE_ONLY" = 1 ]; then exit 0; fi

# Fuzzing: seeds from the sample scene, new inputs kept in $BUILD/fuzz/corpus, crashes in $BUILD/fuzz/crashes.
FUZZ=$BUILD/fuzz
rm -rf "$FUZZ/seeds"
mkdir -p "$FUZZ/crashes"
"$BUILD/fuzz/fuzz_make_seeds" assets/tabletop "$FUZZ/seeds"
for target in transforms_json:transforms colmap_text:colmap colmap_binary:colmap_binary llff:llff checkpoint:checkpoint image:image; do
  name=${target%%:*}
  seeds=$FUZZ/seeds/${target##*:}
  mkdir -p "$FUZZ/corpus/$name"
  log=$FUZZ/$name.log
  # The targets write their inputs as files under $TMPDIR; libFuzzer's exit skips their cleanup.
  rm -rf "$FUZZ/tmp" && mkdir -p "$FUZZ/tmp"
  if ! TMPDIR=$FUZZ/tmp "$BUILD/fuzz/fuzz_$name" -max_total_time="$FUZZ_SECONDS" -seed="$FUZZ_SEED" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$FUZZ/crashes/$name-" "$FUZZ/corpus/$name" "$seeds" >"$log" 2>&1; then
    tail -n 60 "$log"
    echo "fuzz_$name: FAILED (input saved under $FUZZ/crashes/)"
    exit 1
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  echo "fuzz_$name: $runs executions in $FUZZ_SECONDS s, no crash"
done
rm -rf "$FUZZ/tmp"
