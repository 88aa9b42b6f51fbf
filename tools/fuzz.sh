#!/usr/bin/env bash
# Fuzzes Orbis's parsers of outside input (issue 23): builds the libFuzzer targets of tests/fuzz
# with clang, ASan and UBSan into build-fuzz (-DORBIS_FUZZ=ON), seeds each target's corpus and
# runs each in turn. A crash, a leak, undefined behaviour, a time-out or an allocation past the
# limit stops that target; its input is kept in build-fuzz/crashes/TARGET/ and the script exits 1.
#   usage: tools/fuzz.sh [TARGET...]   (default: all; targets: see tests/fuzz/CMakeLists.txt)
#   env:   SECONDS_EACH=60   wall time per target (-max_total_time)
#          RUNS=N            executions per target instead (-runs; e.g. 1000000 for the issue's goal);
#                            with SECONDS_EACH too, whichever comes first
#          REGRESS=1         only run each target over its corpus and the kept crashes, no
#                            mutation (a quick check, as CI does)
#          JOBS=1            parallel fuzzing processes per target (-fork)
# Corpora grow in build-fuzz/corpus/TARGET (ignored by git). Seeds: tests/fuzz/seeds/TARGET,
# the binary ones written by tools/gen/fuzz-seeds.py, a LAS from orbis-make-las, and the real
# files of ../shared/data when it is there.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$here/build-fuzz"
seconds="${SECONDS_EACH:-60}" runs="${RUNS:-}" regress="${REGRESS:-0}" jobs="${JOBS:-1}"
all=(klv las scene camera-path input-script trajectory-csv gpx pose-csv livefeed gltf mesh-checks netcdf vector pg-notify ogc-capabilities wms-time wps)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ is missing (Debian: apt install clang)" >&2; exit 1; }

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}"
mkdir -p "$XDG_RUNTIME_DIR"

CC=clang CXX=clang++ cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Sanitize -DORBIS_FUZZ=ON \
    -DORBIS_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" --target "${targets[@]/#/fuzz-}" orbis-make-las

shared="$here/../shared/data"
seeds="$build/seeds"
rm -rf "$seeds"
python3 "$here/tools/gen/fuzz-seeds.py" "$seeds"
mkdir -p "$seeds/las"
"$build/bin/orbis-make-las" --points 40 --out "$seeds/las/small.las" >/dev/null
# seed TARGET FILE...: what ../shared/data offers each target (skipped when absent).
seed() {
    local t="$1"; shift
    mkdir -p "$seeds/$t"
    for f in "$@"; do [ -f "$f" ] && cp "$f" "$seeds/$t/"; done
    return 0
}
seed klv "$shared"/klv/*.bin
seed las "$shared"/lidar/*.las "$shared"/lidar/simple.laz "$shared"/lidar/simple-laszip-compressor-version-1.2r0.laz "$shared"/lidar/1.2-with-color.copc.laz
seed gpx "$shared"/trajectory/*.gpx "$shared"/bad/*.gpx
seed gltf "$shared"/models/BoxTextured.glb "$shared"/models/BoxTextured_embedded.gltf "$shared"/bad/*.glb
seed scene "$shared"/bad/scene-*.json
seed camera-path "$shared"/bad/path-*.json

dict() {   # the dictionary of a target
    case "$1" in
        scene|camera-path|input-script|gltf) echo "$here/tests/fuzz/dict/json.dict" ;;
        gpx|wps|ogc-capabilities|mesh-checks) echo "$here/tests/fuzz/dict/xml.dict" ;;
        vector) echo "$here/tests/fuzz/dict/vector.dict" ;;
        livefeed|trajectory-csv|pose-csv) echo "$here/tests/fuzz/dict/text.dict" ;;
    esac
}

status=0
for t in "${targets[@]}"; do
    corpus="$build/corpus/$t" crashes="$build/crashes/$t"
    mkdir -p "$corpus" "$crashes"
    inputs=("$corpus")
    [ -d "$here/tests/fuzz/seeds/$t" ] && inputs+=("$here/tests/fuzz/seeds/$t")
    [ -d "$seeds/$t" ] && inputs+=("$seeds/$t")
    args=(-rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=20 -max_len=65536 -print_final_stats=1
          -artifact_prefix="$crashes/")
    d=$(dict "$t"); [ -n "$d" ] && args+=(-dict="$d")
    if [ "$regress" = 1 ]; then
        # Every input once: the corpus, the seeds and the crashes kept from earlier runs.
        mapfile -t files < <(find "${inputs[@]}" "$crashes" -type f 2>/dev/null)
        echo "== fuzz-$t: ${#files[@]} inputs, no mutation"
        "$build/bin/fuzz-$t" "${args[@]}" -runs=0 "${files[@]}" >"$build/fuzz-$t.log" 2>&1 || status=1
    else
        if [ -n "$runs" ]; then
            args+=(-runs="$runs")
            [ -n "${SECONDS_EACH:-}" ] && args+=(-max_total_time="$seconds")   # both: whichever comes first
        else
            args+=(-max_total_time="$seconds")
        fi
        [ "$jobs" -gt 1 ] && args+=(-fork="$jobs" -ignore_crashes=0)
        echo "== fuzz-$t: ${runs:-$seconds s}"
        "$build/bin/fuzz-$t" "${args[@]}" "${inputs[@]}" >"$build/fuzz-$t.log" 2>&1 || status=1
    fi
    # libFuzzer's final stats: executions, coverage (edges), corpus; or what went wrong.
    summary=$(grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" "$build/fuzz-$t.log" | tr "\n" " " || true)
    cov=$(grep -oE "cov: [0-9]+" "$build/fuzz-$t.log" | tail -1 || true)
    echo "   ${summary}${cov:+ $cov} corpus $(find "$corpus" -type f | wc -l) files"
    if grep -qE "ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:|SUMMARY: " "$build/fuzz-$t.log"; then
        status=1
        grep -E "ERROR:|runtime error:|SUMMARY:|Test unit written" "$build/fuzz-$t.log" | head -5 | sed 's/^/   /'
    fi
done
[ "$status" = 0 ] && echo "fuzz.sh: every target ran clean" || echo "fuzz.sh: see build-fuzz/fuzz-TARGET.log and build-fuzz/crashes/" >&2
exit "$status"
