#!/usr/bin/env bash
# Travel outside the model (issue #18) on the shared models at the defaults: carve check's
# figures (outside travel, retractions, header time) and travel_bound.py's split and lower
# bound, one line per model. Usage: bench/travel.sh [OUTDIR] (default /tmp/carve_travel).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/carve_travel}
mkdir -p "$out"
models=${MODELS:-"cat elephant fandisk man skull"}
printf '%-9s %10s %11s %9s %9s %9s %9s %9s\n' model outside retractions time_s first \
    retracted combed bound
for m in $models; do
    stl=/work/shared/models/$m.stl
    build/carve slice "$stl" -o "$out/$m.gcode" -q
    build/carve check "$out/$m.gcode" --mesh "$stl" --json --layers >"$out/$m.check.json"
    /usr/bin/python3 bench/travel_bound.py "$stl" "$out/$m.gcode" "$out/$m.check.json" \
        --out "$out/$m.bound.json" >/dev/null
    /usr/bin/python3 - "$m" "$out" <<'PY'
import json, sys
m, out = sys.argv[1], sys.argv[2]
c = json.load(open(f"{out}/{m}.check.json"))
b = json.load(open(f"{out}/{m}.bound.json"))["totals"]
print(f"{m:<9} {c['travel_outside_mm']:10.0f} {c['retractions']:11d} "
      f"{c['estimated_time_from_header_s']:9.0f} {b['first']:9.0f} {b['retracted']:9.0f} "
      f"{b['combed']:9.0f} {b['bound']:9.0f}")
PY
done
