#!/usr/bin/env bash
# Install, build and run the whole test suite: the README's second command, and what CI runs.
# Warnings are errors here (CI=true), whoever runs it.
set -euo pipefail
cd "$(dirname "$0")/.."
export CI=true
bash scripts/install-deps.sh
# The layering drawn in README.md and the formatting: cheap, so before the build.
python3 scripts/check_layers.py
bash scripts/check_format.sh
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
# The same suite under AddressSanitizer + UBSan, then every fuzz target for a short while.
bash scripts/sanitize.sh
CARVE_FUZZ_BUILD_DIR=build-asan bash scripts/fuzz.sh "${CARVE_FUZZ_SECONDS:-10}"
