#!/usr/bin/env bash
# Install, build, and slice the bundled sample model: the README's first command. Builds the
# program alone (and its man page), not the tests and benchmarks: scripts/test.sh builds those.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh carve
mkdir -p out
./build/carve slice data/sample/fandisk.stl -o out/fandisk.gcode --stats out/fandisk.json \
  --report out/fandisk.html
echo "G-code: $(pwd)/out/fandisk.gcode"
echo "Stats:  $(pwd)/out/fandisk.json"
echo "Report: $(pwd)/out/fandisk.html"
