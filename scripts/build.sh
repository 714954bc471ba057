#!/usr/bin/env bash
# Configures and builds carve (Release) in build/. Under CI=true (CI services set it, and
# scripts/test.sh does) warnings are errors: -DCARVE_WERROR=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
werror=OFF
[ "${CI:-}" = true ] && werror=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCARVE_WERROR="$werror" >/dev/null
cmake --build build -j "$(nproc)"
