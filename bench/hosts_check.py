#!/usr/bin/python3
"""Runs carve's G-code of every --printer preset through the programs that printers and their
hosts run, beside PrusaSlicer 2.5's G-code of the same model (issue #36):

  (a) Klipper's klippy.py in batch mode (-i FILE -o /dev/null -d DICT), with the stock
      config/kit-voron2-250mm.cfg (generic, klipper), config/printer-creality-ender3-2018.cfg
      (ender3) or config/generic-einsy-rambo.cfg made MK3S-like (mk3s), each with the stock
      config/sample-macros.cfg;
  (b) Moonraker's components/file_manager/metadata.py, run as Moonraker runs it (a script);
  (c) OctoPrint's G-code analyser, src/octoprint/util/gcodeInterpreter.py, with the analysis
      settings of OctoPrint's default printer profile (X/Y 6000 mm/min, bed Z 0).

It writes bench/results/hosts.md. Usage:

  /usr/bin/python3 bench/hosts_check.py --klipper DIR --moonraker DIR --octoprint DIR
      [--carve build/carve] [--models a.stl,b.stl] [--printers generic,mk3s,ender3,klipper]
      [--support-models c.stl]

--support-models are sliced with supports only: carve --support auto, PrusaSlicer
support_material (automatic); their rows are named "MODEL (supports)".

The source trees may also come from KLIPPER_DIR, MOONRAKER_DIR, OCTOPRINT_DIR. Whatever is
missing (a tree, gcc-avr to build Klipper's MCU dictionary, prusa-slicer) is skipped with a
message saying so. Debian packages: gcc-avr avr-libc binutils-avr python3-cffi
python3-greenlet python3-serial python3-jinja2 (Klipper), python3-pil (Moonraker).

Klipper runs under the heat model of bench/klipper_batch.py (a cold extrusion stops it as on
the printer).
"""

import argparse
import collections
import importlib.util
import json
import os
import re
import shutil
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from klipper_batch import run, run_klipper  # noqa: E402 (beside this file)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PRESETS = ["generic", "mk3s", "ender3", "klipper"]
# Which Klipper setup runs each preset's G-code: the printers the presets describe.
KLIPPER_SETUP = {"generic": "voron2", "klipper": "voron2", "ender3": "ender3", "mk3s": "mk3s"}


# --- helpers ------------------------------------------------------------------------------------


def revision(tree):
    r = run(["git", "-C", tree, "log", "-1", "--format=%h %cs"])
    if r.returncode == 0 and r.stdout.strip():
        return r.stdout.strip()
    path = os.path.join(tree, "REVISION")
    return open(path).read().strip() if os.path.isfile(path) else "unknown revision"


def config_block(gcode_path):
    """The '; key = value' lines of a G-code file's PrusaSlicer-style configuration block."""
    keys = {}
    with open(gcode_path, errors="replace") as f:
        f.seek(max(0, os.path.getsize(gcode_path) - 200000))
        for line in f:
            m = re.match(r"^; (\w+) = (.*)$", line.rstrip("\n"))
            if m:
                keys[m.group(1)] = m.group(2)
    return keys


def header_figures(gcode_path):
    """What the slicer's own header says: time (s) and filament (mm)."""
    out = {"time": None, "filament": None}
    with open(gcode_path, errors="replace") as f:
        head = f.read(300000)
    with open(gcode_path, errors="replace") as f:
        f.seek(max(0, os.path.getsize(gcode_path) - 300000))
        tail = f.read()
    m = re.search(r"^;TIME:(\d+)", head, re.M)
    if m:
        out["time"] = float(m.group(1))
    else:
        m = re.search(r"estimated printing time \(normal mode\) = (.*)$", head + tail, re.M)
        if m:
            out["time"] = duration(m.group(1))
    m = re.search(r"^;Filament used: ([\d.]+)m", head, re.M)
    if m:
        out["filament"] = float(m.group(1)) * 1000
    else:
        m = re.search(r"^; filament used \[mm\] = ([\d.]+)", tail, re.M)
        if m:
            out["filament"] = float(m.group(1))
    return out


def duration(text):
    s = 0.0
    for n, unit in re.findall(r"(\d+)([dhms])", text):
        s += int(n) * {"d": 86400, "h": 3600, "m": 60, "s": 1}[unit]
    return s


def hms(s):
    if s is None:
        return "–"
    s = int(round(s))
    return "%d:%02d:%02d" % (s // 3600, s // 60 % 60, s % 60)


def pct(a, b):
    if a is None or b is None or not b:
        return ""
    return " (%+.1f %%)" % (100.0 * (a - b) / b)


# --- Moonraker and OctoPrint --------------------------------------------------------------------


def run_moonraker(moonraker, gcode, work):
    script = os.path.join(moonraker, "moonraker", "components", "file_manager", "metadata.py")
    d = tempfile.mkdtemp(dir=work, prefix="moonraker_")
    name = os.path.basename(gcode)
    os.symlink(os.path.abspath(gcode), os.path.join(d, name))
    r = run([sys.executable, script, "-f", name, "-p", d], timeout=600)
    if r.returncode != 0:
        return {"error": (r.stderr.strip().splitlines() or ["exit %d" % r.returncode])[-1]}
    m = json.loads(r.stdout)["metadata"]
    m["thumbnails"] = ["%dx%d" % (t["width"], t["height"]) for t in m.get("thumbnails", [])]
    return m


def load_octoprint(octoprint):
    path = os.path.join(octoprint, "src", "octoprint", "util", "gcodeInterpreter.py")
    spec = importlib.util.spec_from_file_location("octoprint_gcodeInterpreter", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_octoprint(module, gcode):
    g = module.gcode()
    # OctoPrint's defaults: the default profile's X/Y speeds, settings gcodeAnalysis.bedZ 0.
    g.load(gcode, speedx=6000, speedy=6000, bed_z=0.0)
    r = g.get_result()
    return {"time": r["total_time"] * 60, "filament": sum(r["extrusion_length"]),
            "dims": r["dimensions"], "area": r["printing_area"]}


# --- the slicers --------------------------------------------------------------------------------

# What the PrusaSlicer peer takes from carve's configuration block: the printer, the filament,
# the start and end G-code; its own print settings are BASELINES.md's lightning.
PEER_KEYS = ["bed_shape", "max_print_height", "gcode_flavor", "nozzle_diameter", "layer_height",
             "first_layer_height", "filament_diameter", "temperature", "bed_temperature",
             "first_layer_temperature", "first_layer_bed_temperature", "filament_density",
             "travel_speed", "external_perimeter_speed", "perimeter_speed", "solid_infill_speed",
             "bridge_speed", "first_layer_speed", "retract_length", "retract_speed",
             "retract_lift", "skirts", "skirt_distance", "skirt_height", "brim_width",
             "start_gcode", "end_gcode", "use_relative_e_distances", "printer_model",
             "silent_mode", "filament_type", "filament_colour", "thumbnails",
             "machine_max_acceleration_x", "machine_max_acceleration_y",
             "machine_max_acceleration_z", "machine_max_acceleration_e",
             "machine_max_acceleration_extruding", "machine_max_acceleration_retracting",
             "machine_max_acceleration_travel", "machine_max_feedrate_x",
             "machine_max_feedrate_y", "machine_max_feedrate_z", "machine_max_feedrate_e",
             "machine_max_jerk_x", "machine_max_jerk_y", "machine_max_jerk_z",
             "machine_max_jerk_e"]
PEER_PRINT = {"perimeters": "1", "top_solid_layers": "2", "bottom_solid_layers": "2",
              "fill_density": "10%", "fill_pattern": "lightning",
              "top_solid_min_thickness": "0", "bottom_solid_min_thickness": "0"}


def slice_prusa(carve_gcode, model, out, work, support=False):
    keys = config_block(carve_gcode)
    ini = {k: keys[k] for k in PEER_KEYS if k in keys}
    ini.update(PEER_PRINT)
    if support:
        ini["support_material"] = "1"
    ini["machine_limits_usage"] = ("time_estimate_only" if ini.get("gcode_flavor") == "klipper"
                                   else "emit_to_gcode")
    ini_path = out + ".ini"
    with open(ini_path, "w") as f:
        f.writelines("%s = %s\n" % kv for kv in ini.items())
    cmd = ["prusa-slicer", "--export-gcode", "--load", ini_path, "-o", out, model]
    r = run(cmd, timeout=1800)
    if r.returncode != 0 or not os.path.isfile(out):
        # The CLI renders thumbnails with OpenGL; without a display it may not.
        with open(ini_path, "a") as f:
            f.write("thumbnails = \n")
        r = run(cmd, timeout=1800)
        if r.returncode != 0 or not os.path.isfile(out):
            return "prusa-slicer failed: " + (r.stderr.strip().splitlines() or ["?"])[-1]
        return "no thumbnails (the CLI could not render them)"
    return None


def model_height(carve, model):
    r = run([carve, "info", model, "--json"])
    return json.loads(r.stdout)["size_mm"][2] if r.returncode == 0 else None


# --- the report ---------------------------------------------------------------------------------


def klipper_cell(k, estimate):
    if k is None:
        return "not run", ""
    if "skipped" in k:
        return "skipped: " + k["skipped"], ""
    if k["ok"]:
        verdict = "**ok**"
    else:
        verdict = "**stops**: " + (k["errors"][0] if k["errors"] else "exit %d" % k["rc"])
        if k["heat"]:
            verdict += " (heat model: " + "; ".join(k["heat"][-3:]) + ")"
    if k["unknown"]:
        verdict += "; unknown (ignored): " + ", ".join(
            "`%s` ×%d" % (c, n) if n > 1 else "`%s`" % c for c, n in sorted(k["unknown"].items()))
    p = k.get("pause")
    if p is not None and "skipped" not in p:
        verdict += "; with `--pause-at %g`: %s, paused %d×" % (
            k["pause_at"], "ok" if p["ok"] else "**stops**: " + (p["errors"] or ["?"])[0],
            p["paused"])
    t = k["print_time"]
    u = (k.get("unheated") or {}).get("print_time")
    if not t and u:
        return verdict, "– (without the heat model: %s vs %s%s)" % (
            hms(u), hms(estimate), pct(estimate, u))
    return verdict, ("%s vs %s%s" % (hms(t), hms(estimate), pct(estimate, t)) if t else "–")


def klipper_error(row):
    """The header's estimate in % of Klipper's time, and whether that time is the heat model's
    (False: the file stopped cold and was timed without it); None where there is no time."""
    k, est = row.get("klipper") or {}, row["header"]["time"]
    if not est:
        return None
    if k.get("ok") and k.get("print_time"):
        return 100.0 * (est - k["print_time"]) / k["print_time"], True
    u = (k.get("unheated") or {}).get("print_time")
    if u:
        return 100.0 * (est - u) / u, False
    return None


def estimate_table(rows, presets):
    """Per preset and model: carve's and PrusaSlicer's estimate in % of Klipper's time."""
    models = list(dict.fromkeys(r["model"] for r in rows))
    out = ["| preset | " + " | ".join("%s: carve / PrusaSlicer" % m for m in models) + " |",
           "|---|" + "---|" * len(models)]
    for preset in presets:
        cells = []
        for m in models:
            pair = []
            for slicer in ("carve", "PrusaSlicer"):
                r = next((r for r in rows if r["preset"] == preset and r["model"] == m
                          and r["slicer"] == slicer), None)
                e = klipper_error(r) if r else None
                pair.append("–" if e is None else "%+.1f %%%s" % (e[0], "" if e[1] else "*"))
            cells.append(" / ".join(pair))
        out.append("| %s | %s |" % (preset, " | ".join(cells)))
    return out


def write_report(path, rows, meta, notes):
    out = ["# carve's G-code on printers' hosts and firmware (issue #36)", "",
           "Written by `bench/hosts_check.py` on %s; carve %s. Each preset's G-code of each model "
           "goes through (a) Klipper's `klippy.py` in batch mode, (b) Moonraker's `metadata.py`, "
           "(c) OctoPrint's `gcodeInterpreter`, beside PrusaSlicer's G-code of the same model "
           "with the same printer, filament, start and end G-code (its print settings: "
           "BASELINES.md's lightning, 1 perimeter, 2/2 solid layers, 10 %% lightning infill)."
           % (meta["date"], meta["carve"]), "",
           "Sources: Klipper %s, Moonraker %s, OctoPrint %s, %s." % (
               meta["klipper"], meta["moonraker"], meta["octoprint"], meta["prusa"]), "",
           "Klipper setups (stock files of Klipper's `config/`, each with `sample-macros.cfg`, "
           "a `[virtual_sdcard]` and the MCU dictionary built with Debian's gcc-avr):",
           "- generic, klipper: `kit-voron2-250mm.cfg` (its PRINT_START reads no parameters and "
           "turns the hot end off: `M104 S0`), the Arduino Mega pin names of "
           "`sample-aliases.cfg` for the macros' beeper;",
           "- ender3: `printer-creality-ender3-2018.cfg` (atmega1284p), the beeper on PA4;",
           "- mk3s: `generic-einsy-rambo.cfg` with the MK3S's travel (X 0-255, Y -4-212.5, "
           "Z 0-210), without its `[tmc2130]` sections (batch mode reads every driver register as "
           "0, and their periodic check shut klippy down), the beeper on PH2, `[display_status]` (M73) and `max_extrude_cross_section: "
           "1.0` (the intro line of PrusaSlicer's MK3S start G-code, which carve's preset "
           "copies, is 0.75 mm² wide: both files stopped on it with the stock 0.64).", "",
           "Klipper's batch mode lets every extrusion through and does not wait for heaters, so "
           "klippy runs under a heat model: a heater is hot once a wait (M109, M190, "
           "TEMPERATURE_WAIT) asked for at least its `min_extrude_temp`, cold once its target "
           "drops below that; a cold extrusion then stops the run with Klipper's own "
           "`Extrude below minimum temp`. Klipper's print time is its planner's, from the "
           "first command to the last (the macros' moves included, heating excluded); the "
           "estimate beside it is the slicer's header, its difference in % of Klipper's.", "",
           "Moonraker's columns: `object_height` (must equal the model's height), "
           "`estimated_time`, `filament_total` (vs the header's filament), first layer height "
           "and temperatures, thumbnails. OctoPrint's: the printed volume's dimensions, "
           "filament length, time estimate (its own model: no acceleration).", ""]
    out += ["## Summary", ""]
    for slicer in ("carve", "PrusaSlicer"):
        mine = [r for r in rows if r["slicer"] == slicer]
        if not mine:
            continue
        ks = [r["klipper"] for r in mine if r.get("klipper") and "skipped" not in r["klipper"]]
        ms = [r for r in mine if r.get("moonraker") and "error" not in r["moonraker"]]
        tall = [r for r in ms if r["height"] is not None and
                abs(r["moonraker"].get("object_height", -1) - r["height"]) < 0.051]
        dt = [100.0 * (r["header"]["time"] - r["klipper"]["print_time"]) /
              r["klipper"]["print_time"] for r in mine if r.get("klipper")
              and r["klipper"].get("print_time") and r["klipper"].get("ok")
              and r["header"]["time"]]
        out.append("- %s: Klipper runs to the end on %d of %d files; Moonraker's object height "
                   "is the model's on %d of %d; the header's estimate is %s of Klipper's time."
                   % (slicer, sum(k["ok"] for k in ks), len(ks), len(tall), len(ms),
                      "%+.1f to %+.1f %%" % (min(dt), max(dt)) if dt else "never beside"))
    out += ["", "Reading the peer's rows: PrusaSlicer gets carve's start and end G-code but not "
            "the `before_layer_gcode` of its own profiles (`;BEFORE_LAYER_CHANGE` and `;[layer_z]`"
            " in the MK3S one); without it Moonraker takes the highest `G1 Z.. F..`, the end "
            "G-code's lift. PrusaSlicer writes M109 after the start G-code (M104 before it): "
            "with the ender3 start G-code, whose purge line has no wait of its own, its file "
            "purges cold; PrusaSlicer's own Ender-3 profile waits inside its start G-code. "
            "Commands Klipper does not know (M201, M203, M205, the MK3S's M862.x and G80; "
            "RESPOND, which sample-macros.cfg's M117 calls without a `[respond]` section) are "
            "answered `Unknown command` and skipped: they do not stop a print. PrusaSlicer "
            "2.5's CLI wrote no thumbnails though its `thumbnails` key is set.", ""]
    for note in notes:
        out.append("- " + note)
    if notes:
        out.append("")
    out += ["## Estimates against Klipper's time (issue #51, item 5)", ""]
    out += estimate_table(rows, meta["presets"])
    out += ["", "\\* the file stopped cold under the heat model (see its row): Klipper's time "
            "without it, every extrusion let through.", ""]
    for preset in meta["presets"]:
        out += ["## --printer %s (Klipper: %s)" % (preset, KLIPPER_SETUP[preset]), "",
                "| model | slicer | Klipper | Klipper time vs header estimate | Moonraker "
                "height (model) | Moonraker time · filament mm (header) | Moonraker 1st layer "
                "· temps · thumbnails | OctoPrint W×D×H mm | OctoPrint filament mm · time |",
                "|---|---|---|---|---|---|---|---|---|"]
        for r in (r for r in rows if r["preset"] == preset):
            h = r["header"]
            verdict, ktime = klipper_cell(r.get("klipper"), h["time"])
            mr = r.get("moonraker")
            if mr is None:
                mcells = ["not run"] * 3
            elif "error" in mr:
                mcells = ["error: " + mr["error"], "", ""]
            else:
                height = mr.get("object_height")
                ok = "" if height is None or r["height"] is None else (
                    " ✓" if abs(height - r["height"]) < 0.051 else " **✗**")
                mcells = ["%s (%.2f)%s" % (height, r["height"] or 0, ok),
                          "%s · %s (%s)" % (hms(mr.get("estimated_time")),
                                            mr.get("filament_total"),
                                            "%.1f" % h["filament"] if h["filament"] else "–"),
                          "%s · %s/%s · %s" % (mr.get("first_layer_height"),
                                               mr.get("first_layer_extr_temp"),
                                               mr.get("first_layer_bed_temp"),
                                               ",".join(mr.get("thumbnails")) or "none")]
            op = r.get("octoprint")
            if op is None:
                ocells = ["not run", ""]
            elif "error" in op:
                ocells = ["error: " + op["error"], ""]
            else:
                d = op["dims"]
                ocells = ["%.1f×%.1f×%.1f" % (d["width"], d["depth"], d["height"]),
                          "%.1f · %s" % (op["filament"], hms(op["time"]))]
            out.append("| %s | %s | %s | %s | %s |" % (
                r["model"], r["slicer"] + (" (%s)" % r["note"] if r.get("note") else ""),
                verdict, ktime, " | ".join(mcells + ocells)))
        out.append("")
    with open(path, "w") as f:
        f.write("\n".join(out))


# --- main ---------------------------------------------------------------------------------------


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--klipper", default=os.environ.get("KLIPPER_DIR"))
    ap.add_argument("--moonraker", default=os.environ.get("MOONRAKER_DIR"))
    ap.add_argument("--octoprint", default=os.environ.get("OCTOPRINT_DIR"))
    ap.add_argument("--carve", default=os.path.join(REPO, "build", "carve"))
    ap.add_argument("--models", default=",".join([
        os.path.join(REPO, "data", "sample", "fandisk.stl"),
        os.path.join(REPO, "..", "shared", "models", "cat.stl")]))
    ap.add_argument("--support-models", default="",
                    help="models sliced with supports (carve --support auto) instead")
    ap.add_argument("--printers", default=",".join(PRESETS))
    ap.add_argument("--no-prusa", action="store_true", help="leave PrusaSlicer's G-code out")
    ap.add_argument("--work", default=None, help="scratch directory [a new temporary one]")
    ap.add_argument("--out", default=os.path.join(REPO, "bench", "results", "hosts.md"))
    a = ap.parse_args()

    work = a.work or tempfile.mkdtemp(prefix="carve_hosts_")
    os.makedirs(work, exist_ok=True)
    notes = []

    def tree(name, path, probe):
        if not path:
            notes.append("%s skipped: no source tree given (--%s or %s_DIR)"
                         % (name, name.lower(), name.upper()))
        elif not os.path.isfile(os.path.join(path, probe)):
            notes.append("%s skipped: %s not found" % (name, os.path.join(path, probe)))
        else:
            return os.path.abspath(path)
        print(notes[-1], file=sys.stderr)
        return None

    klipper = tree("Klipper", a.klipper, "klippy/klippy.py")
    moonraker = tree("Moonraker", a.moonraker,
                     "moonraker/components/file_manager/metadata.py")
    octoprint = tree("OctoPrint", a.octoprint, "src/octoprint/util/gcodeInterpreter.py")
    if not os.access(a.carve, os.X_OK):
        sys.exit("carve not found at %s: build it (cmake --build build --target carve)" % a.carve)
    prusa = None if a.no_prusa else shutil.which("prusa-slicer")
    if not prusa and not a.no_prusa:
        notes.append("PrusaSlicer skipped: prusa-slicer not found")
    if moonraker:
        r = run([sys.executable, "-c", "import PIL"])
        if r.returncode != 0:
            notes.append("Moonraker skipped: its metadata.py needs PIL (Debian: python3-pil)")
            moonraker = None
    octo = load_octoprint(octoprint) if octoprint else None

    carve_version = run(["git", "-C", REPO, "log", "-1", "--format=%h"]).stdout.strip()
    prusa_version = "no PrusaSlicer"
    if prusa:
        m = re.search(r"PrusaSlicer-\S+", run([prusa, "--help"]).stdout)
        prusa_version = m.group(0) if m else "PrusaSlicer"
    meta = {"date": time.strftime("%Y-%m-%d"), "carve": carve_version,
            "klipper": revision(klipper) if klipper else "–",
            "moonraker": revision(moonraker) if moonraker else "–",
            "octoprint": revision(octoprint) if octoprint else "–",
            "prusa": prusa_version, "presets": a.printers.split(",")}
    rows = []
    jobs = [(m, False) for m in a.models.split(",") if m]
    jobs += [(m, True) for m in a.support_models.split(",") if m]
    for model, support in jobs:
        extra = ["--support", "auto"] if support else []
        name = os.path.splitext(os.path.basename(model))[0]
        label = name + (" (supports)" if support else "")
        name += "_support" if support else ""
        if not os.path.isfile(model):
            notes.append("model %s skipped: not found" % model)
            continue
        height = model_height(a.carve, model)
        for preset in meta["presets"]:
            g = os.path.join(work, "%s_%s_carve.gcode" % (name, preset))
            r = run([a.carve, "slice", model, "-o", g, "--printer", preset, "-q"] + extra)
            if r.returncode != 0:
                notes.append("carve failed on %s --printer %s: %s" % (name, preset, r.stderr))
                continue
            files = [("carve", g, None)]
            if prusa:
                p = os.path.join(work, "%s_%s_prusa.gcode" % (name, preset))
                why = slice_prusa(g, model, p, work, support)
                if why is None or why.startswith("no thumbnails"):
                    files.append(("PrusaSlicer", p, why))
                else:
                    notes.append("%s %s: %s" % (name, preset, why))
            for slicer, path, note in files:
                row = {"model": label, "preset": preset, "slicer": slicer, "note": note,
                       "height": height, "header": header_figures(path)}
                print("%s %s %s" % (name, preset, slicer), file=sys.stderr)
                if klipper:
                    row["klipper"] = run_klipper(klipper, KLIPPER_SETUP[preset], path, work)
                    k = row["klipper"]
                    if slicer != "carve" and any("below minimum temp" in e
                                                 for e in k.get("errors", [])):
                        # Timed without the heat model too, so that its estimate has a
                        # Klipper time to be read against.
                        k["unheated"] = run_klipper(klipper, KLIPPER_SETUP[preset], path, work,
                                                    heat_model=False)
                    if slicer == "carve" and height:
                        # The pause (M600 through sample-macros.cfg's macro, or PAUSE) at half
                        # the height: [pause_resume] takes it, the batch goes on.
                        z = round(height / 2)
                        pg = os.path.join(work, "%s_%s_pause.gcode" % (name, preset))
                        r = run([a.carve, "slice", model, "-o", pg, "--printer", preset, "-q",
                                 "--pause-at", str(z)] + extra)
                        if r.returncode == 0:
                            row["klipper"]["pause"] = run_klipper(
                                klipper, KLIPPER_SETUP[preset], pg, work)
                            row["klipper"]["pause_at"] = z
                if moonraker:
                    row["moonraker"] = run_moonraker(moonraker, path, work)
                if octo:
                    try:
                        row["octoprint"] = run_octoprint(octo, path)
                    except Exception as e:  # the analyser's own failure is a finding
                        row["octoprint"] = {"error": repr(e)}
                rows.append(row)
    with open(os.path.join(work, "hosts.json"), "w") as f:
        json.dump(rows, f, indent=1, default=lambda o: dict(o) if isinstance(o, collections.Counter)
                  else str(o))
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    write_report(a.out, rows, meta, notes)
    print("wrote %s (scratch: %s)" % (a.out, work), file=sys.stderr)
    bad = [r for r in rows if r["slicer"] == "carve" and r.get("klipper")
           and "skipped" not in r["klipper"] and not r["klipper"]["ok"]]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
