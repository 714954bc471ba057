#!/usr/bin/python3
"""What thin walls (issue 47) cost in slicing time: each shared model sliced by carve with thin
walls (its default) and with --no-thin-walls, and optionally by a second carve binary (an older
commit) the same two ways, interleaved round by round so that the machine's load falls on all
alike; the median CPU seconds (user + system, from wait4) of --repeat rounds, and the ratios.
With --instructions, the instructions executed (valgrind's callgrind, --threads 1): slow, but
the same on a loaded machine as on an idle one, so they are the figure to quote.

    bench/thin_walls_cost.py [--carve build/carve] [--baseline /tmp/carve.old]
        [--models man,fandisk] [--repeat 5] [--instructions]

Writes bench/results/thin_walls_cost.md; G-code goes to --work (default /tmp/carve_thin_cost).
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = os.path.join(os.path.dirname(ROOT), 'shared', 'models')
SHARED = ['cat', 'elephant', 'fandisk', 'man', 'skull']


def cpu_seconds(cmd):
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    if status != 0:
        sys.exit(f'failed: {" ".join(cmd)}')
    return usage.ru_utime + usage.ru_stime


def instructions(cmd, work):
    out = os.path.join(work, 'callgrind.out')
    subprocess.run(['valgrind', '--tool=callgrind', f'--callgrind-out-file={out}'] + cmd +
                   ['--threads', '1'], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    with open(out) as f:
        total = re.search(r'^(?:summary|totals): (\d+)', f.read(), re.M)
    os.remove(out)
    return int(total.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--carve', default=os.path.join(ROOT, 'build', 'carve'))
    ap.add_argument('--baseline', help='another carve binary, timed the same way')
    ap.add_argument('--models', default=','.join(SHARED))
    ap.add_argument('--repeat', type=int, default=5)
    ap.add_argument('--instructions', action='store_true')
    ap.add_argument('--work', default='/tmp/carve_thin_cost')
    ap.add_argument('--results', default=os.path.join(ROOT, 'bench', 'results'))
    args = ap.parse_args()
    if args.instructions and not shutil.which('valgrind'):
        sys.exit('--instructions needs valgrind')
    os.makedirs(args.work, exist_ok=True)
    binaries = [('carve', args.carve)] + ([('baseline', args.baseline)] if args.baseline else [])
    variants = [(name, path, flags) for name, path in binaries
                for flags in ([], ['--no-thin-walls'])]
    rows = []
    for model in args.models.split(','):
        stl = os.path.join(MODELS, model + '.stl')
        if not os.path.exists(stl):
            print(f'skipped {model}: {stl} is absent')
            continue
        cmds = [[path, 'slice', stl, '-o', os.path.join(args.work, f'{model}.gcode')] + flags
                for _, path, flags in variants]
        times = [[] for _ in cmds]
        for _ in range(args.repeat):
            for k, cmd in enumerate(cmds):
                times[k].append(cpu_seconds(cmd))
        cpu = [statistics.median(t) for t in times]
        ins = [instructions(cmd, args.work) for cmd in cmds] if args.instructions else None
        rows.append((model, cpu, ins))
        print(model, ' '.join(f'{c:.3f}' for c in cpu), ins or '')
    labels = [f'{name}{" --no-thin-walls" if flags else ""}' for name, _, flags in variants]
    lines = ['# What thin walls cost in slicing time', '',
             'Command: `/usr/bin/python3 bench/thin_walls_cost.py ' + ' '.join(sys.argv[1:]) +
             '`', '', f'Binaries: carve = `{args.carve}`' +
             (f', baseline = `{args.baseline}`' if args.baseline else '') +
             f'. CPU s: median of {args.repeat} interleaved rounds (user + system; a shared '
             'machine, so compare within a row). Ratios are to the same binary with '
             '--no-thin-walls.', '']
    head = '| model | ' + ' | '.join(f'CPU s {l}' for l in labels)
    head += ' | CPU ratio carve' + (' | CPU ratio baseline' if args.baseline else '')
    if args.instructions:
        head += ' | ' + ' | '.join(f'instructions {l}' for l in labels)
        head += ' | instructions ratio carve' + (' | instructions ratio baseline'
                                                 if args.baseline else '')
    lines += [head + ' |', '|' + '---|' * (head.count('|'))]
    for model, cpu, ins in rows:
        cells = [f'{c:.3f}' for c in cpu] + [f'{cpu[0] / cpu[1]:.3f}']
        if args.baseline:
            cells.append(f'{cpu[2] / cpu[3]:.3f}')
        if ins:
            cells += [f'{i / 1e9:.3f} G' for i in ins] + [f'{ins[0] / ins[1]:.3f}']
            if args.baseline:
                cells.append(f'{ins[2] / ins[3]:.3f}')
        lines.append(f'| {model} | ' + ' | '.join(cells) + ' |')
    with open(os.path.join(args.results, 'thin_walls_cost.md'), 'w') as f:
        f.write('\n'.join(lines) + '\n')


if __name__ == '__main__':
    main()
