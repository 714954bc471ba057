#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang-14 (build-fuzz/) and runs each for SECONDS
# (default 60), two at a time. Seeds are made from ../shared/models and from PrusaSlicer's
# vendor bundle (/usr/share/PrusaSlicer/profiles, when installed) at run time; new inputs the
# fuzzer finds stay in build-fuzz/corpus/, crash reproducers go to build-fuzz/crashes/.
# Exits non-zero if any target finds a crash, leak, timeout or out-of-memory.
# With CARVE_FUZZ_BUILD_DIR=DIR it runs the targets of a tree configured already with
# -DCARVE_FUZZ=ON (scripts/sanitize.sh's build-asan/, as scripts/test.sh does) instead.
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(stl_binary_fuzz stl_ascii_fuzz obj_fuzz threemf_fuzz slicer_fuzz
                                     ini_fuzz placeholder_fuzz cli_fuzz)
models=${CARVE_MODELS_DIR:-$(cd .. && pwd)/shared/models}
dir=${CARVE_FUZZ_BUILD_DIR:-build-fuzz}

if [ -z "${CARVE_FUZZ_BUILD_DIR:-}" ]; then
    CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCARVE_FUZZ=ON -DCARVE_BUILD_TESTS=OFF -DCARVE_BUILD_BENCH=OFF >/dev/null
elif ! grep -q '^CARVE_FUZZ:BOOL=ON$' "$dir/CMakeCache.txt" 2>/dev/null; then
    echo "fuzz.sh: $dir is not a tree configured with -DCARVE_FUZZ=ON" >&2
    exit 2
fi
cmake --build "$dir" -j "$(nproc)" --target "${targets[@]}"

rm -rf "$dir/seeds"
/usr/bin/python3 fuzz/make_seeds.py "$models" "$dir/seeds"
mkdir -p "$dir/crashes" "$dir/logs"

run_one() {
    local t=$1
    mkdir -p "$dir/corpus/$t"
    # -rss_limit_mb: one input may not take more than 2 GiB; -timeout: nor more than 20 s.
    if "$dir/$t" "$dir/corpus/$t" "$dir/seeds/$t" \
        -max_total_time="$seconds" -max_len=65536 -timeout=20 -rss_limit_mb=2048 \
        -print_final_stats=1 -artifact_prefix="$dir/crashes/$t-" \
        $([ "$t" = cli_fuzz ] && echo -close_fd_mask=2) \
        >"$dir/logs/$t.log" 2>&1; then
        echo "fuzz $t: $(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' \
            "$dir/logs/$t.log" | grep -o '[0-9]*$') executions, no crash"
    else
        echo "fuzz $t: FAILED, see $dir/logs/$t.log"
        tail -n 40 "$dir/logs/$t.log"
        return 1
    fi
}

status=0
pids=()
jobs=$(nproc)
for t in "${targets[@]}"; do
    run_one "$t" &
    pids+=($!)
    if [ ${#pids[@]} -ge "$jobs" ]; then
        wait "${pids[0]}" || status=1
        pids=("${pids[@]:1}")
    fi
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
exit $status
