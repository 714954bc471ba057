#!/usr/bin/python3
"""Times the hostile cases of issue #38 and their peak memory, each alone under a time limit.

Usage: nice /usr/bin/python3 bench/hostile_bench.py [--carve build/carve] [--limit 300]
Writes a Markdown table to stdout (bench/results/hostile.md holds a run). Inputs are made in a
scratch folder; nothing outside it is read but the carve binary.
"""
import argparse
import os
import shutil
import struct
import subprocess
import time
import tempfile
import zipfile

import numpy as np


def write_stl(path, tris):
    tris = np.asarray(tris, dtype=np.float32).reshape(-1, 3, 3)
    rec = np.zeros(len(tris), dtype=[('n', '<f4', 3), ('v', '<f4', (3, 3)), ('a', '<u2')])
    rec['v'] = tris
    with open(path, 'wb') as f:
        f.write(b'\0' * 80 + struct.pack('<I', len(tris)))
        f.write(rec.tobytes())


def box(x0, y0, z0, x1, y1, z1):
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    f = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
         (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]
    return [[v[a], v[b], v[c]] for a, b, c in f]


def zigzag(path, teeth, height):
    # A comb: 2*teeth vertices on its toothed side, a prism `height` mm tall (closed: the caps
    # are strips down to the straight side, which shares each cap vertex).
    n = 2 * teeth
    xs = np.linspace(0, 200, n)
    ys = np.where(np.arange(n) % 2 == 0, 10.0, 10.5)
    tris = []
    P = np.stack([xs, ys], 1)
    Q = np.stack([xs, np.zeros(n)], 1)
    for z, flip in ((0.0, True), (height, False)):
        a = np.concatenate([P[:-1], np.full((n - 1, 1), z)], 1)
        b = np.concatenate([P[1:], np.full((n - 1, 1), z)], 1)
        c = np.concatenate([Q[:-1], np.full((n - 1, 1), z)], 1)
        d = np.concatenate([Q[1:], np.full((n - 1, 1), z)], 1)
        t1 = np.stack([a, c, b], 1) if not flip else np.stack([a, b, c], 1)
        t2 = np.stack([c, d, b], 1) if not flip else np.stack([c, b, d], 1)
        tris += [t1, t2]
    # Sides: the toothed one, the straight one and the two ends.
    def wall(p0, p1):
        a = np.concatenate([p0, np.zeros((len(p0), 1))], 1)
        b = np.concatenate([p1, np.zeros((len(p1), 1))], 1)
        A = a.copy(); A[:, 2] = height
        B = b.copy(); B[:, 2] = height
        return [np.stack([a, b, B], 1), np.stack([a, B, A], 1)]
    tris += wall(P[1:], P[:-1])
    tris += wall(Q[:-1], Q[1:])
    tris += wall(Q[:1], P[:1])
    tris += wall(P[-1:], Q[-1:])
    write_stl(path, np.concatenate(tris))


def threemf(path, items):
    verts = ''.join(f'<vertex x="{x}" y="{y}" z="{z}"/>' for x in (0, 1) for y in (0, 1) for z in (0, 1))
    f = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4), (2, 6, 7), (2, 7, 3),
         (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
    tri = ''.join(f'<triangle v1="{a}" v2="{b}" v3="{c}"/>' for a, b, c in f)
    build = ''.join(f'<item objectid="1" transform="1 0 0 0 1 0 0 0 1 {(i % 100) * 2} {(i // 100) * 2} 0"/>'
                    for i in range(items))
    model = ('<?xml version="1.0"?><model unit="millimeter" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">'
             f'<resources><object id="1" type="model"><mesh><vertices>{verts}</vertices>'
             f'<triangles>{tri}</triangles></mesh></object></resources><build>{build}</build></model>')
    rels = ('<?xml version="1.0"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
            '<Relationship Target="/3D/3dmodel.model" Id="r0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>')
    with zipfile.ZipFile(path, 'w', zipfile.ZIP_DEFLATED) as z:
        z.writestr('_rels/.rels', rels)
        z.writestr('3D/3dmodel.model', model)
        z.writestr('[Content_Types].xml', '<?xml version="1.0"?><Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/></Types>')


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--carve', default=os.path.join(os.path.dirname(__file__), '..', 'build', 'carve'))
    ap.add_argument('--limit', type=float, default=300)
    ap.add_argument('--only', default='')
    a = ap.parse_args()
    carve = os.path.abspath(a.carve)
    work = tempfile.mkdtemp(prefix='hostile_bench_')
    cases = []
    g = os.path.join(work, 'deep.gcode')
    open(g, 'w').write('G90\nM83\nG1 Z0.2 F600\nG1 X10 Y10 E1\nG1 Z-1e9\nG1 X20 E1\nG1 Z0.4\nG1 X10 E1\n')
    cases.append(('check: one move to Z -1e9 (90 bytes)', [carve, 'check', g]))
    g = os.path.join(work, 'rev.gcode')
    with open(g, 'w') as f:
        f.write('G90\nM83\nG1 F6000\n')
        for i in range(200000):
            f.write(f'G1 Z{0.4 if i % 2 else 0.2}\nG1 X10 Y10\nG1 X12 Y10 E0.1\n')
    cases.append(('check: 200,000 Z reversals', [carve, 'check', g]))
    m = os.path.join(work, 'items.3mf')
    threemf(m, 10000)
    cases.append((f'slice: 3MF of 10,000 build items ({os.path.getsize(m) // 1024} kB)',
                  [carve, 'slice', m, '-q', '--no-bed-check', '-o', os.path.join(work, 'i.gcode')]))
    cases.append(('slice: /dev/zero', [carve, 'slice', '/dev/zero', '-q', '-o', os.path.join(work, 'z.gcode')]))
    z = os.path.join(work, 'zigzag.stl')
    zigzag(z, 400000, 30)
    cases.append(('slice: 800,000-vertex zig-zag, 30 mm', [carve, 'slice', z, '-q', '-o', os.path.join(work, 'zz.gcode')]))
    z = os.path.join(work, 'comb.stl')
    zigzag(z, 20000, 2)
    cases.append(('slice: 40,000-vertex comb within the limits, 2 mm', [carve, 'slice', z, '-q', '-o', os.path.join(work, 'cb.gcode')]))
    c = os.path.join(work, 'cube1000.stl')
    write_stl(c, box(0, 0, 0, 1000, 1000, 1000))
    cases.append(('slice: 1000 mm cube, --no-bed-check (rib planner: the lead\'s)',
                  [carve, 'slice', c, '-q', '--no-bed-check', '--max-print-height', '10000', '-o', os.path.join(work, 'c.gcode')]))
    skull = os.path.join(os.path.dirname(__file__), '..', '..', 'shared', 'models', 'skull.stl')
    first_line = None
    if os.path.exists(skull):
        # Within the size limits (23,000 lines across, 60,000 layers) and days of work: what
        # matters is that the user sees progress within seconds, not a tenth of the layers later.
        first_line = ('slice: skull x100 (7.5 x 10.5 x 12 m), time to the first progress line',
                      [carve, 'slice', skull, '--scale', '100', '--no-bed-check', '-o', os.path.join(work, 's.gcode')])
    print(f'carve: {carve}; limit {a.limit:.0f} s each; peak RSS is the largest child so far\n')
    print('| case | exit | wall s | peak RSS MB | last stderr line |')
    print('|---|---|---|---|---|')
    for name, cmd in cases:
        if a.only and a.only not in name:
            continue
        # Each case in a fresh child of its own so ru_maxrss is its own.
        r = subprocess.run(['/usr/bin/time', '-f', '%e %M', '--'] + ['timeout', str(int(a.limit))] + cmd,
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        lines = r.stderr.decode(errors='replace').strip().splitlines()
        wall, rss = lines[-1].split()[-2:] if lines else ('?', '?')
        msg = next((l for l in reversed(lines[:-1]) if l.startswith('carve')), '')
        status = 'timeout' if r.returncode == 124 else r.returncode
        print(f'| {name} | {status} | {wall} | {int(rss) / 1024:.0f} | {msg[:140]} |', flush=True)
    if first_line and (not a.only or a.only in first_line[0]):
        start = time.monotonic()
        p = subprocess.Popen(first_line[1], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        seen = ''
        try:
            for line in p.stderr:
                seen = line.strip()
                if ' layers (' in line or time.monotonic() - start > a.limit:
                    break
            wall = time.monotonic() - start
            status = 'killed after it' if p.poll() is None else p.returncode
        finally:
            p.kill()
            p.wait()
        print(f'| {first_line[0]} | {status} | {wall:.2f} | | {seen[:140]} |', flush=True)
    shutil.rmtree(work)


if __name__ == '__main__':
    main()
