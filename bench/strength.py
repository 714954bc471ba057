#!/usr/bin/python3
"""Strength of carve's prints on the shared models (issue 49), by carve check --strength.

Slices each model with carve's defaults and with --shells 1, reads every G-code back with
`carve check --strength --json` (2 mm voxels, linear law) and writes bench/results/strength.md:
grams, weakest section and bond, compression and shear stiffness, each per gram.
Usage: /usr/bin/python3 bench/strength.py [MODEL...]   (default: the shared models)
"""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CARVE = os.path.join(ROOT, "build", "carve")
MODELS = os.environ.get("CARVE_SHARED_MODELS", os.path.join(ROOT, "..", "shared", "models"))
CONFIGS = [("carve default", []), ("carve --shells 1", ["--shells", "1"])]


def measure(model, args, out):
    subprocess.run([CARVE, "slice", model, "-o", out, "-q"] + args, check=True)
    text = subprocess.run([CARVE, "check", out, "--strength", "--json"], check=True,
                          capture_output=True, text=True).stdout
    return json.loads(text)["strength"]


def main():
    names = sys.argv[1:] or ["cat", "elephant", "fandisk", "man", "skull"]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            model = os.path.join(MODELS, name + ".stl")
            if not os.path.exists(model):
                print(f"skipped {name}: {model} absent", file=sys.stderr)
                continue
            for label, args in CONFIGS:
                s = measure(model, args, os.path.join(tmp, "out.gcode"))
                fe = s["finite_elements"]
                rows.append((name, label, s, fe))
                print(name, label, round(s["grams"], 2), round(s["compression_n_per_mm"]),
                      round(s["shear_n_per_mm"]), file=sys.stderr)
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    lines = [
        "# Strength of carve's prints (`bench/strength.py`)",
        "",
        f"carve at {commit}, every figure from `carve check --strength --json` of the G-code "
        "(2 mm voxels unless coarsened, linear law E = 3500 MPa x filled fraction). "
        "The stiffness depends on the voxel size and the law: docs/check.md.",
        "",
        "| model | print | grams | weakest section mm⁴ | weakest bond mm² | compression N/mm | "
        "per g | shear N/mm | per g | voxel mm | voxels | solve s |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, label, s, fe in rows:
        bond = s["weakest_bond_mm2"]
        lines.append(
            f"| {name} | {label} | {s['grams']:.2f} | {s['weakest_section_mm4']:.0f} | "
            f"{bond if bond is None else round(bond, 1)} | {s['compression_n_per_mm']:.0f} | "
            f"{s['compression_n_per_mm_per_g']:.1f} | {s['shear_n_per_mm']:.0f} | "
            f"{s['shear_n_per_mm_per_g']:.1f} | {fe['voxel_mm']:g} | {fe['voxels']} | "
            f"{fe['solve_s']:.1f} |")
    with open(os.path.join(ROOT, "bench", "results", "strength.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
