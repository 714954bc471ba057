#!/usr/bin/env bash
# Configures and builds carve (Release) in build/: every target, or only the TARGETs given
# (scripts/sample.sh builds `carve` alone, which builds the man page with it). Under CI=true
# (CI services set it, and scripts/test.sh does) warnings are errors: -DCARVE_WERROR=ON.
# Usage: scripts/build.sh [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
werror=OFF
[ "${CI:-}" = true ] && werror=ON
# A new tree is configured with Ninja, which starts compiling a target's sources while the
# libraries it links are still building (the Makefile generator leaves a core idle at each step
# of that chain); an existing tree keeps the generator it was made with.
generator=()
[ -f build/CMakeCache.txt ] || ! command -v ninja >/dev/null || generator=(-G Ninja)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DCARVE_WERROR="$werror" >/dev/null
if [ $# -gt 0 ]; then
    cmake --build build -j "$(nproc)" --target "$@"
else
    cmake --build build -j "$(nproc)"
fi
