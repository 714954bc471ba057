#!/usr/bin/env bash
# Install, build and run the whole test suite: the README's second command, and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# The layering drawn in README.md (also a ctest test, but a cycle should stop CI before the build).
python3 scripts/check_layers.py
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
# The same suite under AddressSanitizer + UBSan, then every fuzz target for a short while.
bash scripts/sanitize.sh
bash scripts/fuzz.sh "${CARVE_FUZZ_SECONDS:-10}"
