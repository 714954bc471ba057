#!/usr/bin/python3
"""Printability (issue 35): free-standing thin columns, skins left open, hanging, for carve and
its peers, every G-code measured the same way by `carve check --mesh --json`.

Slices the shared models (cat, elephant, fandisk, man, skull) and four synthetic shapes written
here (a wide flat box, a dome, a tall box with a high shelf, a thin-bladed plate) with carve at
its defaults, CuraEngine lightning 10 % (1 wall, 2/2) and PrusaSlicer 1 perimeter 0 % infill
(2/2) - the command lines of bench/baselines.py - and writes bench/results/printability.md and
.json.

    bench/printability.py                        # everything; peers' G-code cached in --work
    bench/printability.py --carve-only --carve /path/to/carve   # rerun carve's rows only
    bench/printability.py --models cat,dome

The peers' G-code does not change: it is kept in --work (default /tmp/carve_printability) and
reused; only its check is rerun (the check may have changed). --carve-only leaves the peers'
rows as the last results JSON has them.
"""
import argparse
import datetime
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import baselines  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = ['cat', 'elephant', 'fandisk', 'man', 'skull']
SYNTHETIC = ['flat_box', 'dome', 'tall_shelf', 'bladed_plate']
SLICERS = ['carve', 'cura_lightning', 'prusa_hollow']


# --- synthetic meshes --------------------------------------------------------------------------

def write_stl(path, tris):
    with open(path, 'wb') as out:
        out.write(b'\0' * 80)
        out.write(struct.pack('<I', len(tris)))
        for t in tris:
            a, b, c = t
            u = [b[i] - a[i] for i in range(3)]
            v = [c[i] - a[i] for i in range(3)]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            norm = math.sqrt(sum(x * x for x in n)) or 1
            out.write(struct.pack('<3f', *(x / norm for x in n)))
            for p in t:
                out.write(struct.pack('<3f', *p))
            out.write(b'\0\0')


def union_of_boxes(boxes):
    """A closed mesh of a union of axis-aligned boxes (x0, y0, z0, x1, y1, z1): the grid of every
    box's planes, its cells filled when inside a box, a quad (two triangles, outward) on every
    face between a filled and an empty cell. The boxes must not touch along an edge only."""
    xs, ys, zs = (sorted({b[k] for b in boxes} | {b[k + 3] for b in boxes}) for k in range(3))

    def filled(i, j, k):
        if not (0 <= i < len(xs) - 1 and 0 <= j < len(ys) - 1 and 0 <= k < len(zs) - 1):
            return False
        c = ((xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2, (zs[k] + zs[k + 1]) / 2)
        return any(b[0] < c[0] < b[3] and b[1] < c[1] < b[4] and b[2] < c[2] < b[5] for b in boxes)

    tris = []
    for i in range(len(xs) - 1):
        for j in range(len(ys) - 1):
            for k in range(len(zs) - 1):
                if not filled(i, j, k):
                    continue
                x0, x1, y0, y1, z0, z1 = xs[i], xs[i + 1], ys[j], ys[j + 1], zs[k], zs[k + 1]
                faces = [  # neighbour, corners counter-clockwise seen from outside
                    ((i - 1, j, k), [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)]),
                    ((i + 1, j, k), [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)]),
                    ((i, j - 1, k), [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)]),
                    ((i, j + 1, k), [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)]),
                    ((i, j, k - 1), [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)]),
                    ((i, j, k + 1), [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]),
                ]
                for nb, q in faces:
                    if not filled(*nb):
                        tris += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    return tris


def dome(radius=35.0, rings=40, sectors=96):
    """A solid half ball on the bed, its flat side down."""
    def p(ring, s):
        th = (math.pi / 2) * ring / rings  # 0 at the pole
        ph = 2 * math.pi * s / sectors
        return (radius * math.sin(th) * math.cos(ph), radius * math.sin(th) * math.sin(ph),
                radius * math.cos(th))
    tris = []
    for r in range(rings):
        for s in range(sectors):
            a, b, c, d = p(r, s), p(r, s + 1), p(r + 1, s + 1), p(r + 1, s)
            if r == 0:
                tris.append((a, d, c))
            else:
                tris += [(a, d, c), (a, c, b)]
    for s in range(sectors):  # the floor, seen from below
        tris.append(((0, 0, 0), p(rings, s + 1), p(rings, s)))
    return tris


def synthetic_meshes(work):
    shapes = {
        # Wide and flat: the widest ceiling over the lowest cavity.
        'flat_box': union_of_boxes([(0, 0, 0, 80, 80, 12)]),
        'dome': dome(),
        # A tall box with a pocket from the top: its floor, a shelf 40 mm up inside the box,
        # is the ceiling of a 40 mm tall interior.
        'tall_shelf': union_of_boxes([(0, 0, 0, 40, 40, 40), (0, 0, 40, 5, 40, 60),
                                      (35, 0, 40, 40, 40, 60), (5, 0, 40, 35, 5, 60),
                                      (5, 35, 40, 35, 40, 60)]),
        # A plate with six blades 1.5 mm thick, 15 mm tall.
        'bladed_plate': union_of_boxes([(0, 0, 0, 100, 60, 8)] + [
            (8 + k * 15, 5, 8, 9.5 + k * 15, 55, 23) for k in range(6)]),
    }
    paths = {}
    for name, tris in shapes.items():
        path = os.path.join(work, name + '.stl')
        write_stl(path, tris)
        paths[name] = path
    return paths


# --- slicing and checking ----------------------------------------------------------------------

def run(cmd, log):
    start = time.monotonic()
    with open(log, 'w') as f:
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    return rc, time.monotonic() - start


def slice_cmd(slicer, carve, model_path, out):
    if slicer == 'carve':
        return [carve, 'slice', model_path, '-o', out, '-q']
    if slicer == 'prusa_hollow':
        return (['prusa-slicer'] + baselines.PRUSA_COMMON + baselines.PRUSA_CONFIGS['hollow'] +
                ['-o', out, model_path])
    settings, errors = baselines.cura_args({**baselines.CURA_COMMON,
                                            **baselines.CURA_CONFIGS['lightning']})
    return (['CuraEngine', 'slice', '-v', '-j',
             os.path.join(baselines.CURA_DEFS, 'fdmprinter.def.json')] + settings + ['-e0'] +
            settings + ['-l', model_path, '-o', out])


def placement(slicer, model_path):
    """Where SLICER put the model: the offset (mm) its G-code adds to the mesh's x and y, so that
    the check lays the mesh under every G-code exactly. carve centres the model's box on its
    default 250 x 210 bed; the peers' command lines (bench/baselines.py: PrusaSlicer
    --dont-arrange on a bed centred on 0, CuraEngine machine_center_is_zero) keep the mesh's own
    coordinates, which check's automatic placement finds within 0.01 mm on them. On carve's
    G-code the automatic placement (the extrusion's box centred on the mesh's) is thrown off by
    any line that reaches past the model on one side only: a thin wall's bead widened to the
    narrowest bead at the tip of fandisk's fin moved it 0.07 mm, which read as 0.13 % of the
    bottom skins open."""
    if not slicer.startswith('carve'):
        return 0.0, 0.0
    lo, hi = baselines.stl_bbox(model_path)
    return 125.0 - (lo[0] + hi[0]) / 2, 105.0 - (lo[1] + hi[1]) / 2


def slice_and_check(args, model, model_path, slicer, slice_cmd):
    """Slices MODEL with SLICER (carve every time, a peer when its G-code is not there yet) and
    reads the G-code back with `carve check --mesh --json`: (row, check JSON), the JSON None
    when the row holds an error."""
    stem = os.path.join(args.work, f'{model}_{slicer}')
    gcode = stem + '.gcode'
    row = {'model': model, 'slicer': slicer}
    if slicer == 'carve' or not os.path.exists(gcode):
        if slicer != 'carve' and not shutil.which(slice_cmd(slicer, '', '', '')[0]):
            row['error'] = 'not installed'
            return row, None
        print(f'slicing {model} with {slicer} ...', file=sys.stderr, flush=True)
        rc, wall = run(slice_cmd(slicer, args.carve, model_path, gcode), stem + '.slice.log')
        if rc != 0 or not os.path.exists(gcode):
            row['error'] = f'slicer exit {rc}'
            if os.path.exists(gcode):
                os.remove(gcode)
            return row, None
        row['slice_wall_s'] = round(wall, 2)
    start = time.monotonic()
    x, y = placement(slicer, model_path)
    out = subprocess.run([args.carve, 'check', gcode, '--mesh', model_path, '--json',
                          '--mesh-offset', f'{x:.4f},{y:.4f}'],
                         capture_output=True, text=True)
    row['check_wall_s'] = round(time.monotonic() - start, 2)
    if out.returncode != 0:
        row['error'] = 'check: ' + out.stderr.strip()
        return row, None
    return row, json.loads(out.stdout)


def measure(args, model, model_path, slicer):
    row, c = slice_and_check(args, model, model_path, slicer, slice_cmd)
    if c is None:
        return row
    p = c['printability']
    volume = baselines.stl_volume_mm3(model_path)
    t = p['columns']['tallest']
    row.update(
        material_percent=round(100 * c['extruded_volume_mm3'] / volume, 2),
        columns_over_5mm=p['columns']['over_5mm'], columns_over_10mm=p['columns']['over_10mm'],
        tallest_mm=round(t['height_mm'], 1), tallest_width_mm=round(t['width_mm'], 2),
        tallest_z_mm=[round(t['z_from_mm'], 2), round(t['z_to_mm'], 2)],
        top_open_percent=round(p['top_skin']['open_percent'], 2),
        top_holes=p['top_skin']['holes_1mm2'],
        top_largest_hole_mm2=round(p['top_skin']['largest_hole_mm2'], 2),
        top_largest_hole_z_mm=p['top_skin']['largest_hole_z_mm'],
        bottom_open_percent=round(p['bottom_skin']['open_percent'], 2),
        bottom_holes=p['bottom_skin']['holes_1mm2'],
        hanging_inside_mm2=round(c['hanging_inside_mm2'], 1),
        hanging_overhang_mm2=round(c['hanging_overhang_mm2'], 1),
        longest_bridge_mm=round(c['longest_bridge']['length_mm'], 1),
        retractions=c['retractions'], stick_time_s=round(c['stick_time_s']),
        passes=p['passes'], failed_rules=p['failed_rules'])
    return row


def cell(row, key, fmt='{}'):
    if row is None or 'error' in row:
        return '–'
    return fmt.format(row[key])


def write_results(args, rows, started, carve_version):
    os.makedirs(args.results, exist_ok=True)
    json_path = os.path.join(args.results, 'printability.json')
    with open(json_path, 'w') as f:
        json.dump({'carve': carve_version, 'run': started, 'rows': rows}, f, indent=1)
    by = {(r['model'], r['slicer']): r for r in rows}
    models = [m for m in SHARED + SYNTHETIC if any(r['model'] == m for r in rows)]
    names = {'carve': 'carve', 'cura_lightning': 'Cura lightning', 'prusa_hollow': 'Prusa 0 %'}
    lines = [
        '# Printability: free-standing columns, skins left open, hanging (issue 35)',
        '',
        f'Run {started} by `bench/printability.py`; {carve_version} at its defaults, CuraEngine '
        'lightning 10 % (1 wall, 2/2), PrusaSlicer 1 perimeter 0 % infill (2/2), the command '
        'lines of bench/baselines.py. Every G-code measured by `carve check --mesh --json` '
        '(definitions in docs/check.md), the mesh laid under it where that slicer put it '
        '(`--mesh-offset`, see placement() in the script). Synthetic shapes: flat_box 80 x 80 x 12 mm; dome, a '
        'half ball of radius 35 mm; tall_shelf, a 40 x 40 x 60 mm box with a 30 x 30 mm pocket '
        'from the top whose floor (a shelf 40 mm up) is the ceiling of the interior; '
        'bladed_plate, 100 x 60 x 8 mm with six blades 1.5 x 50 x 15 mm.',
        '',
        'Columns: free-standing thin interior columns taller than 5 / 10 mm; tallest: height '
        '(median width of its pieces); holes: open pieces of at least 1 mm²; hanging: '
        'far-unsupported mm² inside the model / overhang; time: the stick time (no look-ahead, '
        'the same for every slicer). strict: what `carve check --strict` says.',
        '',
        '| model | slicer | material % | columns >5 / >10 mm | tallest mm (width) | top open % '
        '| top holes | bottom open % | bottom holes | hanging inside / overhang mm² '
        '| longest bridge mm | retractions | time | strict |',
        '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|',
    ]
    for m in models:
        for s in SLICERS:
            r = by.get((m, s))
            if r is None:
                continue
            if 'error' in r:
                lines.append(f"| {m} | {names[s]} | {r['error']} |" + ' |' * 11)
                continue
            t = r['stick_time_s']
            lines.append(
                f"| {m} | {names[s]} | {r['material_percent']:.2f} | {r['columns_over_5mm']} / "
                f"{r['columns_over_10mm']} | {r['tallest_mm']:.1f} ({r['tallest_width_mm']:.2f}) "
                f"| {r['top_open_percent']:.2f} | {r['top_holes']} | "
                f"{r['bottom_open_percent']:.2f} | {r['bottom_holes']} | "
                f"{r['hanging_inside_mm2']:.1f} / {r['hanging_overhang_mm2']:.1f} | "
                f"{r['longest_bridge_mm']:.1f} | {r['retractions']:,} | "
                f"{t // 3600}h {t % 3600 // 60:02d}m | "
                f"{'passes' if r['passes'] else 'fails ' + str(len(r['failed_rules']))} |")
    lines += ['', 'Check time per G-code (s): ' + ', '.join(
        f"{r['model']} {names[r['slicer']]} {r['check_wall_s']}" for r in rows
        if 'check_wall_s' in r), '']
    with open(os.path.join(args.results, 'printability.md'), 'w') as f:
        f.write('\n'.join(lines))
    print('\n'.join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--carve', default=os.path.join(ROOT, 'build', 'carve'))
    ap.add_argument('--work', default='/tmp/carve_printability')
    ap.add_argument('--results', default=os.path.join(ROOT, 'bench', 'results'))
    ap.add_argument('--models', help='comma-separated subset of ' + ','.join(SHARED + SYNTHETIC))
    ap.add_argument('--carve-only', action='store_true',
                    help="slice and check with carve only; the peers' rows are kept from the "
                    'last results JSON')
    args = ap.parse_args()
    args.carve = os.path.abspath(args.carve)
    os.makedirs(args.work, exist_ok=True)
    started = datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')
    carve_version = subprocess.run([args.carve, '--version'], capture_output=True,
                                   text=True).stdout.strip()
    try:
        commit = subprocess.run(['git', '-C', ROOT, 'rev-parse', '--short', 'HEAD'],
                                capture_output=True, text=True).stdout.strip()
        carve_version += f' ({commit})' if commit else ''
    except OSError:
        pass
    paths = {m: os.path.join(baselines.MODELS_DIR, m + '.stl') for m in SHARED}
    paths = {m: p for m, p in paths.items() if os.path.exists(p)}
    paths.update(synthetic_meshes(args.work))
    models = [m for m in SHARED + SYNTHETIC if m in paths]
    if args.models:
        models = [m for m in models if m in args.models.split(',')]
    old = []
    json_path = os.path.join(args.results, 'printability.json')
    if os.path.exists(json_path):
        old = json.load(open(json_path))['rows']
    rows = []
    for m in models:
        for s in SLICERS:
            if args.carve_only and s != 'carve':
                continue
            row = measure(args, m, paths[m], s)
            print(json.dumps(row), file=sys.stderr, flush=True)
            rows.append(row)
    done = {(r['model'], r['slicer']) for r in rows}
    rows += [r for r in old if (r['model'], r['slicer']) not in done]
    order = {(m, s): i for i, (m, s) in enumerate((m, s) for m in SHARED + SYNTHETIC
                                                  for s in SLICERS)}
    rows.sort(key=lambda r: order.get((r['model'], r['slicer']), 1 << 30))
    write_results(args, rows, started, carve_version)


if __name__ == '__main__':
    main()
