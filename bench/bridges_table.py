#!/usr/bin/python3
"""Local minima and bridges on every shared model, with and without bridge pruning and the tear
limit (issue 5). Each configuration slices the model with carve, then `carve check` measures the
G-code itself (far-unsupported = footprint farther than 2 mm from the layer below's footprint,
the BASELINES.md method). Writes bench/results/bridges.{json,md}.

    /usr/bin/python3 bench/bridges_table.py [--carve build/carve] [--models cat,fandisk]
"""
import argparse
import json
import os
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS_DIR = os.path.join(os.path.dirname(ROOT), "shared", "models")
CONFIGS = [
    ("report (no pruning, no tear limit)", ["--keep-all-bridges", "--max-bridge-length", "500"]),
    ("pruning (default)", []),
    # The tear limit belongs to the report's scheme (issue 37): it once switched to it silently.
    ("pruning + tear limit 0.8 mm (4r)", ["--carving", "report", "--tear-limit", "0.8"]),
    ("pruning + tear limit 0.4 mm (2r)", ["--carving", "report", "--tear-limit", "0.4"]),
    ("pruning + tear limit 0.1 mm (r/2)", ["--carving", "report", "--tear-limit", "0.1"]),
]


def run(carve, model, extra, tmp):
    gcode = os.path.join(tmp, "out.gcode")
    stats = os.path.join(tmp, "out.json")
    t0 = time.time()
    subprocess.run([carve, "slice", model, "-o", gcode, "--stats", stats, "-q"] + extra,
                   check=True)
    wall = time.time() - t0
    s = json.load(open(stats))
    check = json.loads(subprocess.run([carve, "check", gcode, "--json"], check=True,
                                      capture_output=True, text=True).stdout)
    return {
        "bridges": s["bridges"],
        "bridge_length_mm": round(s["bridge_length_mm"], 1),
        "material_percent": round(s["material_percent"], 2),
        "estimated_print_time_min": round(s["estimated_print_time_s"] / 60, 1),
        "far_unsupported_percent": round(check["far_unsupported_percent"], 3),
        "far_unsupported_mm2": round(check["far_unsupported_area_mm2"], 1),
        "unsupported_percent": round(check["unsupported_percent"], 2),
        "wall_s": round(wall, 2),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--carve", default=os.path.join(ROOT, "build", "carve"))
    ap.add_argument("--models", default="cat,elephant,fandisk,man,skull")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "bridges"))
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.models.split(","):
            for label, extra in CONFIGS:
                r = run(args.carve, os.path.join(MODELS_DIR, name + ".stl"), extra, tmp)
                r.update(model=name, config=label, options=" ".join(extra))
                rows.append(r)
                print(name, label, r, flush=True)
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    json.dump(rows, open(args.out + ".json", "w"), indent=1)
    with open(args.out + ".md", "w") as f:
        f.write("# Bridges, pruning and the tear limit on the shared models\n\n")
        f.write("Made by `/usr/bin/python3 bench/bridges_table.py` on "
                + time.strftime("%Y-%m-%d %H:%M") + ". Carve defaults otherwise (2 covers, no "
                "shell, 6 cavities, 0.4 mm nozzle, 0.2 mm layers). Far-unsupported and "
                "unsupported are measured from the G-code by `carve check` (BASELINES.md method; "
                "unsupported uses a 0.2 mm radius). Far-unsupported is given both as a share of the "
                "G-code's footprint (BASELINES.md) and as an area: a print with less material has a "
                "smaller footprint, so the same hanging area is a larger share. Wall seconds are "
                "from a shared machine.\n\n")
        f.write("| model | configuration | bridges | bridge length mm | material % | "
                "far-unsupported % | far-unsupported mm2 | unsupported % | est. print min | wall s |\n")
        f.write("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n")
        for r in rows:
            f.write(f"| {r['model']} | {r['config']} | {r['bridges']} | {r['bridge_length_mm']} | "
                    f"{r['material_percent']} | {r['far_unsupported_percent']} | {r['far_unsupported_mm2']} | "
                    f"{r['unsupported_percent']} | {r['estimated_print_time_min']} | "
                    f"{r['wall_s']} |\n")


if __name__ == "__main__":
    main()
