#!/usr/bin/env bash
# The CPU-only tests under sanitizers (issue 23), as CI runs them after the README's test command:
#   SANITIZER=address (default): ASan + UBSan, into build-asan: the unit, motion and live-feed
#     tests, and the command line's tests that need no GPU (argument handling, bad input, info);
#   SANITIZER=thread: TSan, into build-tsan: the tests of what runs on several threads (the
#     worker pool, the terrain's pager and concurrent raster reads, the FMV prefetcher, the
#     vector pager, point stores, live feeds).
# Any sanitizer report fails the run. Run tools/build.sh first: some tests read assets/generated.
#   usage: tools/test-sanitized.sh [GTEST_FILTER]   env: SANITIZER=address|thread
set -euo pipefail
cd "$(dirname "$0")/.."
san="${SANITIZER:-address}"
case "$san" in
    address) dir=build-asan ;;
    thread) dir=build-tsan ;;
    *) echo "test-sanitized.sh: SANITIZER is address or thread, not '$san'" >&2; exit 2 ;;
esac
[ -d assets/generated ] || { echo "test-sanitized.sh: assets/generated is missing: run tools/build.sh first" >&2; exit 2; }
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Sanitize -DORBIS_SANITIZE="$san" -DORBIS_BUILD_TESTS=ON >/dev/null
if [ "$san" = address ]; then
    targets=(orbis_unit_tests orbis_livefeed_tests orbis_motion_tests orbis orbis_cli_tests)
else   # only the sources of the threaded tests (tests/unit/CMakeLists.txt)
    targets=(orbis_threaded_tests orbis_livefeed_tests)
fi
cmake --build "$dir" --target "${targets[@]}"

supp="$PWD/tests/sanitizers"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:check_initialization_order=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$supp/tsan.supp"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"

filter="${1:-}"
status=0
run() {   # run BINARY [GTEST_FILTER]
    local bin="$dir/bin/$1" f="${2:-*}"
    [ -n "$filter" ] && f="$filter"
    echo "== $1 ($san) --gtest_filter=$f"
    local start=$SECONDS
    if ! "$bin" --gtest_filter="$f" --gtest_brief=1 >"$dir/$1.log" 2>&1; then
        status=1
        grep -E "^\[  FAILED|ERROR: |WARNING: ThreadSanitizer|runtime error:|SUMMARY: " "$dir/$1.log" | head -20
    fi
    echo "   $(grep -E '^\[  PASSED|^\[  FAILED  \] [0-9]+ test' "$dir/$1.log" | tr '\n' ' ')in $((SECONDS - start)) s"
}
if [ "$san" = address ]; then
    run orbis_unit_tests
    run orbis_motion_tests
    run orbis_livefeed_tests
    run orbis_cli_tests 'Cli.*'
else
    run orbis_threaded_tests 'ThreadPool*:CancelToken*:TerrainTilesRepaint*:RasterSource.Concurrent*:RasterSource.Cancelled*:FeatureTiles*:FmvVideo*:FramePrefetcher*:PointStore*:NodeResidency*:LazFile*:Copc*'
    run orbis_livefeed_tests
fi
[ "$status" = 0 ] && echo "test-sanitized.sh ($san): clean" || echo "test-sanitized.sh ($san): see $dir/*.log" >&2
exit "$status"
