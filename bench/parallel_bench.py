#!/usr/bin/env python3
"""carve's data-parallel pipeline (#21): wall time against CuraEngine's grid 15 %, the speed-up
from one core to two, and the serial fraction from CARVE_PROFILE, in one run.

    /usr/bin/python3 bench/parallel_bench.py               # every shared model, + Table 1 sizes
    /usr/bin/python3 bench/parallel_bench.py --repeat 1 --models fandisk

Writes bench/results/parallel.md and parallel.json. Per model, carve (default threads: every
core) and CuraEngine grid 15 % are run in turn, --repeat rounds, medians kept. skull and
fandisk are then run under `taskset -c 0` and `taskset -c 0,1` in turn, and as two
single-thread runs at once, one on each core: the machine's own ceiling for the speed-up (2.0 when
its two cores do not slow each other down; a virtual machine's may share one physical core or
its caches with a neighbour, and the ceiling was seen to move from 1.9 to 1.4 within the same
hour). The serial fraction is
carve's own measure (CARVE_PROFILE=1): mesh loading, the critical path of the pipeline's
filters and the assembly after it (G-code, resin zip, HTML), over the CPU of every filter. The
machine's core count and load average before and after are printed with the figures: on a shared machine wall-time
ratios mean little unless the load was low.
"""

import argparse
import datetime
import json
import os
import re
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import baselines as bl  # noqa: E402  (CuraEngine's settings, the timing helper)
from carve_bench import cura_grid  # noqa: E402
from compare import TABLE1, scaled_stl  # noqa: E402

MODELS = ['cat', 'elephant', 'fandisk', 'man', 'skull']
TASKSET_MODELS = ['skull', 'fandisk']


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def load_average():
    return open('/proc/loadavg').read().split()[:3]


def carve_run(carve, model_path, gcode, log_path, extra=(), prefix=(), env=None):
    cmd = list(prefix) + [carve, 'slice', model_path, '-o', gcode, '-q', '--no-bed-check'] + list(extra)
    if env:
        old = {k: os.environ.get(k) for k in env}
        os.environ.update(env)
    try:
        rc, wall, cpu, rss, out = bl.timed(cmd, log_path)
    finally:
        if env:
            for k, v in old.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
    if rc != 0:
        raise RuntimeError(f'carve failed: {" ".join(cmd)}: {out[-500:]}')
    return wall, cpu, rss, out


def pair_wall(carve, model_path, work, extra=()):
    """Two single-thread runs at once, on cores 0 and 1: the wall time until both are done."""
    procs = []
    start = time.monotonic()
    for core in ('0', '1'):
        cmd = ['taskset', '-c', core, carve, 'slice', model_path, '-o',
               os.path.join(work, f'pair{core}.gcode'), '-q', '--no-bed-check', '--threads', '1']
        procs.append(subprocess.Popen(cmd + list(extra), stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL))
    for p in procs:
        if p.wait() != 0:
            raise RuntimeError('carve failed in the pair run')
    return time.monotonic() - start


def profile_figures(out):
    m = re.search(r'serial: load ([\d.]+) \+ pipeline critical path ([\d.]+) \+ assembly '
                  r'([\d.]+) = ([\d.]+) s of ([\d.]+) s CPU: serial fraction ([\d.]+) %', out)
    a = re.search(r'Amdahl: ([\d.]+)x on 2 cores, ([\d.]+)x on 8, ([\d.]+)x on 16 \(ran on (\d+)', out)
    longest = max(((float(t), n.strip()) for n, t, kind in
                   re.findall(r'^  (.{12}) +([\d.]+)  (serial|parallel)$', out, re.M)
                   if kind == 'serial'), default=(0, ''))
    if not m or not a:
        return {}
    return dict(load_s=float(m.group(1)), critical_path_s=float(m.group(2)),
                assembly_s=float(m.group(3)), serial_s=float(m.group(4)),
                work_s=float(m.group(5)), serial_percent=float(m.group(6)),
                amdahl_2=float(a.group(1)), amdahl_8=float(a.group(2)),
                amdahl_16=float(a.group(3)), threads=int(a.group(4)),
                longest_serial_filter=longest[1], longest_serial_filter_s=longest[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--carve', default=os.path.join(bl.ROOT, 'build', 'carve'))
    # The shared models, then those the report's Table 1 prints at another size, at that size.
    table1 = [f'{m}_x{scale:g}' for m, (scale, _) in sorted(TABLE1.items())]
    ap.add_argument('--models', default=','.join(MODELS + table1))
    ap.add_argument('--repeat', type=int, default=3)
    ap.add_argument('--work', default='/tmp/carve_parallel_bench')
    ap.add_argument('--no-cura', action='store_true')
    ap.add_argument('--out', default='parallel', help='results name in bench/results [parallel]')
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    started = datetime.datetime.utcnow()
    load_before = load_average()
    cores = os.cpu_count()
    usable = len(os.sched_getaffinity(0))
    log(f'{cores} cores ({usable} usable), load average {" ".join(load_before)}')
    cura_settings = None
    if not args.no_cura:
        cura_settings, errors = bl.cura_args({**bl.CURA_COMMON, **bl.CURA_CONFIGS['grid']})
        if errors:
            log(f'cura settings left at defaults: {errors}')

    rows = []
    for name in args.models.split(','):
        base, _, scale_text = name.partition('_x')
        scale = float(scale_text) if scale_text else 1.0
        model_path = os.path.join(bl.MODELS_DIR, base + '.stl')
        extra = []
        cura_mesh = model_path
        if scale != 1:
            extra = ['--scale', f'{scale:g}', '--preset', '2c0s']  # as bench/compare.py's table1
            cura_mesh = os.path.join(args.work, f'{name}.stl')
            if not os.path.exists(cura_mesh):
                scaled_stl(model_path, scale, cura_mesh)
        gcode = os.path.join(args.work, name + '.gcode')
        runs = {'carve': [], 'cura': []}
        for rep in range(args.repeat):
            log(f'{name}: carve ({rep + 1}/{args.repeat}) ...')
            wall, cpu, rss, _ = carve_run(args.carve, model_path, gcode,
                                          os.path.join(args.work, name + '.log'), extra)
            runs['carve'].append((wall, cpu))
            if cura_settings is not None:
                log(f'{name}: CuraEngine grid 15 % ({rep + 1}/{args.repeat}) ...')
                c = cura_grid(cura_mesh, name, args.work, cura_settings)
                runs['cura'].append((c['wall'], c['cpu']))
        row = dict(model=name,
                   carve_wall_s=statistics.median(w for w, _ in runs['carve']),
                   carve_cpu_s=statistics.median(c for _, c in runs['carve']))
        if runs['cura']:
            row.update(cura_wall_s=statistics.median(w for w, _ in runs['cura']),
                       cura_cpu_s=statistics.median(c for _, c in runs['cura']))
            row['wall_ratio_cura'] = row['carve_wall_s'] / max(row['cura_wall_s'], 1e-9)
        log(f'{name}: CARVE_PROFILE=1 ...')
        _, _, _, out = carve_run(args.carve, model_path, gcode,
                                 os.path.join(args.work, name + '.profile.log'), extra,
                                 env={'CARVE_PROFILE': '1'})
        row.update(profile_figures(out))
        if name in TASKSET_MODELS:
            one, two, pair = [], [], []
            for rep in range(args.repeat):
                log(f'{name}: taskset -c 0 / -c 0,1 ({rep + 1}/{args.repeat}) ...')
                one.append(carve_run(args.carve, model_path, gcode,
                                     os.path.join(args.work, name + '.c0.log'), extra,
                                     prefix=['taskset', '-c', '0'])[0])
                two.append(carve_run(args.carve, model_path, gcode,
                                     os.path.join(args.work, name + '.c01.log'), extra,
                                     prefix=['taskset', '-c', '0,1'])[0])
                if usable >= 2:
                    pair.append(pair_wall(args.carve, model_path, args.work, extra))
            row.update(one_core_wall_s=statistics.median(one), two_core_wall_s=statistics.median(two))
            row['speedup_1_to_2'] = row['one_core_wall_s'] / max(row['two_core_wall_s'], 1e-9)
            if pair:
                row['pair_wall_s'] = statistics.median(pair)
                row['ceiling_1_to_2'] = 2 * row['one_core_wall_s'] / max(row['pair_wall_s'], 1e-9)
        rows.append(row)
        log(json.dumps(row))

    load_after = load_average()
    commit = subprocess.run(['git', '-C', bl.ROOT, 'rev-parse', '--short', 'HEAD'],
                            capture_output=True, text=True).stdout.strip()
    info = dict(started_utc=started.strftime('%Y-%m-%d %H:%M'), cores=cores, usable_cores=usable,
                load_before=load_before, load_after=load_after, commit=commit,
                repeat=args.repeat, rows=rows)
    json.dump(info, open(os.path.join(bl.RESULTS, args.out + '.json'), 'w'), indent=1)

    def f(row, key, spec='.2f'):
        return format(row[key], spec) if key in row else '-'

    md = [f'# carve on every core (#21)', '',
          f'One run of `bench/parallel_bench.py` at {info["started_utc"]} UTC from {commit}, on '
          f'{cores} cores ({usable} usable), load average {" ".join(load_before)} before and '
          f'{" ".join(load_after)} after; medians of {args.repeat} rounds, carve (default '
          f'threads) and CuraEngine grid 15 % in turn.', '',
          '| model | carve wall / CPU s | Cura grid wall / CPU s | carve / Cura wall | '
          '1 core / 2 cores wall s | speed-up | machine ceiling | serial % | '
          'longest serial filter s | Amdahl 8 / 16 cores |',
          '|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|']
    for r in rows:
        md.append(f"| {r['model']} | {f(r, 'carve_wall_s')} / {f(r, 'carve_cpu_s')} | "
                  f"{f(r, 'cura_wall_s')} / {f(r, 'cura_cpu_s')} | **{f(r, 'wall_ratio_cura')}** | "
                  f"{f(r, 'one_core_wall_s')} / {f(r, 'two_core_wall_s')} | "
                  f"**{f(r, 'speedup_1_to_2')}** | {f(r, 'ceiling_1_to_2')} | "
                  f"{f(r, 'serial_percent', '.1f')} | "
                  f"{r.get('longest_serial_filter', '')} {f(r, 'longest_serial_filter_s', '.3f')} | "
                  f"{f(r, 'amdahl_8')} / {f(r, 'amdahl_16')} |")
    md += ['', 'Serial % = (mesh loading + critical path of the pipeline + assembly: G-code, '
           'resin zip, HTML) / CPU of the whole run, from `CARVE_PROFILE=1` (thread CPU per layer and filter); '
           'Amdahl = 1 / (s + (1 - s) / n). Machine ceiling = 2 x (1-core wall) / (wall of two '
           'single-thread runs at once, one per core): what two cores give two independent jobs '
           'here, the most any program could gain.', '']
    open(os.path.join(bl.RESULTS, args.out + '.md'), 'w').write('\n'.join(md))
    print('\n'.join(md))


if __name__ == '__main__':
    main()
