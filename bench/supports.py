#!/ usr / bin / python3
"""Supports (issue #20): carve --support auto against PrusaSlicer 2.5's snug supports and
CuraEngine 4.13's tree supports on the shared models, one measuring stick for every file.

    /usr/bin/python3 bench/supports.py                      # cat, elephant, skull
    /usr/bin/python3 bench/supports.py --models cat --reuse  # measure G-code already sliced

Every slicer prints the same model at its own coordinates, 0.4 mm nozzle, 0.2 mm layers (first
too), 1.75 mm filament. carve at its defaults, with --support none (today) and --support auto;
the peers with their cheapest supported
        interior(shared / BASELINES.md's lightning: 1 wall, 2/2, lightning 10 %) and
    their supports on at their own
        defaults(PrusaSlicer-- support - material-- support - material - style snug;
                 CuraEngine support_enable, support_structure tree, support_type everywhere,
                 every derived setting from fdmprinter.def.json as bench / baselines.py does)
            .

        Each G
        - code is measured with `carve check FILE-- mesh MODEL-- json-- support
        - gap 0.4`: support material is what its;
TYPE : comments call support; hanging is extrusion more than 2 mm from
anything printed below, where a support's top up to 0.4 mm below the layer under counts as below
(carve and PrusaSlicer leave 0.2 mm, CuraEngine 0.3 mm rounded to layers), split into inside (over
the model's slice one layer down), overhang (the rest) and, of it, the support's own. Print time:
each slicer's own estimate, and the analyser's common stick (every move a trapezoid from rest).

Writes bench/results/supports.md and bench/results/supports.json; G-code goes to /tmp/carve_supports.
"""
import argparse
import datetime
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import baselines  # noqa: E402  (peer settings, CuraEngine's derived settings, timing)

ROOT = baselines.ROOT
CARVE = os.path.join(ROOT, 'build', 'carve')
WORK = '/tmp/carve_supports'
GAP = 0.4


def jobs(model, model_path):
    out = os.path.join(WORK, model)
    cura_args, errors = baselines.cura_args({
        **baselines.CURA_COMMON, **baselines.CURA_CONFIGS['lightning'],
        'support_enable': True, 'support_structure': 'tree', 'support_type': 'everywhere'})
    if errors:
        print(f'  cura settings left at defaults: {errors}', file=sys.stderr)
    return {
        'carve_none': [CARVE, 'slice', model_path, '-o', out + '_carve_none.gcode', '--stats',
                       out + '_carve_none.stats.json', '-q'],
        'carve_auto': [CARVE, 'slice', model_path, '-o', out + '_carve_auto.gcode', '--stats',
                       out + '_carve_auto.stats.json', '-q', '--support', 'auto'],
        'prusa_snug': (['prusa-slicer'] + baselines.PRUSA_COMMON +
                       baselines.PRUSA_CONFIGS['lightning'] +
                       ['--support-material', '--support-material-style', 'snug',
                        '-o', out + '_prusa_snug.gcode', model_path]),
        'cura_tree': (['CuraEngine', 'slice', '-v', '-j',
                       os.path.join(baselines.CURA_DEFS, 'fdmprinter.def.json')] + cura_args +
                      ['-e0'] + cura_args + ['-l', model_path, '-o', out + '_cura_tree.gcode']),
    }


def slicer_time_s(slicer, gcode, log):
    if slicer.startswith('carve'):
        return json.load(open(gcode[:-len('.gcode')] + '.stats.json'))['estimated_print_time_s']
    if slicer == 'prusa_snug':
        return baselines.prusa_header(gcode).get('slicer_time_s')
    return baselines.cura_log_figures(log).get('slicer_time_s')


def measure(gcode, model_path, log_path):
    rc, _, _, _, out = baselines.timed(
        [CARVE, 'check', gcode, '--mesh', model_path, '--json', '--support-gap', str(GAP)],
        log_path)
    if rc != 0:
        raise RuntimeError(f'carve check failed on {gcode}: {out[-500:]}')
    return json.loads(out[out.index('{'):])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--models', default='cat,elephant,skull')
    ap.add_argument('--reuse', action='store_true', help='measure the G-code already in ' + WORK)
    ap.add_argument('--markdown', action='store_true',
                    help='only write supports.md again from supports.json')
    args = ap.parse_args()
    results = os.path.join(ROOT, 'bench', 'results')
    if args.markdown:
        data = json.load(open(os.path.join(results, 'supports.json')))
        write_markdown(os.path.join(results, 'supports.md'), data['meta'], data['rows'])
        return
    os.makedirs(WORK, exist_ok=True)
    started = datetime.datetime.now(datetime.timezone.utc)
    rows = []
    for model in args.models.split(','):
        model_path = os.path.join(baselines.MODELS_DIR, model + '.stl')
        volume = baselines.stl_volume_mm3(model_path)
        for slicer, cmd in jobs(model, model_path).items():
            gcode = os.path.join(WORK, f'{model}_{slicer}.gcode')
            log = gcode[:-len('.gcode')] + '.log'
            wall = cpu = None
            if not args.reuse or not os.path.exists(gcode):
                print(f'{model}: {slicer}', file=sys.stderr)
                rc, wall, cpu, _, text = baselines.timed(cmd, log)
                if rc != 0:
                    raise RuntimeError(f'{slicer} failed on {model}: {text[-500:]}')
            check = measure(gcode, model_path, gcode[:-len('.gcode')] + '.check.log')
            logtext = open(log, errors='replace').read() if os.path.exists(log) else ''
            rows.append(dict(
                model=model, slicer=slicer, model_volume_mm3=volume,
                support_mm3=check.get('support_volume_mm3', 0),
                material_mm3=check['extruded_volume_mm3'],
                time_s=slicer_time_s(slicer, gcode, logtext),
                stick_time_s=check['stick_time_s'],
                hanging_overhang_mm2=check['hanging_overhang_mm2'],
                hanging_support_mm2=check.get('hanging_support_mm2', 0),
                hanging_inside_mm2=check['hanging_inside_mm2'],
                outside_other_mm2=check.get('outside_other_mm2', 0),
                retractions=check['retractions'], slice_wall_s=wall, slice_cpu_s=cpu))
            r = rows[-1]
            print(f"  {slicer}: support {r['support_mm3']:.0f} mm3, material "
                  f"{r['material_mm3']:.0f} mm3, hanging overhang {r['hanging_overhang_mm2']:.1f} "
                  f"mm2", file=sys.stderr)
    meta = dict(
        started=started.isoformat(timespec='seconds'),
        commit=subprocess.run(['git', '-C', ROOT, 'rev-parse', '--short', 'HEAD'],
                              capture_output=True, text=True).stdout.strip(),
        prusa=baselines.version(['prusa-slicer', '--help'], r'PrusaSlicer-[^ ]+'),
        cura=baselines.version(['CuraEngine', 'help'], r'[0-9]+[.][0-9.]+'),
        support_gap_mm=GAP)
    with open(os.path.join(results, 'supports.json'), 'w') as f:
        json.dump(dict(meta=meta, rows=rows), f, indent=1)
        f.write('\n')
    write_markdown(os.path.join(results, 'supports.md'), meta, rows)


NAMES = {'carve_none': 'carve, no support (today)', 'carve_auto': 'carve --support auto',
         'prusa_snug': 'PrusaSlicer snug', 'cura_tree': 'CuraEngine tree'}


def write_markdown(path, meta, rows):
    def hm(s):
        return '–' if s is None else f'{int(s) // 3600}h{int(s) % 3600 // 60:02d}'

    lines = [
        '# Supports: carve against PrusaSlicer (snug) and CuraEngine (tree), one measuring stick',
        '',
        f"Made by `/usr/bin/python3 bench/supports.py` (started {meta['started']}, carve "
        f"{meta.get('carve', 'at ' + meta['commit'] + ' plus its working tree')}, "
        f"{meta['prusa']}, "
        f"CuraEngine {meta['cura']}). 0.4 mm nozzle, 0.2 mm layers; peers with 1 wall, 2/2, "
        'lightning 10 % and their supports at their own defaults; carve at its defaults. '
        'Measured by `carve check FILE --mesh MODEL --json --support-gap 0.4`.',
        '',
        '- *support*: extrusion under a ;TYPE: naming support, interface included, mm³ '
        '(CuraEngine\'s brim under its trees is typed SKIRT: it counts in *material* and in '
        '*outside, not support*);',
        '- *material*: all extrusion, mm³ (% of the model\'s volume);',
        '- *time*: the slicer\'s own estimate; *stick*: the analyser\'s, the same for every file;',
        '- *hanging*: extrusion more than 2 mm from anything printed below (a support\'s top up '
        'to 0.4 mm below the layer under counts, and support standing on the model across that '
        'gap is held), mm²: *overhang* where it is not over the model\'s slice one layer down, '
        '*inside* where it is; *support\'s own*: the part of all the hanging (inside or '
        'overhang) that is support extrusion;',
        '- *outside, not support*: footprint outside the model\'s slice (beyond half a line) '
        'that is not support, mm² (CuraEngine: its support brim on the first layer).',
        '',
        '| model | slicer | support mm³ | material mm³ (%) | time · stick | hanging overhang mm² '
        '| hanging inside mm² | support\'s own hanging mm² | outside, not support mm² | '
        'retractions |',
        '|---|---|---:|---:|---:|---:|---:|---:|---:|---:|',
    ]
    for r in rows:
        pct = 100 * r['material_mm3'] / r['model_volume_mm3'] if r['model_volume_mm3'] else 0
        lines.append(
            f"| {r['model']} | {NAMES[r['slicer']]} | {r['support_mm3']:,.0f} | "
            f"{r['material_mm3']:,.0f} ({pct:.1f} %) | {hm(r['time_s'])} · "
            f"{hm(r['stick_time_s'])} | {r['hanging_overhang_mm2']:.1f} | "
            f"{r['hanging_inside_mm2']:.1f} | {r['hanging_support_mm2']:.1f} | "
            f"{r['outside_other_mm2']:.1f} | {r['retractions']:,} |")
    lines.append('')
    with open(path, 'w') as f:
        f.write('\n'.join(lines))


if __name__ == '__main__':
    main()
