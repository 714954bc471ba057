#!/usr/bin/python3
"""Flat shapes: where carve's carving is weakest (issue #23: "make flat and thin-bladed test
shapes of your own"). Writes two meshes, a flat 60 x 60 x 12 mm box and a 100 x 60 x 8 mm plate
with six blades 1.5 mm thick and 15 mm tall, slices them with carve (defaults), CuraEngine
lightning 10 % and PrusaSlicer grid 15 % (the settings of bench/baselines.py), measures every
G-code with `carve check --mesh --json` and writes bench/results/flat_shapes.md.

    bench/flat_shapes.py [--carve build/carve] [--work /tmp/carve_flat]

PrusaSlicer refuses to load the 12-triangle box (it says "Loading of a model file failed"),
so that row has no PrusaSlicer figures.
"""
import argparse
import datetime
import json
import os
import struct
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import baselines  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def box(x0, y0, z0, x1, y1, z1):
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    f = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
         (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]
    return [(v[a], v[b], v[c]) for a, b, c in f]


def write_stl(path, tris):
    with open(path, 'wb') as out:
        out.write(b'\0' * 80)
        out.write(struct.pack('<I', len(tris)))
        for t in tris:
            out.write(struct.pack('<3f', 0, 0, 0))
            for p in t:
                out.write(struct.pack('<3f', *p))
            out.write(b'\0\0')


SHAPES = {
    # name: (triangles, volume mm3)
    'flat_box': (box(0, 0, 0, 60, 60, 12), 60 * 60 * 12),
    'bladed_plate': (box(0, 0, 0, 100, 60, 8) +
                     sum((box(8 + k * 15, 5, 7.9, 9.5 + k * 15, 55, 23) for k in range(6)), []),
                     100 * 60 * 8 + 6 * 1.5 * 50 * 15.0),
}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--carve', default=os.path.join(ROOT, 'build', 'carve'))
    ap.add_argument('--work', default='/tmp/carve_flat')
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    rows = []
    for name, (tris, volume) in SHAPES.items():
        stl = os.path.join(args.work, name + '.stl')
        write_stl(stl, tris)
        runs = {
            'carve': [args.carve, 'slice', stl, '-q', '-o'],
            'Cura lightning 10 %': None,
            'Prusa grid 15 %': ['prusa-slicer'] + baselines.PRUSA_COMMON +
                               baselines.PRUSA_CONFIGS['grid'] + [stl, '-o'],
        }
        for slicer, cmd in runs.items():
            gcode = os.path.join(args.work, f'{name}_{slicer.split()[0].lower()}.gcode')
            if cmd is None:
                settings, _ = baselines.cura_args({**baselines.CURA_COMMON,
                                                   **baselines.CURA_CONFIGS['lightning']})
                cmd = (['CuraEngine', 'slice', '-v', '-j',
                        os.path.join(baselines.CURA_DEFS, 'fdmprinter.def.json')] + settings +
                       ['-e0'] + settings + ['-l', stl, '-o', gcode])
            else:
                cmd = cmd + [gcode]
            if os.path.exists(gcode):
                os.remove(gcode)
            subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            if not os.path.exists(gcode):
                rows.append((name, slicer, None))
                continue
            check = subprocess.run([args.carve, 'check', gcode, '--mesh', stl, '--json'],
                                   capture_output=True, text=True)
            d = json.loads(check.stdout)
            rows.append((name, slicer, {
                'material': 100 * d['extruded_volume_mm3'] / volume,
                'inside': d['hanging_inside_mm2'], 'overhang': d['hanging_overhang_mm2'],
                'retractions': d['retractions'], 'stick_min': d['stick_time_s'] / 60}))
            print(name, slicer, rows[-1][2], flush=True)
    commit = subprocess.run(['git', '-C', ROOT, 'rev-parse', '--short', 'HEAD'],
                            capture_output=True, text=True).stdout.strip()
    lines = ['# Flat shapes: carve against CuraEngine lightning and PrusaSlicer grid', '',
             f'Made by `bench/flat_shapes.py` on {datetime.datetime.now():%Y-%m-%d %H:%M} '
             f'(carve at {commit}), every G-code measured by `carve check --mesh --json`.', '',
             '| shape | slicer | material % | hanging inside mm² | hanging overhang mm² | '
             'retractions | stick time min |', '|---|---|---:|---:|---:|---:|---:|']
    for name, slicer, r in rows:
        if r is None:
            lines.append(f'| {name} | {slicer} | – | – | – | – | – |')
        else:
            lines.append(f"| {name} | {slicer} | {r['material']:.1f} | {r['inside']:.1f} | "
                         f"{r['overhang']:.1f} | {r['retractions']:,} | {r['stick_min']:.0f} |")
    out = os.path.join(ROOT, 'bench', 'results', 'flat_shapes.md')
    with open(out, 'w') as f:
        f.write('\n'.join(lines) + '\n')
    print('wrote', out)


if __name__ == '__main__':
    main()
