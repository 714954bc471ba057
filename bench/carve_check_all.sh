#!/bin/bash
# carve at its defaults on the shared models, each G-code measured with carve check --mesh: material,
# hanging inside/overhang, minima, retractions, travel outside, stick and own time, slicing time.
# Usage: bench/carve_check_all.sh (needs build/carve, ../shared/models, and the scaled meshes
# that bench/compare.sh leaves in /tmp/carve_compare for the Table 1 rows).
cd "$(dirname "$0")/.."; B=$PWD/build/carve; M=$PWD/../shared/models; mkdir -p /tmp/final
run() { n=$1; mesh=$2; shift 2
  /usr/bin/time -f "%e %U" -o /tmp/final/$n.time $B slice $mesh -o /tmp/final/$n.gcode --stats /tmp/final/$n.json -q "$@" 2>/dev/null
  $B check /tmp/final/$n.gcode --mesh ${CHECKMESH:-$mesh} --json > /tmp/final/$n.check.json 2>/dev/null
  /usr/bin/python3 - $n <<'PY'
import json,sys
n=sys.argv[1]; s=json.load(open(f'/tmp/final/{n}.json')); c=json.load(open(f'/tmp/final/{n}.check.json'))
t=open(f'/tmp/final/{n}.time').read().split()
print(f"{n:12s} mat {s['material_percent']:.2f}%  inside {c['hanging_inside_mm2']:.1f}  overhang {c['hanging_overhang_mm2']:.1f}  unsup_minima {s.get('minima_unsupported')}/{s.get('minima_found')}  retr {c.get('retractions')}  travel_out_m {c.get('travel_outside_mm',0)/1000:.1f}  stick_min {c.get('stick_time_s',0)/60:.0f}  own_min {s['estimated_print_time_s']/60:.0f}  wall_s {t[0]} cpu_s {t[1]}")
PY
}
for m in cat elephant fandisk man skull; do run $m $M/$m.stl; done
CHECKMESH=/tmp/carve_compare/cat_x1.47.stl run cat147 $M/cat.stl --scale 1.47 --preset 2c0s
CHECKMESH=/tmp/carve_compare/skull_x1.43.stl run skull143 $M/skull.stl --scale 1.43 --preset 2c0s
