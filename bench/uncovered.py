#!/usr/bin/python3
"""Uncovered area (issue 47): how much of the model each slicer leaves unprinted, every G-code
measured the same way by `carve check --mesh --json` (uncovered_mm2, uncovered_percent,
largest_uncovered; the definitions in docs/check.md).

Slices the shared models (cat, elephant, fandisk, man, skull) and the thin shapes of
bench/thin_shapes.py (fins, slots, vase, lettering) with carve at its defaults, PrusaSlicer 2.5
with its classic perimeter generator (thin-wall detection on) and with Arachne, both 1 perimeter
0 % infill 2/2 (bench/baselines.py's "hollow" command line), and CuraEngine 4.13 1 wall,
lightning 10 %, 2/2 (bench/baselines.py's "lightning"), and writes bench/results/uncovered.md
and .json.

    bench/uncovered.py                                  # everything; peers' G-code cached in --work
    bench/uncovered.py --only carve --carve /path/to/carve   # rerun carve's rows only
    bench/uncovered.py --models fins,cat

The peers' G-code does not change: it is kept in --work (default /tmp/carve_uncovered) and
reused; only its check is rerun. --only keeps the other slicers' rows as the last results JSON
has them. Whatever follows the line `<!-- notes -->` in the existing uncovered.md is kept.
"""
import argparse
import datetime
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import baselines  # noqa: E402
import printability  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = ['cat', 'elephant', 'fandisk', 'man', 'skull']
THIN = ['fins', 'slots', 'vase', 'lettering']
SLICERS = ['carve', 'prusa_classic', 'prusa_arachne', 'cura']
NAMES = {'carve': 'carve', 'prusa_classic': 'Prusa classic', 'prusa_arachne': 'Prusa Arachne',
         'cura': 'Cura 4.13'}
NOTES = '<!-- notes -->'


def slice_cmd(slicer, carve, model_path, out):
    if slicer == 'carve':
        return [carve, 'slice', model_path, '-o', out, '-q']
    if slicer.startswith('prusa'):
        generator = (['--perimeter-generator', 'classic', '--thin-walls']
                     if slicer == 'prusa_classic' else ['--perimeter-generator', 'arachne'])
        return (['prusa-slicer'] + baselines.PRUSA_COMMON + baselines.PRUSA_CONFIGS['hollow'] +
                generator + ['-o', out, model_path])
    settings, errors = baselines.cura_args({**baselines.CURA_COMMON,
                                            **baselines.CURA_CONFIGS['lightning']})
    return (['CuraEngine', 'slice', '-v', '-j',
             os.path.join(baselines.CURA_DEFS, 'fdmprinter.def.json')] + settings + ['-e0'] +
            settings + ['-l', model_path, '-o', out])


def shown(cmd):
    """A command line as a person would type it (Cura's hundreds of -s settings elided)."""
    words, skip = [], False
    for w in cmd:
        if skip:
            skip = False
            continue
        if w == '-s':
            skip = True
            continue
        words.append(w)
    text = ' '.join(words)
    return text.replace(' -e0', ' -s KEY=VALUE... -e0 -s KEY=VALUE...') if '-e0' in words else text


def measure(args, model, model_path, slicer):
    row, c = printability.slice_and_check(args, model, model_path, slicer, slice_cmd)
    if c is None:
        return row
    u, big = c['uncovered'], c['largest_uncovered']
    row.update(
        uncovered_mm2=round(c['uncovered_mm2'], 2), uncovered_percent=round(c['uncovered_percent'], 5),
        slice_mm2=round(u['slice_mm2']), enclosed_mm2=round(u['enclosed_mm2']),
        deep_mm2=round(u['deep_mm2'], 1), layers_above_print=u['layers_above_print'],
        largest={k: round(big[k], 2) for k in ('area_mm2', 'z', 'x', 'y')},
        largest_layer=big['layer'], line_width_mm=round(u['line_width_mm'], 3),
        line_width_source=u['line_width_source'], wide_pieces=u['wide_pieces'],
        wide_layers=u['wide_layers'], wide_mm2=round(u['wide_mm2'], 2),
        material_percent=round(100 * c['extruded_volume_mm3'] /
                               baselines.stl_volume_mm3(model_path), 2),
        strict_failed=[f for f in c['printability']['failed_rules']
                       if f.startswith('model left unprinted')])
    return row


def write_results(args, rows, started, carve_version, paths):
    os.makedirs(args.results, exist_ok=True)
    with open(os.path.join(args.results, 'uncovered.json'), 'w') as f:
        json.dump({'carve': carve_version, 'run': started, 'rows': rows}, f, indent=1)
    by = {(r['model'], r['slicer']): r for r in rows}
    models = [m for m in SHARED + THIN if any(r['model'] == m for r in rows)]

    def cell(r):
        if r is None:
            return '–'
        if 'error' in r:
            return r['error']
        wide = f" · **{r['wide_pieces']} wide**" if r['wide_pieces'] else ''
        above = f" · {r['layers_above_print']} layers above" if r['layers_above_print'] else ''
        return f"{r['uncovered_mm2']:.1f} ({r['uncovered_percent']:.4f} %){wide}{above}"

    lines = [
        '# Uncovered area: the model left unprinted (issue 47)',
        '',
        f'Run {started} by `bench/uncovered.py`; {carve_version} at its defaults; PrusaSlicer '
        '2.5 1 perimeter, 0 % infill, 2/2, with its classic perimeter generator (`--thin-walls`) '
        'and with Arachne; CuraEngine 4.13 1 wall, lightning 10 %, 2/2 (bench/baselines.py). '
        'Every G-code measured by `carve check FILE --mesh MODEL --json` (docs/check.md), the mesh '
        'where that slicer put it (`--mesh-offset`, bench/printability.py placement()): each '
        "layer's model slice shrunk by 0.1 mm, minus the footprint (every extruding move widened "
        'to its line width), the pieces open to the surface (what printed lines enclose, the '
        'interior, is not counted). Cell: uncovered mm² over all layers (% of the shrunk '
        'slices); **N wide**: pieces that hold a disk one line wide, which `--strict` fails; '
        'N layers above: layers of the model above the G-code\'s last, counted whole.',
        '',
        '| model | ' + ' | '.join(NAMES[s] for s in SLICERS) + ' |',
        '|---|' + '---|' * len(SLICERS),
    ]
    for m in models:
        lines.append(f'| {m} | ' + ' | '.join(cell(by.get((m, s))) for s in SLICERS) + ' |')
    lines += ['', 'Largest uncovered piece (mm², layer z, x, y) and material (% of the model):', '']
    for m in models:
        parts = []
        for s in SLICERS:
            r = by.get((m, s))
            if r is None or 'error' in r:
                continue
            b = r['largest']
            parts.append(f"{NAMES[s]} {b['area_mm2']:.2f} at z {b['z']:.2f} "
                         f"({b['x']:.1f}, {b['y']:.1f}), material {r['material_percent']:.1f} %")
        lines.append(f'- {m}: ' + '; '.join(parts))
    lines += ['', 'Commands (MODEL.stl, OUT.gcode; the thin shapes written by '
              '`bench/thin_shapes.py DIR`):', '']
    for s in SLICERS:
        lines.append(f'    {shown(slice_cmd(s, "carve", "MODEL.stl", "OUT.gcode"))}')
    lines.append('    carve check OUT.gcode --mesh MODEL.stl --json')
    lines += ['', 'Check time per G-code (s): ' + ', '.join(
        f"{r['model']} {NAMES[r['slicer']]} {r['check_wall_s']}" for r in rows
        if 'check_wall_s' in r), '']
    md = os.path.join(args.results, 'uncovered.md')
    notes = ''
    if os.path.exists(md):
        old = open(md).read()
        if NOTES in old:
            notes = old[old.index(NOTES):]
    with open(md, 'w') as f:
        f.write('\n'.join(lines) + ('\n' + notes if notes else ''))
    print('\n'.join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--carve', default=os.path.join(ROOT, 'build', 'carve'))
    ap.add_argument('--work', default='/tmp/carve_uncovered')
    ap.add_argument('--results', default=os.path.join(ROOT, 'bench', 'results'))
    ap.add_argument('--models', help='comma-separated subset of ' + ','.join(SHARED + THIN))
    ap.add_argument('--only', help='comma-separated subset of ' + ','.join(SLICERS) +
                    "; the others' rows are kept from the last results JSON")
    args = ap.parse_args()
    args.carve = os.path.abspath(args.carve)
    os.makedirs(args.work, exist_ok=True)
    started = datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')
    carve_version = subprocess.run([args.carve, '--version'], capture_output=True,
                                   text=True).stdout.strip()
    commit = subprocess.run(['git', '-C', ROOT, 'rev-parse', '--short', 'HEAD'],
                            capture_output=True, text=True).stdout.strip()
    carve_version += f' ({commit})' if commit else ''
    paths = {m: os.path.join(baselines.MODELS_DIR, m + '.stl') for m in SHARED}
    paths = {m: p for m, p in paths.items() if os.path.exists(p)}
    thin_dir = os.path.join(args.work, 'thin')
    subprocess.run([sys.executable, os.path.join(ROOT, 'bench', 'thin_shapes.py'), thin_dir],
                   check=True, capture_output=True)
    paths.update({m: os.path.join(thin_dir, m + '.stl') for m in THIN})
    models = [m for m in SHARED + THIN if m in paths]
    if args.models:
        models = [m for m in models if m in args.models.split(',')]
    slicers = args.only.split(',') if args.only else SLICERS
    json_path = os.path.join(args.results, 'uncovered.json')
    old = json.load(open(json_path))['rows'] if os.path.exists(json_path) else []
    rows = []
    for m in models:
        for s in SLICERS:
            if s in slicers:
                row = measure(args, m, paths[m], s)
                print(json.dumps(row), file=sys.stderr, flush=True)
                rows.append(row)
    done = {(r['model'], r['slicer']) for r in rows}
    rows += [r for r in old if (r['model'], r['slicer']) not in done]
    order = {(m, s): i for i, (m, s) in enumerate((m, s) for m in SHARED + THIN for s in SLICERS)}
    rows.sort(key=lambda r: order.get((r['model'], r['slicer']), 1 << 30))
    write_results(args, rows, started, carve_version, paths)


if __name__ == '__main__':
    main()
