#!/usr/bin/python3
"""Strength of carve's prints and of the peers' on the shared models (issue 49), by carve check
--strength.

Slices each model with carve (default, --preset strong, every step of --strong) and with the
peers of shared/BASELINES.md (PrusaSlicer 2.5 grid 15 % 2 walls 3/3; CuraEngine 4.13 grid 15 %
2 walls 3/3 and lightning 10 % 1 wall 2/2; 0.4 mm nozzle, 0.2 mm layers, commands from
bench/baselines.py), reads every G-code back with `carve check --strength --json` under the
linear and the cubic material law (2 mm voxels) and writes bench/results/strength.md: grams,
print time (carve check's stick time, one measure for every slicer), compression and shear
stiffness, each per gram, and whether `carve check --strict` passes.
Usage: /usr/bin/python3 bench/strength.py [--work DIR] [--reuse] [--prints A,B] [MODEL...]
       (default models: fandisk and man; G-code goes to /tmp/carve_strength; --prints keeps
       the prints whose label contains one of the comma-separated words, e.g. "default,strong,
       PrusaSlicer" for carve's default and strong preset against PrusaSlicer's grid)
"""
import argparse
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import baselines  # noqa: E402  (the peers' commands, one definition)

CARVE = os.path.join(ROOT, "build", "carve")
MODELS = os.environ.get("CARVE_SHARED_MODELS", os.path.join(ROOT, "..", "shared", "models"))
STEPS = ["0.25", "0.5", "0.75"]  # 0 is the default, 1 the strong preset: the same G-code
CARVE_CONFIGS = ([("carve default", []), ("carve --preset strong", ["--preset", "strong"])] +
                 [(f"carve --strong {s}", ["--strong", s]) for s in STEPS])
PEERS = [("PrusaSlicer grid 15 %", "prusa", "grid"), ("CuraEngine grid 15 %", "cura", "grid"),
         ("CuraEngine lightning 10 %", "cura", "lightning")]
LAWS = ["linear", "cubic"]
VOXELS = ["1", "2", "4"]
VOXEL_PRINTS = ["carve --preset strong", "PrusaSlicer grid 15 %"]  # on the first model


def peer_command(slicer, config, model, out):
    if slicer == "prusa":
        return (["prusa-slicer"] + baselines.PRUSA_COMMON + baselines.PRUSA_CONFIGS[config] +
                ["-o", out, model])
    settings, _ = baselines.cura_args({**baselines.CURA_COMMON, **baselines.CURA_CONFIGS[config]})
    return (["CuraEngine", "slice", "-v", "-j",
             os.path.join(baselines.CURA_DEFS, "fdmprinter.def.json")] + settings + ["-e0"] +
            settings + ["-l", model, "-o", out])


def measure(gcode, model):
    """{law: strength JSON}, the stick time and the --strict verdict of one G-code."""
    out = {}
    for law in LAWS:
        text = subprocess.run([CARVE, "check", gcode, "--strength", "--json", "--material-law",
                               law], check=True, capture_output=True, text=True).stdout
        j = json.loads(text)
        out[law] = j["strength"]
        out["time_s"] = j["stick_time_s"]
    strict = subprocess.run([CARVE, "check", gcode, "--strict", "--mesh", model],
                            capture_output=True, text=True)
    out["strict"] = strict.returncode == 0
    return out


def runs(model, work, reuse, keep):
    name = os.path.splitext(os.path.basename(model))[0]
    for label, args in CARVE_CONFIGS:
        if not keep(label):
            continue
        stem = "_".join([name, "carve"] + [a.strip("-") for a in args])
        gcode = os.path.join(work, stem + ".gcode")
        if not (reuse and os.path.exists(gcode)):
            subprocess.run([CARVE, "slice", model, "-o", gcode, "-q"] + args, check=True)
        yield label, gcode
    for label, slicer, config in PEERS:
        if not keep(label):
            continue
        gcode = os.path.join(work, f"{name}_{slicer}_{config}.gcode")
        if not (reuse and os.path.exists(gcode)):
            with open(gcode + ".log", "w") as log:
                subprocess.run(peer_command(slicer, config, model, gcode), check=True,
                               stdout=log, stderr=subprocess.STDOUT)
        yield label, gcode


def voxel_rows(name, prints):
    """How the voxel's size moves the figures: each print at 1, 2 and 4 mm, both laws."""
    out = []
    for label, gcode in prints:
        cells = []
        for voxel in VOXELS:
            for law in LAWS:
                text = subprocess.run([CARVE, "check", gcode, "--strength", "--json",
                                       "--voxel-size", voxel, "--material-law", law,
                                       "--max-voxels", "150000"], check=True,
                                      capture_output=True, text=True).stdout
                s = json.loads(text)["strength"]
                cells.append(f"{s['compression_n_per_mm']:.0f} / {s['shear_n_per_mm']:.0f}")
        out.append(f"| {name} | {label} | " + " | ".join(cells) + " |")
        print(out[-1], file=sys.stderr, flush=True)
    return out


def row(name, label, m):
    lin, cub = m["linear"], m["cubic"]
    g = lin["grams"]
    return (f"| {name} | {label} | {g:.2f} | {m['time_s'] / 60:.0f} | "
            f"{lin['compression_n_per_mm']:.0f} | {lin['compression_n_per_mm_per_g']:.1f} | "
            f"{lin['shear_n_per_mm']:.0f} | {lin['shear_n_per_mm_per_g']:.1f} | "
            f"{cub['compression_n_per_mm']:.1f} | {cub['compression_n_per_mm_per_g']:.2f} | "
            f"{cub['shear_n_per_mm']:.1f} | {cub['shear_n_per_mm_per_g']:.2f} | "
            f"{lin['weakest_section_mm4']:.0f} | {'yes' if m['strict'] else 'no'} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("models", nargs="*", default=["fandisk", "man"])
    ap.add_argument("--work", default="/tmp/carve_strength")
    ap.add_argument("--reuse", action="store_true", help="measure G-code already in --work")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "strength.md"))
    ap.add_argument("--no-voxels", action="store_true", help="leave out the voxel-size table")
    ap.add_argument("--prints", default="", help="keep the prints whose label has one of these")
    args = ap.parse_args()
    words = [w for w in args.prints.split(",") if w]

    def keep(label):
        return not words or any(w in label for w in words)

    os.makedirs(args.work, exist_ok=True)
    lines = []
    voxel_lines = []
    voxel = set()
    for name in args.models:
        model = os.path.join(MODELS, name + ".stl")
        if not os.path.exists(model):
            print(f"skipped {name}: {model} absent", file=sys.stderr)
            continue
        gcodes = []
        for label, gcode in runs(model, args.work, args.reuse, keep):
            gcodes.append((label, gcode))
            m = measure(gcode, model)
            voxel.add(m["linear"]["finite_elements"]["voxel_mm"])
            lines.append(row(name, label, m))
            print(lines[-1], file=sys.stderr, flush=True)
        if not voxel_lines and not args.no_voxels:
            voxel_lines = voxel_rows(name, [g for g in gcodes if g[0] in VOXEL_PRINTS])
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    head = [
        "# Strength of carve's prints and the peers' (`bench/strength.py`)",
        "",
        f"`bench/strength.py {' '.join(sys.argv[1:])}`; carve at {commit}; PrusaSlicer 2.5 and CuraEngine 4.13 with bench/baselines.py's "
        "settings (0.4 mm nozzle, 0.2 mm layers). Every figure from `carve check --strength "
        f"--json` of the G-code, voxel {', '.join(f'{v:g}' for v in sorted(voxel))} mm, "
        "E = 3500 MPa x f (linear) or x f^3 (cubic) of a voxel's filled fraction f; time = "
        "carve check's stick time (one measure for every slicer), minutes; strict = `carve "
        "check --strict` passes. The stiffness depends on the voxel size and the law "
        "(docs/check.md): compare rows only within a column. The law weighs material by "
        "where it lies: the cubic one counts a thinly filled voxel for almost nothing (15 % "
        "filled: 0.3 % of E), so it favours thick walls over sparse infill, the linear one "
        "counts every gram alike; README.md (Stronger prints) reads the table.",
        "",
        "| model | print | grams | min | compr. N/mm linear | per g | shear N/mm linear | per g | "
        "compr. N/mm cubic | per g | shear N/mm cubic | per g | weakest section mm⁴ | strict |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    tail = [
        "",
        "## The voxel's size",
        "",
        "Compression / shear N/mm of the same G-code at each voxel side (`--voxel-size`, "
        "`--max-voxels 150000` so that none is coarsened):",
        "",
        "| model | print | 1 mm linear | 1 mm cubic | 2 mm linear | 2 mm cubic | 4 mm linear | "
        "4 mm cubic |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ] + voxel_lines
    with open(args.out, "w") as f:
        f.write("\n".join(head + lines + tail) + "\n")


if __name__ == "__main__":
    main()
