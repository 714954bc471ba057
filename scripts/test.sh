#!/usr/bin/env bash
# Install, build and run the whole test suite: the README's second command, and what CI runs.
# Warnings are errors here (CI=true), whoever runs it.
set -euo pipefail
cd "$(dirname "$0")/.."
export CI=true
# Each phase's end, seconds since the start and the load average, for bench/results/ci_time.md.
mark() { echo "test.sh: $1 done at ${SECONDS} s, load $(cut -d' ' -f1-3 /proc/loadavg)"; }
bash scripts/install-deps.sh
# The layering drawn in docs/architecture.md, the size rules (no function body over 150 lines,
# no file over 650) and the formatting: cheap, so before the build.
python3 scripts/check_layers.py
python3 scripts/check_sizes.py
bash scripts/check_format.sh
mark "install-deps, check_layers, check_sizes, check_format"
bash scripts/build.sh
mark "Release build"
ctest --test-dir build --output-on-failure -j "$(nproc)"
mark "Release ctest"
# The same suite under AddressSanitizer + UBSan, and every fuzz target for a short while, both
# from the one clang-14 tree. The fuzz targets run alongside the suite, whose last minute or so
# runs one or two long tests and would leave a core idle (bench/results/ci_time.md).
bash scripts/sanitize.sh build
mark "sanitizer+fuzz build"
(CARVE_FUZZ_BUILD_DIR=build-asan bash scripts/fuzz.sh "${CARVE_FUZZ_SECONDS:-10}" && mark fuzz) &
fuzz=$!
status=0
bash scripts/sanitize.sh test || status=1
mark "sanitizer ctest"
wait "$fuzz" || status=1
exit $status
