#!/usr/bin/python3
"""--orient auto (issue 48): each shared model turned 90 degrees about x (a rotated STL written
with numpy), then sliced with `--orient auto --support auto`, against the best of the six
axis-aligned orientations of that turned model sliced by hand (each written as its own STL and
sliced with `--support auto` at the same settings). Figures: the material of the run --orient
auto chose and of the best by hand, the orientation each picked, and the time --orient auto
spent choosing as a ratio of one slice (the turned model sliced as given). Writes
bench/results/orient.md and .json; whatever follows the line `<!-- notes -->` in the existing
orient.md is kept.

    bench/orient.py [--carve build/carve] [--models cat,skull] [--work /tmp/carve_orient]
"""
import argparse
import datetime
import json
import os
import resource
import struct
import subprocess
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = os.environ.get('CARVE_SHARED_MODELS', os.path.join(ROOT, '..', 'shared', 'models'))
SHARED = ['cat', 'elephant', 'fandisk', 'man', 'skull']
NOTES = '<!-- notes -->'


def read_stl(path):
    """The triangles of a binary or ASCII STL as an (n, 3, 3) array."""
    data = open(path, 'rb').read()
    if len(data) >= 84:
        n = struct.unpack_from('<I', data, 80)[0]
        if 84 + 50 * n == len(data):
            rec = np.frombuffer(data, dtype=np.dtype([('n', '<f4', 3), ('v', '<f4', (3, 3)),
                                                      ('a', '<u2')]), count=n, offset=84)
            return rec['v'].astype(np.float64)
    vs = [list(map(float, line.split()[1:4])) for line in data.decode('ascii', 'replace').splitlines()
          if line.strip().startswith('vertex')]
    return np.array(vs, dtype=np.float64).reshape(-1, 3, 3)


def write_stl(path, tris):
    rec = np.zeros(len(tris), dtype=np.dtype([('n', '<f4', 3), ('v', '<f4', (3, 3)),
                                              ('a', '<u2')]))
    rec['v'] = tris
    with open(path, 'wb') as out:
        out.write(b'\0' * 80)
        out.write(struct.pack('<I', len(tris)))
        out.write(rec.tobytes())


def rot(axis, deg):
    a = np.radians(deg)
    c, s = np.cos(a), np.sin(a)
    return {'x': np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            'y': np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])}[axis]


# The six orientations by hand, named as carve names them (the model's axis turned onto the bed).
SIX = [('as given', None), ('x+180', ('x', 180)), ('x+90', ('x', 90)), ('x-90', ('x', -90)),
       ('y+90', ('y', 90)), ('y-90', ('y', -90))]


def slice_stats(carve, stl, work, name, extra):
    gcode, stats = os.path.join(work, name + '.gcode'), os.path.join(work, name + '.json')
    start = time.monotonic()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run([carve, 'slice', stl, '-o', gcode, '--stats', stats, '--support', 'auto',
                        '-q'] + extra, capture_output=True, text=True)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if r.returncode != 0:
        return {'refused': r.stderr.strip().splitlines()[-1] if r.stderr.strip() else 'failed',
                'wall_s': wall, 'cpu_s': cpu}
    j = json.load(open(stats))
    j['wall_s'] = wall
    j['cpu_s'] = cpu
    return j


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--carve', default=os.path.join(ROOT, 'build', 'carve'))
    ap.add_argument('--models', default=','.join(SHARED))
    ap.add_argument('--work', default='/tmp/carve_orient')
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    rows = []
    for model in args.models.split(','):
        src = os.path.join(MODELS, model + '.stl')
        if not os.path.exists(src):
            print(f'{model}: {src} missing, skipped')
            continue
        turned = read_stl(src) @ rot('x', 90).T
        turned_stl = os.path.join(args.work, model + '_x90.stl')
        write_stl(turned_stl, turned)
        by_hand = []
        for name, r in SIX:
            tris = turned if r is None else turned @ rot(*r).T
            stl = os.path.join(args.work, f'{model}_x90_{name.replace(" ", "_")}.stl')
            write_stl(stl, tris)
            s = slice_stats(args.carve, stl, args.work, os.path.basename(stl)[:-4], [])
            by_hand.append({'name': name, 'material_mm3': s.get('extruded_volume_mm3'),
                            'time_s': s.get('estimated_print_time_s'),
                            'processing_s': s.get('processing_time_s'), 'cpu_s': s.get('cpu_s'),
                            'refused': s.get('refused')})
        fits = [b for b in by_hand if b['material_mm3'] is not None]
        best = min(fits, key=lambda b: b['material_mm3'])
        one_slice = by_hand[0]['processing_s']
        one_slice_cpu = by_hand[0]['cpu_s']
        auto = slice_stats(args.carve, turned_stl, args.work, model + '_auto', ['--orient', 'auto'])
        o = auto['orientation']
        row = {'model': model, 'by_hand': by_hand, 'best_by_hand': best['name'],
               'best_by_hand_mm3': best['material_mm3'], 'as_given_mm3': by_hand[0]['material_mm3'],
               'auto_chosen': o['chosen']['description'], 'auto_mm3': auto['extruded_volume_mm3'],
               'auto_time_s': auto['estimated_print_time_s'], 'choice_s': o['choice_time_s'],
               'candidates': len(o['candidates']), 'one_slice_s': one_slice,
               'choice_cpu_s': o['choice_cpu_s'], 'one_slice_cpu_s': one_slice_cpu,
               'given_up': sum(1 for c in o['candidates'] if c.get('given_up')),
               'auto_processing_s': auto['processing_time_s']}
        row['auto_vs_best'] = row['auto_mm3'] / row['best_by_hand_mm3']
        row['choice_ratio'] = row['choice_s'] / one_slice
        row['choice_cpu_ratio'] = row['choice_cpu_s'] / one_slice_cpu
        rows.append(row)
        print(f"{model}: auto {row['auto_chosen']} {row['auto_mm3']:.0f} mm3, best by hand "
              f"{best['name']} {best['material_mm3']:.0f} mm3, choice {row['choice_s']:.2f} s = "
              f"{row['choice_ratio']:.1f} slices; CPU {row['choice_cpu_s']:.2f} s = "
              f"{row['choice_cpu_ratio']:.2f} slices")
    out = os.path.join(ROOT, 'bench', 'results', 'orient')
    json.dump(rows, open(out + '.json', 'w'), indent=1)
    rev = subprocess.run(['git', '-C', ROOT, 'rev-parse', '--short', 'HEAD'], capture_output=True,
                         text=True).stdout.strip()
    notes = ''
    if os.path.exists(out + '.md'):
        text = open(out + '.md').read()
        if NOTES in text:
            notes = text[text.index(NOTES):]
    with open(out + '.md', 'w') as md:
        md.write('# --orient auto against the best axis-aligned orientation by hand\n\n')
        md.write(f'`nice /usr/bin/python3 bench/orient.py` at {rev}, '
                 f'{datetime.date.today().isoformat()}, on a shared 2-core machine. Each shared '
                 'model turned 90 degrees about x, sliced with `--orient auto --support auto`; '
                 'by hand: the six axis-aligned orientations of the turned model, each sliced '
                 'with `--support auto`. Material is the whole run\'s extruded volume, supports '
                 'included (cm³). Choice CPU: the CPU time (user + system, every thread) '
                 '--orient auto spent choosing (stats `orientation.choice_cpu_s`), and that as a '
                 'multiple of the CPU time (user + system, from the process\'s rusage) of one '
                 'slice of the turned model as given: the figure the machine\'s load moves least. '
                 'Wall: the same for the wall times (`choice_time_s` against '
                 '`processing_time_s`), which the load of a shared machine moves a lot.\n\n')
        md.write('| model | as turned cm³ | best by hand | cm³ | --orient auto chose | cm³ | '
                 'auto / best | candidates | given up | choice CPU s | one slice CPU s | '
                 'choice / slice (CPU) | choice / slice (wall) |\n')
        md.write('|---|---:|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n')
        for r in rows:
            md.write(f"| {r['model']} | {r['as_given_mm3'] / 1000:.2f} | {r['best_by_hand']} | "
                     f"{r['best_by_hand_mm3'] / 1000:.2f} | {r['auto_chosen']} | "
                     f"{r['auto_mm3'] / 1000:.2f} | {r['auto_vs_best']:.3f} | {r['candidates']} | "
                     f"{r['given_up']} | {r['choice_cpu_s']:.2f} | {r['one_slice_cpu_s']:.2f} | "
                     f"{r['choice_cpu_ratio']:.2f} | {r['choice_ratio']:.1f} |\n")
        md.write('\nThe six by hand (cm³ of material, estimated print time in minutes):\n\n')
        md.write('| model | ' + ' | '.join(n for n, _ in SIX) + ' |\n')
        md.write('|---|' + '---:|' * len(SIX) + '\n')
        for r in rows:
            cells = [f"{b['material_mm3'] / 1000:.2f} / {b['time_s'] / 60:.0f}"
                     if b['material_mm3'] is not None else 'does not fit' for b in r['by_hand']]
            md.write(f"| {r['model']} | " + ' | '.join(cells) + ' |\n')
        if notes:
            md.write('\n' + notes)
    print('wrote', out + '.md')


if __name__ == '__main__':
    main()
