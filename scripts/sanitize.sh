#!/usr/bin/env bash
# Builds the whole test suite with AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/)
# and runs it with ctest. Any sanitizer report fails the test that triggered it.
# The tree is clang-14's and holds the libFuzzer targets of fuzz/ too, so that CI builds the
# instrumented libraries once for both: scripts/test.sh runs them from here with
# CARVE_FUZZ_BUILD_DIR=build-asan (scripts/fuzz.sh alone keeps its own -O2 tree, build-fuzz/).
set -euo pipefail
cd "$(dirname "$0")/.."
# -O1 -g1: quick to compile, fast enough to run, line numbers in reports; asserts stay on.
werror=OFF
[ "${CI:-}" = true ] && werror=ON
# Usage: scripts/sanitize.sh [build|test]: only build the tree, or only run its suite (scripts/
# test.sh runs the fuzz targets alongside the suite); both by default.
stage=${1:-all}
case "$stage" in
    build | test | all) ;;
    *) echo "usage: scripts/sanitize.sh [build|test]" >&2; exit 2 ;;
esac
if [ "$stage" != test ]; then
    # A build-asan/ left by the GCC sanitizer build of older revisions: CMake cannot switch an
    # existing tree's compiler.
    if [ -f build-asan/CMakeCache.txt ] && ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++-14$' \
        build-asan/CMakeCache.txt; then
        rm -rf build-asan
    fi
    # Ninja for a new tree (see scripts/build.sh). Each library is compiled as one unity file:
    # its sources share most of their headers (Clipper, Boost.Polygon, TBB, fmt), which are
    # then parsed and instrumented once per library instead of once per file. The Release tree
    # keeps one object per source, so that a source that does not include what it uses is still
    # caught there.
    generator=()
    [ -f build-asan/CMakeCache.txt ] || ! command -v ninja >/dev/null || generator=(-G Ninja)
    CC=clang-14 CXX=clang++-14 cmake -S . -B build-asan "${generator[@]}" \
        -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
        -DCMAKE_UNITY_BUILD=ON -DCARVE_SANITIZE=ON -DCARVE_FUZZ=ON -DCARVE_BUILD_BENCH=OFF \
        -DCARVE_WERROR="$werror" >/dev/null
    cmake --build build-asan -j "$(nproc)"
fi
[ "$stage" != build ] || exit 0
# A 64 MB quarantine of freed memory instead of 256: a use after free is still caught unless 64 MB
# were freed in between, and carve runs a fifth faster with less than half the resident memory
# (fandisk: 2.5 -> 2.0 s, 486 -> 214 MB; bench/results/ci_time.md).
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_stack_use_after_return=0:strict_string_checks=1:quarantine_size_mb=64}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir build-asan --output-on-failure -j "$(nproc)"
