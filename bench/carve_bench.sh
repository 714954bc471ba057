#!/bin/sh
# carve's performance and scale in one command: builds the carve executable (Release) and runs
# bench/carve_bench.py (models against PrusaSlicer/CuraEngine, then the fandisk scaling study).
#   bash bench/carve_bench.sh            # every shared model but skull_x4_400k, s = 1..10
#   bash bench/carve_bench.sh --quick    # fandisk and cat, s = 1,2,4,8
#   bash bench/carve_bench.sh --all      # also skull_x4_400k
# Other arguments go to carve_bench.py (see its --help). CARVE_BUILD_DIR picks the build
# directory (default build/). Results: bench/results/carve_*.{csv,md,json,png}.
set -e
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BUILD="${CARVE_BUILD_DIR:-$ROOT/build}"
if [ -f "$BUILD/CMakeCache.txt" ]; then
    # an existing build directory keeps its own options (tests, benchmarks); only Release is forced
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
else
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DCARVE_BUILD_TESTS=OFF \
        -DCARVE_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$BUILD" -j2 --target carve
exec /usr/bin/python3 "$ROOT/bench/carve_bench.py" --carve "$BUILD/carve" "$@"
