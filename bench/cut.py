#!/usr/bin/python3
"""Cuts shared models scaled 3x to fit a Prusa MK3S (--cut auto, issue #48) and tabulates the
plates, pieces, material, print time and the time to slice, as bench/results/cut.md.

Usage: bench/cut.py [MODEL...]   (default: the five shared models; names of
/work/shared/models/*.stl)

Each run also writes the plates' meshes (--plate-meshes), and every plate is then measured by
`carve check PLATE.gcode --mesh PLATE.stl --mesh-offset 0,0 --strict`: the "plates pass" column
counts those that pass every printability rule.

The skull at 3x is issue #48's case, 225 x 314 x 360 mm: no cut across z alone fits its
footprint on the MK3S, so --cut auto cuts across x or y too.

Runs build/carve once a model. The time to slice is the run's CPU time (user + system, every
thread), which the other work on a shared machine moves far less than the wall time.
Standard library only.
"""
import glob
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = "/work/shared/models"
CARVE = os.path.join(ROOT, "build", "carve")


def planes(cut):
    """The planes as "z=120" (heights across z) or "y=157" (planes across an axis)."""
    if not cut.get("planes"):
        return [f"z={z:.0f}" for z in cut["planes_mm"]]
    out = []
    for p in cut["planes"]:
        n, at = p["normal"], p["point_mm"]
        axis = max(range(3), key=lambda k: abs(n[k]))
        if abs(n[axis]) > 0.999:
            out.append(f"{'xyz'[axis]}={at[axis]:.0f}")
        else:
            out.append("({:.0f},{:.0f},{:.0f}) n ({:.2f},{:.2f},{:.2f})".format(*at, *n))
    return out


def plate_checks(tmp, name):
    """How many of the run's plates pass carve check --strict against their own meshes."""
    passed, failed = 0, []
    for gcode in sorted(glob.glob(os.path.join(tmp, f"{name}-plate*.gcode"))):
        mesh = gcode[:-len(".gcode")] + ".stl"
        done = subprocess.run([CARVE, "check", gcode, "--mesh", mesh, "--mesh-offset", "0,0",
                               "--strict"], capture_output=True, text=True)
        if done.returncode == 0:
            passed += 1
        else:
            failed.append(os.path.basename(gcode) + ": " + done.stderr.strip())
    return passed, failed


def run(name):
    with tempfile.TemporaryDirectory() as tmp:
        out, stats = os.path.join(tmp, f"{name}.gcode"), os.path.join(tmp, f"{name}.json")
        command = [CARVE, "slice", os.path.join(MODELS, f"{name}.stl"), "-o", out, "--stats",
                   stats, "--printer", "mk3s", "--scale", "3", "--cut", "auto",
                   "--plate-meshes", "-q"]
        before = os.times()
        done = subprocess.run(command, capture_output=True, text=True)
        after = os.times()
        cpu = (after.children_user - before.children_user +
               after.children_system - before.children_system)
        if done.returncode != 0:
            return {"name": name, "error": done.stderr.strip()}
        j = json.load(open(stats))
        passed, failed = plate_checks(tmp, name)
        return {"name": name, "command": " ".join(command[1:]).replace(tmp + "/", ""),
                "plates": len(j["plates"]), "pieces": len(j["pieces"]),
                "planes": planes(j["cut"]),
                "connectors": sum(len(p["connectors"]) for p in j["pieces"]),
                "volume": j["model_volume_mm3"],
                "pieces_volume": sum(p["volume_mm3"] for p in j["pieces"]),
                "material": j["material_percent"], "grams": j["filament_weight_g"],
                "hours": j["estimated_print_time_s"] / 3600, "cpu": cpu,
                "passed": passed, "failed": failed}


def main():
    names = sys.argv[1:] or ["cat", "elephant", "fandisk", "man", "skull"]
    rows = [run(n) for n in names]
    lines = ["# --cut auto on the shared models at 3x, Prusa MK3S (bench/cut.py)", "",
             "Each model scaled 3x, cut by `--cut auto` into pieces that fit the MK3S "
             "(250 x 210 x 210 mm, less the skirt's room): across z when that fits, across x "
             "and y too when the footprint does not (the skull, 225 x 314 x 360 mm, issue #48), "
             "each piece then on its largest cut face; dowel holes by default. Time to "
             "slice: the CPU time (user + system) of the whole run, every plate. Plates pass: "
             "how many plates pass `carve check --mesh --strict` against the plate's own mesh "
             "(`--plate-meshes`).", "",
             "| model | planes (mm from the model's corner) | pieces | plates | connectors | pieces' volume / model "
             "| material % | filament g | print time h | time to slice CPU s | plates pass |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['name']} | refused: {r['error']} ||||||||||")
            continue
        planes = ", ".join(r["planes"])
        lines.append(f"| {r['name']} | {planes} | {r['pieces']} | {r['plates']} | "
                     f"{r['connectors']} | {r['pieces_volume'] / r['volume']:.4f} | "
                     f"{r['material']:.2f} | {r['grams']:.0f} | {r['hours']:.1f} | "
                     f"{r['cpu']:.1f} | {r['passed']} of {r['plates']} |")
    for r in rows:
        for f in r.get("failed", []):
            lines.append(f"- {r['name']}: {f}")
    lines += ["", "Commands (from the repository, models in /work/shared/models):", ""]
    lines += [f"    carve {r['command']}" for r in rows if "command" in r]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(ROOT, "bench", "results", "cut.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
