#!/usr/bin/python3
"""carve's performance and scale: the shared models against the baselines, and the report's
scalability study (section 6.1, figure 6).

    bench/carve_bench.sh                      # build carve, then everything below
    /usr/bin/python3 bench/carve_bench.py --carve build-x/carve [--quick] [--all]
        [--models cat,fandisk] [--scales 1,2,4,8] [--no-models] [--no-scaling] [--repeat 3]

1. Models: each shared model (skull_x4_400k only with --all) is sliced by carve with its defaults
   (2 covers, 0 shells, 6 cavities, 0.2 mm layers, 0.4 mm nozzle) under /usr/bin/time -v, and
   its G-code is judged by `carve check --json`. The machine is shared and its load changes by
   the minute, so the earlier baseline timings cannot be compared with a carve run made now:
   PrusaSlicer grid 15 % is re-timed right before carve and CuraEngine grid 15 % right after it,
   with the exact command lines of bench/baselines.py (imported), --repeat rounds in turn
   (default 3), keeping the median of each. Material and far-unsupported of
   the baselines come from bench/results/baselines.csv (the G-code does not change from run to
   run); estimated print times of the re-timed runs come from Prusa's G-code footer and Cura's -v
   log. Writes bench/results/carve_models.{csv,md}.
2. Scaling: fandisk at --scale 0.25*s, s = 1..10 (20 to 200 mm tall), 6 cavities; wall, CPU,
   peak RSS, layers, model and extruded volume; exponents alpha of R*s^alpha by log-log least
   squares. Writes bench/results/carve_scaling.{csv,md,json,png}.

G-code and logs go to --work (default /tmp/carve_bench); never commit them.
"""
import argparse
import csv
import datetime
import json
import os
import shutil
import subprocess
import statistics
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import baselines as bl  # noqa: E402  (the baseline command lines and the timing helper)

ROOT = bl.ROOT
RESULTS = bl.RESULTS
MODELS_DIR = bl.MODELS_DIR
QUICK_MODELS = ['fandisk', 'cat']
QUICK_SCALES = [1, 2, 4, 8]
BASE_SCALE = 0.25  # s = 1 is fandisk 20 mm tall, s = 10 is 200 mm


def log(msg):
    print(f'[{datetime.datetime.now():%H:%M:%S}] {msg}', file=sys.stderr, flush=True)


def load_baselines():
    path = os.path.join(RESULTS, 'baselines.csv')
    rows = {}
    if os.path.exists(path):
        for r in csv.DictReader(open(path)):
            rows[(r['model'], r['slicer'], r['config'])] = r
    return rows


def carve_slice(carve, model_path, stem, work, extra=()):
    gcode = os.path.join(work, stem + '.gcode')
    stats = os.path.join(work, stem + '.json')
    rc, wall, cpu, rss, out = bl.timed(
        [carve, 'slice', model_path, '-o', gcode, '--stats', stats, '-q', '--no-bed-check'] +
        list(extra), os.path.join(work, stem + '.log'))
    if rc != 0:
        raise RuntimeError(f'carve failed on {stem} (exit {rc}): {out[-500:]}')
    return gcode, json.load(open(stats)), wall, cpu, rss


def carve_check(carve, gcode, work, stem):
    rc, wall, cpu, rss, out = bl.timed([carve, 'check', gcode, '--json'],
                                       os.path.join(work, stem + '.check'))
    if rc != 0:
        raise RuntimeError(f'carve check failed on {gcode}: {out[-500:]}')
    return json.loads(out[out.index('{'):])


def prusa_grid(model_path, stem, work):
    gcode = os.path.join(work, stem + '_prusa_grid.gcode')
    cmd = (['prusa-slicer'] + bl.PRUSA_COMMON + bl.PRUSA_CONFIGS['grid'] +
           ['-o', gcode, model_path])
    rc, wall, cpu, rss, out = bl.timed(cmd, os.path.join(work, stem + '_prusa_grid.log'))
    if rc != 0 or not os.path.exists(gcode):
        raise RuntimeError(f'prusa-slicer failed on {stem}: {out[-500:]}')
    return dict(wall=wall, cpu=cpu, rss=rss, **bl.prusa_header(gcode))


def cura_grid(model_path, stem, work, settings):
    gcode = os.path.join(work, stem + '_cura_grid.gcode')
    cmd = (['CuraEngine', 'slice', '-v', '-j', os.path.join(bl.CURA_DEFS, 'fdmprinter.def.json')] +
           settings + ['-e0'] + settings + ['-l', model_path, '-o', gcode])
    rc, wall, cpu, rss, out = bl.timed(cmd, os.path.join(work, stem + '_cura_grid.log'))
    if rc != 0 or not os.path.exists(gcode):
        raise RuntimeError(f'CuraEngine failed on {stem}: {out[-500:]}')
    return dict(wall=wall, cpu=cpu, rss=rss, **bl.cura_log_figures(out))


MODEL_FIELDS = [
    'model', 'model_volume_mm3', 'load_before', 'carve_wall_s', 'carve_cpu_s', 'carve_peak_rss_mb',
    'carve_layers', 'carve_bridges', 'carve_extruded_mm3', 'carve_material_percent',
    'carve_unsupported_percent', 'carve_far_unsupported_percent', 'carve_far_unsupported_mm2',
    'carve_est_time_s',
    'prusa_grid_wall_s', 'prusa_grid_cpu_s', 'prusa_grid_peak_rss_mb', 'prusa_grid_est_time_s',
    'cura_grid_wall_s', 'cura_grid_cpu_s', 'cura_grid_peak_rss_mb', 'cura_grid_est_time_s',
    'wall_ratio_prusa', 'wall_ratio_cura', 'cpu_ratio_prusa', 'cpu_ratio_cura']


def run_models(args, carve, models):
    baselines = load_baselines()
    cura_settings = None
    have_prusa = shutil.which('prusa-slicer') is not None
    have_cura = (shutil.which('CuraEngine') is not None and
                 os.path.exists(os.path.join(bl.CURA_DEFS, 'fdmprinter.def.json')))
    if have_cura:
        cura_settings, errors = bl.cura_args({**bl.CURA_COMMON, **bl.CURA_CONFIGS['grid']})
        if errors:
            log(f'cura settings left at defaults: {errors}')
    rows = []
    for model in models:
        path = os.path.join(MODELS_DIR, model + '.stl')
        row = {'model': model, 'model_volume_mm3': round(bl.stl_volume_mm3(path), 1),
               'load_before': round(os.getloadavg()[0], 1)}
        # --repeat rounds, each PrusaSlicer, carve, CuraEngine in turn; the medians are kept,
        # since one run on a shared machine can be off by a third.
        runs = {'prusa': [], 'carve': [], 'cura': []}
        for rep in range(args.repeat):
            if have_prusa:
                log(f'{model}: PrusaSlicer grid 15 % ({rep + 1}/{args.repeat}) ...')
                runs['prusa'].append(prusa_grid(path, model, args.work))
            log(f'{model}: carve ({rep + 1}/{args.repeat}) ...')
            gcode, stats, wall, cpu, rss = carve_slice(carve, path, model + '_carve', args.work)
            runs['carve'].append(dict(wall=wall, cpu=cpu, rss=rss))
            if have_cura:
                log(f'{model}: CuraEngine grid 15 % ({rep + 1}/{args.repeat}) ...')
                runs['cura'].append(cura_grid(path, model, args.work, cura_settings))

        def median(slicer, key):
            return statistics.median(r[key] for r in runs[slicer])

        if have_prusa:
            row.update(prusa_grid_wall_s=round(median('prusa', 'wall'), 2),
                       prusa_grid_cpu_s=round(median('prusa', 'cpu'), 2),
                       prusa_grid_peak_rss_mb=round(median('prusa', 'rss'), 1),
                       prusa_grid_est_time_s=runs['prusa'][-1].get('slicer_time_s'))
        row.update(carve_wall_s=round(median('carve', 'wall'), 2),
                   carve_cpu_s=round(median('carve', 'cpu'), 2),
                   carve_peak_rss_mb=round(median('carve', 'rss'), 1), carve_layers=stats['layers'],
                   carve_bridges=stats.get('bridges'),
                   carve_est_time_s=round(stats['estimated_print_time_s']))
        if have_cura:
            row.update(cura_grid_wall_s=round(median('cura', 'wall'), 2),
                       cura_grid_cpu_s=round(median('cura', 'cpu'), 2),
                       cura_grid_peak_rss_mb=round(median('cura', 'rss'), 1),
                       cura_grid_est_time_s=runs['cura'][-1].get('slicer_time_s'))
        log(f'{model}: carve check ...')
        check = carve_check(carve, gcode, args.work, model + '_carve')
        volume = row['model_volume_mm3']
        row.update(carve_extruded_mm3=round(check['extruded_volume_mm3'], 1),
                   carve_material_percent=round(100 * check['extruded_volume_mm3'] / volume, 2),
                   carve_unsupported_percent=round(check['unsupported_percent'], 3),
                   carve_far_unsupported_percent=round(check['far_unsupported_percent'], 4),
                   carve_far_unsupported_mm2=round(check['far_unsupported_area_mm2'], 1))
        for slicer in ('prusa', 'cura'):
            if f'{slicer}_grid_wall_s' in row:
                row[f'wall_ratio_{slicer}'] = round(row['carve_wall_s'] /
                                                    row[f'{slicer}_grid_wall_s'], 3)
                row[f'cpu_ratio_{slicer}'] = round(row['carve_cpu_s'] /
                                                   max(row[f'{slicer}_grid_cpu_s'], 0.01), 3)
        rows.append(row)
        log('  ' + ', '.join(f'{k}={row.get(k)}' for k in (
            'carve_wall_s', 'carve_cpu_s', 'prusa_grid_wall_s', 'cura_grid_wall_s',
            'carve_material_percent', 'carve_far_unsupported_percent')))
        for f in os.listdir(args.work):  # the G-code is large and only needed for the check
            if f.startswith(model + '_') and f.endswith('.gcode') and not args.keep_gcode:
                os.remove(os.path.join(args.work, f))

    with open(os.path.join(args.results, 'carve_models.csv'), 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=MODEL_FIELDS)
        w.writeheader()
        for row in rows:
            w.writerow(row)
    write_models_md(args, rows, baselines)
    return rows


def fmt(value, spec='g'):
    return '–' if value is None or value == '' else format(float(value), spec)


def write_models_md(args, rows, baselines):
    def base(model, slicer, config, key):
        r = baselines.get((model, slicer, config))
        return r.get(key) if r else None

    configs = [('prusa', 'hollow', 'Prusa hollow'), ('prusa', 'lightning', 'Prusa lightning'),
               ('cura', 'lightning', 'Cura lightning'), ('prusa', 'grid', 'Prusa grid 15 %'),
               ('cura', 'grid', 'Cura grid 15 %')]
    lines = [
        '# carve against the baselines, per model (bench/carve_bench.py)', '',
        f'Run {args.started:%Y-%m-%d %H:%M}; carve {args.carve_version}; '
        f'{bl.version(["prusa-slicer", "--help"], r"PrusaSlicer-[^ ]+")}; CuraEngine '
        f'{bl.version(["CuraEngine", "help"], r"[0-9]+[.][0-9.]+")}; {os.cpu_count()} cores, '
        f'shared: load average {args.load_before[0]:.1f} at the start, '
        f'{os.getloadavg()[0]:.1f} at the end.', '',
        'carve with its defaults (2 covers, 0 shells, 6 cavities, 0.2 mm layers, 0.4 mm nozzle). '
        'Material and far-unsupported of every G-code measured by `carve check` with the method '
        'of shared/BASELINES.md (material = extruded volume / STL volume; far-unsupported = '
        'footprint farther than 2 mm from the layer below / total footprint). Baseline figures '
        'come from bench/results/baselines.csv.', '',
        '## Material · far-unsupported', '',
        '| model | **carve** | ' + ' | '.join(c[2] for c in configs) + ' | carve unsupported % '
        '(r 0.2) | carve bridges |',
        '|---|---|' + '---|' * len(configs) + '---:|---:|']
    for r in rows:
        m = r['model']
        cells = [f"**{r['carve_material_percent']:.1f} % · {r['carve_far_unsupported_percent']:.3f}"
                 " %**"]
        for slicer, config, _ in configs:
            mat = base(m, slicer, config, 'material_percent')
            far = base(m, slicer, config, 'far_unsupported_percent')
            cells.append('–' if mat is None else f'{float(mat):.1f} % · {float(far):.3f} %')
        lines.append(f'| {m} | ' + ' | '.join(cells) +
                     f" | {r['carve_unsupported_percent']:.3f} | {r.get('carve_bridges', '')} |")

    lines += ['', '## Far-unsupported extrusion as an area (mm²)', '',
              'The same measure as an area instead of a share of the footprint: a print with '
              'less material has a smaller footprint, so the same hanging area is a larger share '
              'of it. Baselines: their footprint times their share.', '',
              '| model | **carve** | ' + ' | '.join(c[2] for c in configs) + ' |',
              '|---|---:|' + '---:|' * len(configs)]
    for r in rows:
        m = r['model']
        cells = [f"**{float(r['carve_far_unsupported_mm2']):.1f}**"]
        for slicer, config, _ in configs:
            foot = base(m, slicer, config, 'footprint_area_mm2')
            far = base(m, slicer, config, 'far_unsupported_percent')
            cells.append('–' if foot in (None, '') else
                         f'{float(foot) * float(far) / 100:.1f}')
        lines.append(f'| {m} | ' + ' | '.join(cells) + ' |')

    lines += ['', '## Estimated print time (min), from each slicer', '',
              'carve from its stats; Prusa from its G-code footer (normal mode); Cura from its -v '
              'log. Grid columns from this run, the others from baselines.csv.', '',
              '| model | **carve** | ' + ' | '.join(c[2] for c in configs) + ' |',
              '|---|---:|' + '---:|' * len(configs)]
    for r in rows:
        m = r['model']
        cells = [f"**{r['carve_est_time_s'] / 60:.0f}**"]
        for slicer, config, _ in configs:
            v = r.get(f'{slicer}_grid_est_time_s') if config == 'grid' else None
            if v is None:
                v = base(m, slicer, config, 'slicer_time_s')
            cells.append('–' if v in (None, '') else f'{float(v) / 60:.0f}')
        lines.append(f'| {m} | ' + ' | '.join(cells) + ' |')

    lines += ['', '## Slicing time (re-timed in this run: Prusa grid, then carve, then Cura grid)',
              '',
              f'Wall and CPU (user+sys) seconds and peak RSS from /usr/bin/time -v, the median of '
              f'{args.repeat} rounds of the three slicers in turn. The machine '
              'has 2 cores shared with other jobs, so wall times swing with the load; the ratios '
              'compare runs made seconds apart, and CPU seconds are the steadier figure. Wall '
              'times of the hollow/lightning configurations (earlier run, other load) are in '
              'baselines.md.', '',
              '| model | load | carve wall / CPU s | Prusa grid wall / CPU s | Cura grid wall / CPU s '
              '| **carve / Prusa grid** wall · CPU | **carve / Cura grid** wall · CPU | peak RSS MB '
              'carve / Prusa / Cura |',
              '|---|---:|---:|---:|---:|---:|---:|---:|']
    for r in rows:
        lines.append(
            f"| {r['model']} | {r['load_before']} | {r['carve_wall_s']} / {r['carve_cpu_s']} | "
            f"{fmt(r.get('prusa_grid_wall_s'))} / {fmt(r.get('prusa_grid_cpu_s'))} | "
            f"{fmt(r.get('cura_grid_wall_s'))} / {fmt(r.get('cura_grid_cpu_s'))} | "
            f"**{fmt(r.get('wall_ratio_prusa'), '.2f')}** · {fmt(r.get('cpu_ratio_prusa'), '.2f')} | "
            f"**{fmt(r.get('wall_ratio_cura'), '.2f')}** · {fmt(r.get('cpu_ratio_cura'), '.2f')} | "
            f"{r['carve_peak_rss_mb']} / {fmt(r.get('prusa_grid_peak_rss_mb'))} / "
            f"{fmt(r.get('cura_grid_peak_rss_mb'))} |")
    if rows:
        def total(key):
            return sum(float(r.get(key) or 0) for r in rows)
        tw, tc = total('carve_wall_s'), total('carve_cpu_s')
        lines.append(
            f"| **all** | | {tw:.2f} / {tc:.2f} | {total('prusa_grid_wall_s'):.2f} / "
            f"{total('prusa_grid_cpu_s'):.2f} | {total('cura_grid_wall_s'):.2f} / "
            f"{total('cura_grid_cpu_s'):.2f} | "
            f"**{tw / max(total('prusa_grid_wall_s'), 1e-9):.2f}** · "
            f"{tc / max(total('prusa_grid_cpu_s'), 1e-9):.2f} | "
            f"**{tw / max(total('cura_grid_wall_s'), 1e-9):.2f}** · "
            f"{tc / max(total('cura_grid_cpu_s'), 1e-9):.2f} | |")
    with open(os.path.join(args.results, 'carve_models.md'), 'w') as f:
        f.write('\n'.join(lines) + '\n')


# ---------------------------------------------------------------------------------------------

SCALE_FIELDS = ['s', 'scale', 'height_mm', 'layers', 'wall_s', 'cpu_s', 'peak_rss_mb',
                'carve_peak_memory_mb', 'model_volume_mm3', 'extruded_volume_mm3',
                'material_percent', 'bridges', 'load_before']


def fit_alpha(s, y):
    """alpha and R of y = R s^alpha, least squares on log y = log R + alpha log s."""
    alpha, log_r = np.polyfit(np.log(s), np.log(y), 1)
    return float(alpha), float(np.exp(log_r))


def run_scaling(args, carve, scales):
    model_path = os.path.join(MODELS_DIR, 'fandisk.stl')
    rows = []
    for s in scales:
        scale = BASE_SCALE * s
        log(f'scaling: fandisk s={s} (--scale {scale:g}) ...')
        load = os.getloadavg()[0]
        gcode, stats, wall, cpu, rss = carve_slice(
            carve, model_path, f'fandisk_s{s}', args.work,
            ['--scale', f'{scale:g}', '--cavities', '6'])
        if not args.keep_gcode:
            os.remove(gcode)
        rows.append(dict(
            s=s, scale=scale, height_mm=round(stats['layers'] * stats['settings']['layer_height_mm'], 2),
            layers=stats['layers'], wall_s=round(wall, 2), cpu_s=round(cpu, 2),
            peak_rss_mb=round(rss, 1), carve_peak_memory_mb=round(stats.get('peak_memory_mb', 0), 1),
            model_volume_mm3=round(stats['model_volume_mm3'], 1),
            extruded_volume_mm3=round(stats['extruded_volume_mm3'], 1),
            material_percent=round(stats['material_percent'], 2), bridges=stats.get('bridges'),
            load_before=round(load, 1)))
        log('  ' + ', '.join(f'{k}={rows[-1][k]}' for k in (
            'height_mm', 'wall_s', 'cpu_s', 'peak_rss_mb', 'extruded_volume_mm3')))

    with open(os.path.join(args.results, 'carve_scaling.csv'), 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=SCALE_FIELDS)
        w.writeheader()
        for row in rows:
            w.writerow(row)
    if len(rows) < 2:
        return rows

    s = np.array([r['s'] for r in rows], dtype=float)
    series = {
        'height': np.array([r['height_mm'] for r in rows]),
        'model volume': np.array([r['model_volume_mm3'] for r in rows]),
        'extruded volume': np.array([r['extruded_volume_mm3'] for r in rows]),
        'processing time (wall)': np.array([r['wall_s'] for r in rows]),
        'processing time (CPU)': np.array([r['cpu_s'] for r in rows]),
        'peak RSS': np.array([r['peak_rss_mb'] for r in rows]),
    }
    targets = {'height': '1', 'model volume': '3', 'extruded volume': '<= 2.2',
               'processing time (wall)': '<= 1.5', 'processing time (CPU)': '<= 1.5',
               'peak RSS': ''}
    fits = {name: fit_alpha(s, y) for name, y in series.items()}
    mem_ratio = rows[-1]['peak_rss_mb'] / rows[0]['peak_rss_mb']
    summary = dict(
        started=f'{args.started:%Y-%m-%d %H:%M}', carve=args.carve_version, model='fandisk.stl',
        base_scale=BASE_SCALE, cavities=6, scales=[r['s'] for r in rows],
        alpha={k: round(v[0], 3) for k, v in fits.items()},
        R={k: v[1] for k, v in fits.items()},
        peak_rss_mb_first=rows[0]['peak_rss_mb'], peak_rss_mb_last=rows[-1]['peak_rss_mb'],
        peak_rss_ratio_last_over_first=round(mem_ratio, 2), rows=rows)
    with open(os.path.join(args.results, 'carve_scaling.json'), 'w') as f:
        json.dump(summary, f, indent=1)

    first, last = rows[0], rows[-1]
    lines = [
        '# Scalability: fandisk at 10 sizes (bench/carve_bench.py, report section 6.1)', '',
        f"Run {args.started:%Y-%m-%d %H:%M}; carve {args.carve_version}; fandisk.stl with "
        f"`--scale {BASE_SCALE:g}*s`, s = {', '.join(str(int(v)) for v in s)} "
        f"({first['height_mm']:g} mm to {last['height_mm']:g} mm tall), 6 cavities, otherwise "
        'defaults (2 covers, 0 shells, 0.2 mm, 0.4 mm nozzle). Runs one after the other on a '
        f'shared 2-core machine (load average {args.load_before[0]:.1f} at the start of the '
        'whole benchmark); wall time includes loading the STL and writing the G-code.', '',
        '| s | scale | height mm | layers | wall s | CPU s | peak RSS MB | model volume mm3 | '
        'extruded mm3 | material % | bridges | load |',
        '|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|']
    for r in rows:
        lines.append('| ' + ' | '.join(str(r[k]) for k in (
            's', 'scale', 'height_mm', 'layers', 'wall_s', 'cpu_s', 'peak_rss_mb',
            'model_volume_mm3', 'extruded_volume_mm3', 'material_percent', 'bridges',
            'load_before')) + ' |')
    lines += ['', '## Exponents alpha of R s^alpha (least squares on log-log)', '',
              '| quantity | alpha | target (report) |', '|---|---:|---|']
    for name, (alpha, _) in fits.items():
        lines.append(f'| {name} | **{alpha:.3f}** | {targets[name]} |')
    lines += ['', f"Peak memory (max RSS): {first['peak_rss_mb']:g} MB at s = {int(s[0])}, "
              f"{last['peak_rss_mb']:g} MB at s = {int(s[-1])}: x{mem_ratio:.2f} for a model "
              f"{s[-1] / s[0]:g}x taller and {last['model_volume_mm3'] / first['model_volume_mm3']:.0f}x "
              'larger in volume.', '',
              '![figure](carve_scaling.png)']
    with open(os.path.join(args.results, 'carve_scaling.md'), 'w') as f:
        f.write('\n'.join(lines) + '\n')
    plot_scaling(args, s, series, fits)
    return rows


def plot_scaling(args, s, series, fits):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    fig, (left, mid, right) = plt.subplots(1, 3, figsize=(15, 4.5))
    left.plot(s, series['height'], 'o-', color='tab:blue', label='height (mm)')
    left.set_xlabel('scale factor s')
    left.set_ylabel('height (mm)', color='tab:blue')
    twin = left.twinx()
    twin.plot(s, series['processing time (wall)'], 's-', color='tab:red', label='wall time (s)')
    twin.plot(s, series['processing time (CPU)'], '^--', color='tab:orange', label='CPU time (s)')
    twin.set_ylabel('processing time (s)', color='tab:red')
    handles = left.get_legend_handles_labels()[0] + twin.get_legend_handles_labels()[0]
    left.legend(handles, [h.get_label() for h in handles], loc='upper left')
    left.set_title('Height and processing time')

    mid.plot(s, series['model volume'] / 10 / 1000, 'o-', label='model volume / 10 (cm³)')
    mid.plot(s, series['extruded volume'] / 1000, 's-', label='extruded volume (cm³)')
    mid.set_xlabel('scale factor s')
    mid.set_ylabel('cm³')
    mid.legend(loc='upper left')
    mid.set_title('Volumes')

    names = ['height', 'model volume', 'extruded volume', 'processing time (wall)',
             'processing time (CPU)', 'peak RSS']
    alphas = [fits[n][0] for n in names]
    bars = right.bar(range(len(names)), alphas,
                     color=['tab:blue', 'tab:green', 'tab:purple', 'tab:red', 'tab:orange',
                            'tab:gray'])
    for bar, a in zip(bars, alphas):
        right.text(bar.get_x() + bar.get_width() / 2, a + 0.05, f'{a:.2f}', ha='center')
    for level, style in ((3, ':'), (2.2, '--'), (1.5, '-.')):
        right.axhline(level, color='k', linestyle=style, linewidth=0.8)
    right.set_xticks(range(len(names)))
    right.set_xticklabels(['height', 'model\nvolume', 'extruded\nvolume', 'time\n(wall)',
                           'time\n(CPU)', 'peak\nRSS'])
    right.set_ylabel('alpha in R s^alpha')
    right.set_ylim(0, max(3.4, max(alphas) + 0.4))
    right.set_title('Fitted exponents (lines: 3, 2.2, 1.5)')
    fig.suptitle(f'carve, fandisk.stl scaled by {BASE_SCALE:g}·s, 6 cavities')
    fig.tight_layout()
    fig.savefig(os.path.join(args.results, 'carve_scaling.png'), dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--carve', default=os.path.join(ROOT, 'build', 'carve'))
    ap.add_argument('--quick', action='store_true',
                    help=f'models {",".join(QUICK_MODELS)}, scales {QUICK_SCALES}')
    ap.add_argument('--all', action='store_true', help='include skull_x4_400k')
    ap.add_argument('--models', help='comma-separated model names')
    ap.add_argument('--scales', help='comma-separated s values (default 1..10)')
    ap.add_argument('--no-models', action='store_true')
    ap.add_argument('--no-scaling', action='store_true')
    ap.add_argument('--keep-gcode', action='store_true')
    ap.add_argument('--repeat', type=int, default=3,
                    help='rounds of PrusaSlicer, carve, CuraEngine per model; medians kept')
    ap.add_argument('--work', default='/tmp/carve_bench')
    ap.add_argument('--results', default=RESULTS)
    args = ap.parse_args()

    carve = os.path.abspath(args.carve)
    if not os.path.exists(carve):
        sys.exit(f'no carve executable at {carve} (build it, or pass --carve)')
    os.makedirs(args.work, exist_ok=True)
    os.makedirs(args.results, exist_ok=True)
    args.started = datetime.datetime.now()
    args.load_before = os.getloadavg()
    args.carve_version = subprocess.run([carve, '--version'], capture_output=True,
                                        text=True).stdout.strip().replace('carve ', '') or '?'
    try:
        commit = subprocess.run(['git', '-C', ROOT, 'rev-parse', '--short', 'HEAD'],
                                capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(['git', '-C', ROOT, 'status', '--porcelain', '--', 'src'],
                               capture_output=True, text=True).stdout.strip()
        if commit:
            args.carve_version += (f' (built from {commit}' +
                                   (' + uncommitted changes in src/)' if dirty else ')'))
    except OSError:
        pass

    if args.models:
        models = args.models.split(',')
    elif args.quick:
        models = QUICK_MODELS
    else:
        models = sorted(os.path.splitext(f)[0] for f in os.listdir(MODELS_DIR)
                        if f.endswith('.stl') and (args.all or 'skull_x4' not in f))
    if args.scales:
        scales = [int(v) for v in args.scales.split(',')]
    else:
        scales = QUICK_SCALES if args.quick else list(range(1, 11))

    if not args.no_models:
        run_models(args, carve, models)
    if not args.no_scaling:
        run_scaling(args, carve, scales)
    log(f'done; results in {args.results}')


if __name__ == '__main__':
    main()
