#!/usr/bin/env bash
# Slices a 2-million-triangle mesh (bench/big_mesh.py, written to /tmp) with the Release build
# under /usr/bin/time -v and appends wall time and peak RSS to bench/results/big_mesh.md.
# Not part of the test suite. Usage: bench/big_mesh.sh [SEGMENTS] [extra carve options...]
set -euo pipefail
cd "$(dirname "$0")/.."
segments=${1:-1000}
shift || true
dir=/tmp/carve_big_mesh
mkdir -p "$dir"
stl=$dir/torus_${segments}.stl
[ -f "$stl" ] || /usr/bin/python3 bench/big_mesh.py "$stl" "$segments"
cmake --build build -j "$(nproc)" --target carve >/dev/null
/usr/bin/time -v build/carve slice "$stl" -o "$dir/out.gcode" --stats "$dir/stats.json" -q "$@" \
    2>"$dir/time.txt"
wall=$(grep 'Elapsed (wall clock)' "$dir/time.txt" | awk '{print $NF}')
user=$(grep 'User time' "$dir/time.txt" | awk '{print $NF}')
rss=$(grep 'Maximum resident set size' "$dir/time.txt" | awk '{print $NF}')
tris=$(( 2 * segments * segments ))
layers=$(grep -o '"layers": *[0-9]*' "$dir/stats.json" | grep -o '[0-9]*$' || echo '?')
line="| $(date -u +%F) | $(git rev-parse --short HEAD) | $tris | $layers | $wall | ${user} s | $(( rss / 1024 )) MiB | ${*:-defaults} |"
out=bench/results/big_mesh.md
if [ ! -f "$out" ]; then
    cat >"$out" <<'HEAD'
# A 2-million-triangle mesh

`bench/big_mesh.sh` writes a rippled torus (bench/big_mesh.py, 165 x 164 x 45 mm, closed) as a
binary STL into /tmp and slices it with the Release build under `/usr/bin/time -v`.
Wall time is not trustworthy while other jobs share the 2 cores; user time and peak RSS are.

| date | commit | triangles | layers | wall | user CPU | peak RSS | options |
|---|---|---:|---:|---:|---:|---:|---|
HEAD
fi
echo "$line" >>"$out"
echo "$line"
