#!/usr/bin/python3
"""Compare: carve against CuraEngine's lightning infill and PrusaSlicer's grid on the shared
models, every G-code measured by one stick, `carve check --mesh --json`.

    bench/compare.sh                          # every model but skull_x4_400k, then Table 1 sizes
    bench/compare.sh --models cat,fandisk --sets default
    bench/compare.sh --reuse                  # re-measure the G-code of the last run, no slicing
    bench/compare.sh --carve ../wt-carve/build/carve   # another carve build against the same peers

Two sets of runs:
- default: every model at its own size, carve at its defaults, CuraEngine lightning 10 %
  (1 wall, 2 top / 2 bottom), PrusaSlicer grid 15 % (2 perimeters, 3 / 3), as in
  shared/BASELINES.md (the settings and the CuraEngine derived settings come from
  bench/baselines.py);
- table1: the sizes of the report's Table 1, skull x1.43 and cat x1.47, carve with
  --preset 2c0s, next to the report's material figures (3.35 % and 7.77 %). carve scales with
  --scale, PrusaSlicer with --scale, CuraEngine gets an STL scaled here into the work dir (it has
  no scale setting of its own on the command line), and the check gets that STL too.

Writes bench/results/compare.{md,csv,json}; G-code, logs and stats go to the work dir
(/tmp/carve_compare: they are large, never commit them). The mesh's placement under each G-code
is found by `carve check` itself (the extrusion's bounding box centred on the mesh's, the
lowest point on the bed), which covers carve centring on the bed, PrusaSlicer keeping the
model's coordinates and anything CuraEngine does; the offset it used is in each check JSON.
"""
import argparse
import csv
import datetime
import json
import os
import shutil
import struct
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import baselines  # noqa: E402  (settings of the peers, CuraEngine's derived settings, timing)

ROOT = baselines.ROOT
MODELS_DIR = baselines.MODELS_DIR
DEFAULT_MODELS = ['cat', 'elephant', 'fandisk', 'man', 'skull']
TABLE1 = {'skull': (1.43, 3.35), 'cat': (1.47, 7.77)}  # scale, the report's material %

# What issue #23 measured at f0a14a7 (hanging inside and far-unsupported mm², retractions), to
# tell at a glance whether this measure and that one agree: slicer -> model -> figure.
ISSUE_F0A14A7 = {
    'hanging_inside_mm2': {'carve': dict(cat=12, elephant=12, fandisk=31, man=0, skull=4),
                           'prusa_grid': dict(cat=4, elephant=1, fandisk=4, man=0, skull=3),
                           'cura_lightning': dict(cat=7, elephant=3)},
    'far_unsupported_mm2': {'carve': dict(cat=72, elephant=46, fandisk=52, man=32, skull=393),
                            'prusa_grid': dict(cat=69, elephant=35, fandisk=26, man=38, skull=408),
                            'cura_lightning': dict(cat=67, elephant=38, fandisk=26, man=42,
                                                   skull=442)},
    'retractions': {'carve': dict(cat=4342, elephant=7372, fandisk=1494, man=2891, skull=8526),
                    'cura_lightning': dict(cat=583, elephant=966, fandisk=2, man=1558, skull=435)},
}

# What the stats JSON of carve may call the local minima it leaves without support; the carving
# engineer owns that figure, this bench only reads it.
MINIMA_KEYS = ['unsupported_minima', 'minima_unsupported', 'minima_left_unsupported']


def scaled_stl(src, scale, dst):
    """Binary STL of src scaled by `scale` about the origin (placement does not matter: the check
    and CuraEngine place it themselves)."""
    with open(src, 'rb') as f:
        data = f.read()
    count = struct.unpack_from('<I', data, 80)[0]
    if 84 + 50 * count != len(data):
        raise RuntimeError(f'{src}: only binary STL is scaled here')
    dtype = np.dtype([('n', '<f4', 3), ('v', '<f4', (3, 3)), ('a', '<u2')])
    rec = np.frombuffer(data, dtype=dtype, count=count, offset=84).copy()
    rec['v'] *= scale
    with open(dst + '.tmp', 'wb') as f:
        f.write(data[:80])
        f.write(struct.pack('<I', count))
        f.write(rec.tobytes())
    os.replace(dst + '.tmp', dst)


def minima_unsupported(stats):
    for key in MINIMA_KEYS:
        if key in stats:
            return stats[key]
    for key, value in stats.items():
        if 'minim' in key and 'unsupp' in key and isinstance(value, (int, float)):
            return value
    return None


def jobs_for(carve, model, model_path, check_mesh, scale, preset):
    """(slicer, command maker) for the three slicers on one model."""
    carve_extra = (['--scale', f'{scale:g}'] if scale != 1 else []) + (
        ['--preset', preset] if preset else [])
    prusa_extra = ['--scale', f'{scale:g}'] if scale != 1 else []
    cura_settings, errors = baselines.cura_args({**baselines.CURA_COMMON,
                                                 **baselines.CURA_CONFIGS['lightning']})
    if errors:
        print(f'  cura settings left at defaults: {errors}', file=sys.stderr)
    return [
        ('carve', lambda out: [carve, 'slice', model_path, '-o', out, '--stats',
                               out[:-len('.gcode')] + '.stats.json', '-q'] + carve_extra),
        ('cura_lightning', lambda out: (
            ['CuraEngine', 'slice', '-v', '-j',
             os.path.join(baselines.CURA_DEFS, 'fdmprinter.def.json')] + cura_settings + ['-e0'] +
            cura_settings + ['-l', check_mesh, '-o', out])),
        ('prusa_grid', lambda out: (['prusa-slicer'] + baselines.PRUSA_COMMON +
                                    baselines.PRUSA_CONFIGS['grid'] + prusa_extra +
                                    ['-o', out, model_path])),
    ]


def check(carve, gcode, mesh, log_path):
    rc, wall, cpu, _, out = baselines.timed([carve, 'check', gcode, '--mesh', mesh, '--json'],
                                            log_path)
    if rc != 0:
        raise RuntimeError(f'carve check failed on {gcode}: {out[-500:]}')
    return json.loads(out[out.index('{'):]), wall


def run_set(args, name, models, rows):
    for model in models:
        model_path = os.path.join(MODELS_DIR, model + '.stl')
        scale, report_percent = (TABLE1[model] if name == 'table1' else (1.0, None))
        preset = '2c0s' if name == 'table1' else None
        tag = model if scale == 1 else f'{model}_x{scale:g}'
        check_mesh = model_path
        if scale != 1:
            check_mesh = os.path.join(args.work, tag + '.stl')
            if not os.path.exists(check_mesh):
                scaled_stl(model_path, scale, check_mesh)
        volume = baselines.stl_volume_mm3(check_mesh)
        for slicer, make_cmd in jobs_for(args.carve, model, model_path, check_mesh, scale, preset):
            stem = f'{tag}_{slicer}'
            gcode = os.path.join(args.work, stem + '.gcode')
            log_path = os.path.join(args.work, stem + '.log')
            row = {'set': name, 'model': tag, 'scale': scale, 'slicer': slicer,
                   'model_volume_mm3': round(volume, 1), 'report_material_percent': report_percent}
            times_path = os.path.join(args.work, stem + '.wall')
            if args.reuse and os.path.exists(gcode):
                if os.path.exists(times_path):
                    row['slice_wall_s'] = float(open(times_path).read())
            else:
                if slicer != 'carve' and not shutil.which(make_cmd('x')[0]):
                    print(f'  {make_cmd("x")[0]} not installed: skipping', file=sys.stderr)
                    continue
                print(f'slicing {stem} ...', file=sys.stderr, flush=True)
                rc, wall, cpu, rss, _ = baselines.timed(make_cmd(gcode), log_path)
                if rc != 0 or not os.path.exists(gcode):
                    print(f'  {slicer} failed (exit {rc}), see {log_path}', file=sys.stderr)
                    continue
                row['slice_wall_s'] = round(wall, 2)
                with open(times_path, 'w') as f:
                    f.write(f'{wall:.2f}\n')
            log = open(log_path, errors='replace').read() if os.path.exists(log_path) else ''
            if slicer == 'carve':
                stats_path = gcode[:-len('.gcode')] + '.stats.json'
                stats = json.load(open(stats_path)) if os.path.exists(stats_path) else {}
                row['slicer_time_s'] = stats.get('estimated_print_time_s')
                row['minima_unsupported'] = minima_unsupported(stats)
            elif slicer == 'prusa_grid':
                row['slicer_time_s'] = baselines.prusa_header(gcode).get('slicer_time_s')
            else:
                row['slicer_time_s'] = baselines.cura_log_figures(log).get('slicer_time_s')
            print(f'checking {stem} ...', file=sys.stderr, flush=True)
            result, check_wall = check(args.carve, gcode, check_mesh,
                                       os.path.join(args.work, stem + '.check'))
            with open(os.path.join(args.work, stem + '.check.json'), 'w') as f:
                json.dump(result, f, indent=1, sort_keys=True)
            types = result.get('material_by_type', {})
            row.update(
                material_percent=round(100 * result['extruded_volume_mm3'] / volume, 2),
                far_unsupported_mm2=round(result['far_unsupported_area_mm2'], 1),
                hanging_inside_mm2=round(result['hanging_inside_mm2'], 1),
                hanging_overhang_mm2=round(result['hanging_overhang_mm2'], 1),
                retractions=result['retractions'],
                travel_mm=round(result['travel_length_mm']),
                travel_outside_mm=round(result['travel_outside_mm']),
                wall_crossings=result['wall_crossings'],
                stick_time_s=round(result['stick_time_s']),
                outside_model_mm2=round(result['outside_area_mm2'], 1),
                mesh_offset_mm=','.join(f'{v:.2f}' for v in result.get('mesh_offset_mm', [])),
                material_by_type=';'.join(f'{k} {v["percent"]:.1f}' for k, v in
                                          sorted(types.items(), key=lambda kv: -kv[1]['percent'])),
                check_wall_s=round(check_wall, 2))
            rows.append(row)
            print('  ' + ', '.join(f'{k}={row.get(k)}' for k in (
                'slice_wall_s', 'material_percent', 'hanging_inside_mm2', 'hanging_overhang_mm2',
                'retractions')), file=sys.stderr, flush=True)


FIELDS = ['set', 'model', 'scale', 'slicer', 'model_volume_mm3', 'material_percent',
          'report_material_percent', 'far_unsupported_mm2', 'hanging_inside_mm2',
          'hanging_overhang_mm2', 'retractions', 'travel_mm', 'travel_outside_mm',
          'wall_crossings', 'stick_time_s', 'slicer_time_s', 'slice_wall_s', 'minima_unsupported',
          'outside_model_mm2', 'mesh_offset_mm', 'material_by_type', 'check_wall_s']
SLICER_NAMES = {'carve': 'carve', 'cura_lightning': 'Cura lightning 10 %',
                'prusa_grid': 'Prusa grid 15 %'}


def fmt(value, digits=None):
    if value is None or value == '':
        return '–'
    if digits is not None and isinstance(value, (int, float)):
        return f'{value:,.{digits}f}'
    return f'{value:,}' if isinstance(value, int) else str(value)


def minutes(seconds):
    return '–' if seconds is None else f'{seconds / 60:,.0f}'


def write_markdown(path, rows, args, meta):
    lines = [
        '# carve against CuraEngine lightning and PrusaSlicer grid, one measuring stick',
        '',
        f"Made by `bench/compare.sh{meta['argv']}` on {meta['started']} ({meta['cores']} cores, "
        f"load average {meta['load_before']:.1f} before, {meta['load_after']:.1f} after; "
        f"carve {meta['carve_version']} at {meta['commit']}, {meta['prusa']}, CuraEngine "
        f"{meta['cura']}). Every G-code measured by `carve check --mesh --json`.",
        '',
        'Hanging: extrusion more than 2 mm from anything printed on the layer below (mm², summed '
        'over layers), split into *inside* (over the model\'s own slice one layer down: the '
        'interior strategy\'s doing) and *overhang* (the model\'s own, which only supports fix). '
        'Retractions: moves that lower E, and G10. Travel outside: travel outside the model\'s '
        'slice grown by half a line width; crossings: travels that leave the slice and come back. '
        'Stick time: every move a trapezoid from rest to rest (1000 mm/s² extruding, 1500 '
        'travel), retractions at their F: one stick for all three, slower than any planner. Own '
        'estimate: what each slicer says (carve\'s stats, PrusaSlicer\'s header, CuraEngine\'s -v '
        'log). Slice s: wall time of the slicer process on this loaded machine. Minima '
        'unsupported: carve\'s stats JSON, when it has that figure.',
        '',
    ]
    if rows:
        worst = max(rows, key=lambda r: r['outside_model_mm2'])
        lines += [f"Placement of the mesh under each G-code, found by `carve check` from the "
                  f"extrusion's bounding box (offsets in compare.csv): the most extrusion outside "
                  f"the model beyond half a line width on any file is "
                  f"{worst['outside_model_mm2']:.1f} mm² ({worst['model']}, "
                  f"{SLICER_NAMES[worst['slicer']]}); a misplaced mesh would show thousands.", '']
    for name, title in (('default', 'At the models\' own size, carve at its defaults'),
                        ('table1', 'At the report\'s Table 1 size, carve --preset 2c0s')):
        subset = [r for r in rows if r['set'] == name]
        if not subset:
            continue
        lines += [f'## {title}', '',
                  '| model | slicer | material % | hanging inside mm² | hanging overhang mm² | '
                  'retractions | travel outside mm (crossings) | stick time min | own estimate min '
                  '| slice s | minima unsupported |',
                  '|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|']
        for r in subset:
            material = fmt(r['material_percent'], 1)
            if r['slicer'] == 'carve' and r.get('report_material_percent'):
                material += f" (report {r['report_material_percent']})"
            lines.append(
                f"| {r['model']} | {SLICER_NAMES[r['slicer']]} | {material} | "
                f"{fmt(r['hanging_inside_mm2'], 1)} | {fmt(r['hanging_overhang_mm2'], 1)} | "
                f"{fmt(r['retractions'])} | {fmt(r['travel_outside_mm'], 0)} "
                f"({fmt(r['wall_crossings'])}) | {minutes(r['stick_time_s'])} | "
                f"{minutes(r.get('slicer_time_s'))} | {fmt(r.get('slice_wall_s'), 2)} | "
                f"{fmt(r.get('minima_unsupported')) if r['slicer'] == 'carve' else ''} |")
        lines.append('')
    subset = [r for r in rows if r['set'] == 'default']
    if subset:
        lines += ['## This measure against the figures of issue #23 (carve f0a14a7)', '',
                  'measured here / in the issue; carve\'s own figures move with its commit.', '',
                  '| model | slicer | hanging inside mm² | far-unsupported mm² | retractions |',
                  '|---|---|---:|---:|---:|']
        for r in subset:
            cells = []
            for key in ('hanging_inside_mm2', 'far_unsupported_mm2', 'retractions'):
                ref = ISSUE_F0A14A7[key].get(r['slicer'], {}).get(r['model'])
                cells.append(f"{fmt(r[key], 0 if key != 'retractions' else None)} / {fmt(ref)}")
            lines.append(f"| {r['model']} | {SLICER_NAMES[r['slicer']]} | " + ' | '.join(cells)
                         + ' |')
        lines.append('')
    lines += ['## Material per feature (% of the extruded volume, from the ;TYPE: comments)', '',
              '| model | slicer | types |', '|---|---|---|']
    for r in rows:
        lines.append(f"| {r['model']} | {SLICER_NAMES[r['slicer']]} | "
                     f"{r['material_by_type'].replace(';', ', ')} |")
    lines.append('')
    with open(path, 'w') as f:
        f.write('\n'.join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--models', help='comma-separated model names [cat,elephant,fandisk,man,skull]')
    ap.add_argument('--sets', default='default,table1',
                    help='default (own size), table1 (skull x1.43, cat x1.47) [both]')
    ap.add_argument('--carve', default=os.path.join(ROOT, 'build', 'carve'),
                    help='the carve binary that slices and checks [build/carve]')
    ap.add_argument('--reuse', action='store_true',
                    help='re-measure the G-code already in the work dir, slice nothing')
    ap.add_argument('--work', default='/tmp/carve_compare', help='G-code and logs go here')
    ap.add_argument('--results', default=baselines.RESULTS)
    args = ap.parse_args()
    args.carve = os.path.abspath(args.carve)
    models = args.models.split(',') if args.models else DEFAULT_MODELS
    sets = args.sets.split(',')
    os.makedirs(args.work, exist_ok=True)
    os.makedirs(args.results, exist_ok=True)
    cores = len(os.sched_getaffinity(0))
    print(f'running on {cores} cores ({os.cpu_count()} in the machine)', file=sys.stderr)

    def output(cmd):
        try:
            return subprocess.run(cmd, capture_output=True, text=True, timeout=60, cwd=ROOT)
        except (OSError, subprocess.SubprocessError):
            return None

    version = output([args.carve, '--version'])
    commit = output(['git', 'rev-parse', '--short', 'HEAD'])
    meta = {
        'argv': ''.join(' ' + a for a in sys.argv[1:]),
        'started': f'{datetime.datetime.now():%Y-%m-%d %H:%M}',
        'cores': cores,
        'load_before': os.getloadavg()[0],
        'carve_version': version.stdout.strip().split()[-1] if version and version.stdout else '?',
        'commit': commit.stdout.strip() if commit else '?',
        'prusa': baselines.version(['prusa-slicer', '--help'], r'PrusaSlicer-[^ ]+'),
        'cura': baselines.version(['CuraEngine', 'help'], r'[0-9]+[.][0-9.]+'),
    }
    rows = []
    if 'default' in sets:
        run_set(args, 'default', models, rows)
    if 'table1' in sets:
        run_set(args, 'table1', [m for m in models if m in TABLE1], rows)
    meta['load_after'] = os.getloadavg()[0]

    base = os.path.join(args.results, 'compare')
    with open(base + '.csv', 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=FIELDS, extrasaction='ignore')
        w.writeheader()
        for r in rows:
            w.writerow(r)
    with open(base + '.json', 'w') as f:
        json.dump({'meta': meta, 'rows': rows}, f, indent=1)
    write_markdown(base + '.md', rows, args, meta)
    print(f'ran on {cores} cores; wrote {base}.md, .csv, .json', file=sys.stderr)


if __name__ == '__main__':
    main()
