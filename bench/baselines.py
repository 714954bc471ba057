#!/usr/bin/python3
"""Baselines: slice the shared models with PrusaSlicer and CuraEngine, time them, and judge every
G-code with carve's own analyser (src/check/gcode_analysis.cpp), as described in
shared/BASELINES.md.

    bench/baselines.sh                       # every model except skull_x4_400k, both slicers
    bench/baselines.sh --models cat,fandisk --slicers prusa
    bench/baselines.sh --reuse               # analyse G-code already in the work dir, no slicing

Writes bench/results/baselines.csv, bench/results/baselines.md and one analysis JSON per run in
bench/results/json/. G-code goes to /tmp/carve_baselines (it is large; never commit it).

CuraEngine evaluates none of the formulas of its setting definitions, so every derived setting is
computed here from fdmprinter.def.json (each "value" is a Python expression) and passed with -s,
for the global stack and again for extruder 0 (material_diameter lives there). Its G-code header
holds placeholders; the real time and volume are read from its -v log.
"""
import argparse
import builtins
import csv
import datetime
import glob
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS_DIR = os.path.normpath(os.path.join(ROOT, '..', 'shared', 'models'))
RESULTS = os.path.join(ROOT, 'bench', 'results')
CURA_DEFS = '/usr/share/cura/resources/definitions'

PRUSA_COMMON = [
    '--export-gcode', '--dont-arrange', '--bed-shape', '-150x-150,150x-150,150x150,-150x150',
    '--nozzle-diameter', '0.4', '--layer-height', '0.2', '--first-layer-height', '0.2',
    '--filament-diameter', '1.75', '--skirts', '0', '--brim-width', '0', '--gcode-flavor',
    'marlin2', '--top-solid-min-thickness', '0', '--bottom-solid-min-thickness', '0'
]
PRUSA_CONFIGS = {
    'hollow': ['--perimeters', '1', '--top-solid-layers', '2', '--bottom-solid-layers', '2',
               '--fill-density', '0%'],
    'lightning': ['--perimeters', '1', '--top-solid-layers', '2', '--bottom-solid-layers', '2',
                  '--fill-density', '10%', '--fill-pattern', 'lightning'],
    'grid': ['--perimeters', '2', '--top-solid-layers', '3', '--bottom-solid-layers', '3',
             '--fill-density', '15%', '--fill-pattern', 'grid'],
}
CURA_COMMON = dict(
    machine_width=300, machine_depth=300, machine_height=300, machine_center_is_zero=True,
    machine_nozzle_size=0.4, layer_height=0.2, layer_height_0=0.2, material_diameter=1.75,
    adhesion_type='none', support_enable=False, machine_start_gcode='G28 ;Home\nG92 E0')
CURA_CONFIGS = {
    'lightning': dict(wall_thickness=0.4, top_thickness=0.4, bottom_thickness=0.4,
                      infill_sparse_density=10, infill_pattern='lightning'),
    'grid': dict(wall_thickness=0.8, top_thickness=0.6, bottom_thickness=0.6,
                 infill_sparse_density=15, infill_pattern='grid'),
}


# ---------------------------------------------------------------------------------------------
# CuraEngine settings: evaluate the definition's formulas like the Cura front end does.

def _flatten(path):
    flat = {}

    def walk(node):
        for key, setting in node.items():
            flat[key] = setting
            walk(setting.get('children', {}))

    walk(json.load(open(path))['settings'])
    return flat


def cura_settings(overrides):
    """All settings of fdmprinter (+ fdmextruder) with formulas evaluated; returns (dict, errors)."""
    flat = _flatten(os.path.join(CURA_DEFS, 'fdmprinter.def.json'))
    for key, setting in _flatten(os.path.join(CURA_DEFS, 'fdmextruder.def.json')).items():
        flat.setdefault(key, setting)
    cache = dict(overrides)
    errors = []
    busy = set()

    class Env(dict):
        def __missing__(self, key):
            if key not in flat:
                raise KeyError(key)  # not a setting: let eval look in the globals
            return value(key)

    env_globals = {
        'math': math, '__builtins__': builtins,
        'extruderValue': lambda extruder, key: value(key),
        'extruderValues': lambda key: [value(key)],
        'resolveOrValue': lambda key: value(key),
        'defaultExtruderPosition': lambda: '0',
    }

    def value(key):
        if key in cache:
            return cache[key]
        setting = flat[key]
        result = setting.get('default_value')
        formula = setting.get('value')
        if isinstance(formula, str) and key not in busy:
            busy.add(key)
            try:
                result = eval(formula, env_globals, Env())
            except Exception as error:  # keep the default, say so
                errors.append((key, repr(error)))
            busy.discard(key)
        cache[key] = result
        return result

    for key, setting in flat.items():
        if setting.get('type') != 'category':
            value(key)
    return {k: v for k, v in cache.items() if k in flat and flat[k].get('type') != 'category'}, errors


def cura_args(overrides):
    settings, errors = cura_settings(overrides)
    args = []
    for key, val in sorted(settings.items()):
        if val is None:
            continue
        if isinstance(val, bool):
            text = 'true' if val else 'false'
        elif isinstance(val, (list, dict)):
            text = json.dumps(val)
        else:
            text = str(val)
        args += ['-s', f'{key}={text}']
    return args, errors


# ---------------------------------------------------------------------------------------------

def stl_triangles(path):
    """The triangles of an STL (binary or ASCII) as an (n, 3, 3) float64 array."""
    with open(path, 'rb') as f:
        data = f.read()
    if len(data) >= 84:
        count = struct.unpack_from('<I', data, 80)[0]
        if 84 + 50 * count == len(data):
            rec = np.frombuffer(data, dtype=np.dtype([('n', '<f4', 3), ('v', '<f4', (3, 3)),
                                                       ('a', '<u2')]), count=count, offset=84)
            return rec['v'].astype(np.float64)
    verts = [list(map(float, m.groups())) for m in re.finditer(
        rb'vertex\s+(\S+)\s+(\S+)\s+(\S+)', data)]
    return np.array(verts, dtype=np.float64).reshape(-1, 3, 3)


def stl_volume_mm3(path):
    """Signed volume of a closed STL, by the divergence theorem."""
    v = stl_triangles(path)
    return float(np.einsum('ij,ij->i', v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6)


def stl_bbox(path):
    """(min xyz, max xyz) of an STL's vertices."""
    v = stl_triangles(path).reshape(-1, 3)
    return v.min(axis=0), v.max(axis=0)


def timed(cmd, log_path):
    """Runs cmd under /usr/bin/time -v; returns (returncode, wall s, cpu s, peak RSS MB, log)."""
    time_path = log_path + '.time'
    with open(log_path, 'w') as log:
        rc = subprocess.call(['/usr/bin/time', '-v', '-o', time_path] + cmd, stdout=log,
                             stderr=subprocess.STDOUT)
    text = open(time_path).read()

    def field(name):
        m = re.search(re.escape(name) + r':\s*(.+)', text)
        return m.group(1).strip() if m else ''

    wall = 0.0
    for part in field('Elapsed (wall clock) time (h:mm:ss or m:ss)').split(':'):
        wall = wall * 60 + float(part or 0)
    cpu = float(field('User time (seconds)') or 0) + float(field('System time (seconds)') or 0)
    rss = float(field('Maximum resident set size (kbytes)') or 0) / 1024
    return rc, wall, cpu, rss, open(log_path, errors='replace').read()


class Analyser:
    """`carve check FILE --json` (build/carve; build it first)."""

    def __init__(self):
        carve = os.path.join(ROOT, 'build', 'carve')
        if not os.path.exists(carve):
            raise SystemExit(f'{carve} not found: build carve first (scripts/build.sh)')
        self.cmd = [carve, 'check']
        self.name = 'carve check'

    def run(self, gcode, log_path):
        rc, wall, cpu, rss, out = timed(self.cmd + [gcode, '--json'], log_path)
        if rc != 0:
            raise RuntimeError(f'analyser failed on {gcode}: {out[-500:]}')
        return json.loads(out[out.index('{'):]), wall, cpu


def prusa_header(gcode):
    """PrusaSlicer's own figures from the end of its G-code."""
    with open(gcode, 'rb') as f:
        f.seek(max(0, os.path.getsize(gcode) - 64 * 1024))
        tail = f.read().decode(errors='replace')
    out = {}
    m = re.search(r'; filament used \[cm3\] = ([\d.]+)', tail)
    if m:
        out['slicer_filament_mm3'] = float(m.group(1)) * 1000
    m = re.search(r'; estimated printing time \(normal mode\) = (.+)', tail)
    if m:
        secs = 0
        for num, unit in re.findall(r'(\d+)([dhms])', m.group(1)):
            secs += int(num) * {'d': 86400, 'h': 3600, 'm': 60, 's': 1}[unit]
        out['slicer_time_s'] = secs
    return out


def cura_log_figures(log):
    out = {}
    m = re.search(r'Print time \(s\): (\d+)', log)
    if m:
        out['slicer_time_s'] = int(m.group(1))
    m = re.search(r'Filament \(mm\^3\): (\d+)', log)
    if m:
        out['slicer_filament_mm3'] = float(m.group(1))
    return out


def version(cmd, pattern):
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
        m = re.search(pattern, out.stdout + out.stderr)
        return m.group(0) if m else '?'
    except (OSError, subprocess.SubprocessError):
        return 'not installed'


FIELDS = ['model', 'model_volume_mm3', 'slicer', 'config', 'slice_wall_s', 'slice_cpu_s',
          'slice_peak_rss_mb', 'gcode_mb', 'layers', 'extruded_volume_mm3', 'material_percent',
          'footprint_area_mm2', 'unsupported_percent', 'far_unsupported_percent',
          'mean_line_width_mm', 'slicer_time_s', 'slicer_filament_mm3', 'analyse_wall_s',
          'analyse_cpu_s']


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--models', help='comma-separated model names (default: all but skull_x4_400k)')
    ap.add_argument('--all', action='store_true', help='include skull_x4_400k')
    ap.add_argument('--slicers', default='prusa,cura')
    ap.add_argument('--work', default='/tmp/carve_baselines', help='G-code and logs go here')
    ap.add_argument('--reuse', action='store_true', help='analyse existing G-code, do not slice')
    ap.add_argument('--results', default=RESULTS)
    args = ap.parse_args()

    os.makedirs(args.work, exist_ok=True)
    os.makedirs(os.path.join(args.results, 'json'), exist_ok=True)
    paths = sorted(glob.glob(os.path.join(MODELS_DIR, '*.stl')))
    if args.models:
        wanted = args.models.split(',')
        paths = [p for p in paths if os.path.splitext(os.path.basename(p))[0] in wanted]
    elif not args.all:
        paths = [p for p in paths if 'skull_x4' not in p]
    slicers = args.slicers.split(',')
    have = {'prusa': shutil.which('prusa-slicer'), 'cura': shutil.which('CuraEngine')}
    if 'cura' in slicers and not os.path.exists(os.path.join(CURA_DEFS, 'fdmprinter.def.json')):
        print('CuraEngine definitions missing (apt-get install cura): skipping Cura',
              file=sys.stderr)
        have['cura'] = None
    analyser = Analyser()
    load_before = os.getloadavg()
    started = datetime.datetime.now()

    rows = []
    for model_path in paths:
        model = os.path.splitext(os.path.basename(model_path))[0]
        volume = stl_volume_mm3(model_path)
        jobs = []
        if 'prusa' in slicers and have['prusa']:
            for config, extra in PRUSA_CONFIGS.items():
                jobs.append(('prusa', config, lambda out, extra=extra: (
                    ['prusa-slicer'] + PRUSA_COMMON + extra + ['-o', out, model_path])))
        if 'cura' in slicers and have['cura']:
            for config, extra in CURA_CONFIGS.items():
                def cmd(out, extra=extra):
                    settings, errors = cura_args({**CURA_COMMON, **extra})
                    if errors:
                        print(f'  cura settings left at defaults: {errors}', file=sys.stderr)
                    return (['CuraEngine', 'slice', '-v', '-j',
                             os.path.join(CURA_DEFS, 'fdmprinter.def.json')] + settings +
                            ['-e0'] + settings + ['-l', model_path, '-o', out])
                jobs.append(('cura', config, cmd))
        for slicer, config, make_cmd in jobs:
            stem = f'{model}_{slicer}_{config}'
            gcode = os.path.join(args.work, stem + '.gcode')
            log_path = os.path.join(args.work, stem + '.log')
            row = {'model': model, 'model_volume_mm3': round(volume, 1), 'slicer': slicer,
                   'config': config}
            if args.reuse and os.path.exists(gcode):
                log = open(log_path, errors='replace').read() if os.path.exists(log_path) else ''
            else:
                print(f'slicing {stem} ...', file=sys.stderr, flush=True)
                rc, wall, cpu, rss, log = timed(make_cmd(gcode), log_path)
                if rc != 0 or not os.path.exists(gcode):
                    print(f'  {slicer} failed (exit {rc}), see {log_path}', file=sys.stderr)
                    continue
                row.update(slice_wall_s=round(wall, 2), slice_cpu_s=round(cpu, 2),
                           slice_peak_rss_mb=round(rss, 1))
            row.update(prusa_header(gcode) if slicer == 'prusa' else cura_log_figures(log))
            row['gcode_mb'] = round(os.path.getsize(gcode) / 1e6, 1)
            print(f'analysing {stem} ...', file=sys.stderr, flush=True)
            result, awall, acpu = analyser.run(gcode, os.path.join(args.work, stem + '.check'))
            with open(os.path.join(args.results, 'json', stem + '.json'), 'w') as f:
                json.dump(result, f, indent=1, sort_keys=True)
            row.update(layers=result['layers'],
                       extruded_volume_mm3=round(result['extruded_volume_mm3'], 1),
                       material_percent=round(100 * result['extruded_volume_mm3'] / volume, 2),
                       footprint_area_mm2=round(result['footprint_area_mm2'], 1),
                       unsupported_percent=round(result['unsupported_percent'], 3),
                       far_unsupported_percent=round(result['far_unsupported_percent'], 4),
                       mean_line_width_mm=round(result['mean_line_width_mm'], 3),
                       analyse_wall_s=round(awall, 2), analyse_cpu_s=round(acpu, 2))
            rows.append(row)
            print('  ' + ', '.join(f'{k}={row[k]}' for k in (
                'slice_wall_s', 'material_percent', 'far_unsupported_percent', 'analyse_wall_s')
                if k in row), file=sys.stderr, flush=True)

    with open(os.path.join(args.results, 'baselines.csv'), 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        for row in rows:
            w.writerow(row)
    write_markdown(args, rows, analyser.name, load_before, os.getloadavg(), started)


def write_markdown(args, rows, analyser_name, load_before, load_after, started):
    def cell(model, slicer, config, what):
        for r in rows:
            if (r['model'], r['slicer'], r['config']) == (model, slicer, config):
                if what == 'pair':
                    return f"{r['material_percent']:.1f} % · {r['far_unsupported_percent']:.3f} %"
                value = r.get(what)
                return '' if value is None else f'{value:g}'
        return '–'

    models = sorted({r['model'] for r in rows})
    lines = [
        '# Baselines measured by bench/baselines.py',
        '',
        f'Run {started:%Y-%m-%d %H:%M}; {version(["prusa-slicer", "--help"], r"PrusaSlicer-[^ ]+")}; '
        f'CuraEngine {version(["CuraEngine", "help"], r"[0-9]+[.][0-9.]+")}; '
        f'analyser: {analyser_name}; '
        f'load average {load_before[0]:.1f} before, {load_after[0]:.1f} after '
        f'({os.cpu_count()} cores; wall times of a loaded machine are not comparable with '
        'BASELINES.md, CPU seconds are closer).',
        '',
        'Settings and measuring method as in shared/BASELINES.md: 0.4 mm nozzle, 0.2 mm layers, '
        '1.75 mm filament, no supports/skirt/brim. Material = extruded volume read from the '
        'G-code / model volume (from the STL); far-unsupported = footprint of a layer farther '
        'than 2 mm from the footprint below, summed, / total footprint (rounded bead model).',
        '',
        '| model | hollow: material · far-unsup | Prusa lightning | Cura lightning | '
        'Prusa grid 15 % | Cura grid 15 % | slice s: Prusa grid / Cura grid |',
        '|---|---|---|---|---|---|---|',
    ]
    for m in models:
        lines.append(
            f"| {m} | {cell(m, 'prusa', 'hollow', 'pair')} | {cell(m, 'prusa', 'lightning', 'pair')}"
            f" | {cell(m, 'cura', 'lightning', 'pair')} | {cell(m, 'prusa', 'grid', 'pair')} | "
            f"{cell(m, 'cura', 'grid', 'pair')} | {cell(m, 'prusa', 'grid', 'slice_wall_s')} / "
            f"{cell(m, 'cura', 'grid', 'slice_wall_s')} |")
    lines += ['', '## Every run', '',
              '| model | slicer | config | slice wall s | slice CPU s | peak RSS MB | G-code MB | '
              'layers | material % | unsupported % (r 0.2) | far-unsup % | slicer est. time s | '
              'slicer filament mm3 | analyser wall s |',
              '|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|']
    for r in rows:
        lines.append('| ' + ' | '.join(str(r.get(k, '')) for k in (
            'model', 'slicer', 'config', 'slice_wall_s', 'slice_cpu_s', 'slice_peak_rss_mb',
            'gcode_mb', 'layers', 'material_percent', 'unsupported_percent',
            'far_unsupported_percent', 'slicer_time_s', 'slicer_filament_mm3',
            'analyse_wall_s')) + ' |')
    with open(os.path.join(args.results, 'baselines.md'), 'w') as f:
        f.write('\n'.join(lines) + '\n')


if __name__ == '__main__':
    main()
