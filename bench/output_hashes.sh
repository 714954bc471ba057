#!/bin/bash
# The sha256 of the G-code of every shared model, at the defaults and with --support auto, on 1 and
# 8 threads: what a refactoring must leave byte-identical (issue 50). One line per run:
# model, configuration, threads, hash. Compare two runs with diff.
# Usage: bench/output_hashes.sh [CARVE_BINARY] [MODELS_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
carve=${1:-$PWD/build/carve}
models=${2:-/work/shared/models}
# The header's date is the clock unless this is set.
export SOURCE_DATE_EPOCH=0
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for mesh in "$models"/*.stl; do
    name=$(basename "$mesh" .stl)
    for config in default support-auto; do
        extra=()
        [ "$config" = support-auto ] && extra=(--support auto)
        for threads in 1 8; do
            "$carve" slice "$mesh" -o "$out/g.gcode" -q --threads "$threads" "${extra[@]}"
            echo "$name $config $threads $(sha256sum <"$out/g.gcode" | cut -d' ' -f1)"
        done
    done
done
