#!/usr/bin/python3
"""carve's print-time estimate against PrusaSlicer's G-code viewer, on the same file (#19).

For each shared model and printer preset, carve slices the model; PrusaSlicer 2.5's G-code
viewer (prusa-gcodeviewer) opens the G-code under Xvfb; the viewer's window is captured and its
"Total:" estimate read back with tesseract. The table compares it with carve's own estimate
(estimated_print_time_s of the stats JSON). The screenshots stay in the work folder, so that a
person can check what was read.

Needs: prusa-slicer, xvfb, imagemagick, tesseract-ocr and an en_US.UTF-8 locale (the
viewer stops on a dialog without one): `--install` installs them with apt-get, as root.

    /usr/bin/python3 bench/viewer_estimate.py [--carve build/carve] [--models cat,fandisk]
        [--printers generic,mk3s] [--work /tmp/viewer_bench] [--out bench/results/viewer_estimate.md]
"""
import argparse
import datetime
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MODELS = ROOT.parent / "shared" / "models"
DISPLAY = ":77"


def install():
    pkgs = ["prusa-slicer", "xvfb", "imagemagick", "tesseract-ocr", "locales"]
    subprocess.run(["apt-get", "install", "-y", "-qq", *pkgs], check=True,
                   env={**os.environ, "DEBIAN_FRONTEND": "noninteractive"})
    gen = Path("/etc/locale.gen")
    text = gen.read_text()
    if "\nen_US.UTF-8 UTF-8" not in "\n" + text:
        gen.write_text(re.sub(r"^# *en_US.UTF-8 UTF-8", "en_US.UTF-8 UTF-8", text, flags=re.M))
    subprocess.run(["locale-gen"], check=True, stdout=subprocess.DEVNULL)


def seconds(text):
    """'1h20m', '58m', '3m 4s', '2d3h' -> seconds."""
    units = {"d": 86400, "h": 3600, "m": 60, "s": 1}
    parts = re.findall(r"(\d+)\s*([dhms])", text)
    return sum(int(v) * units[u] for v, u in parts) if parts else None


def total_from_screen(shot, work):
    """Reads the viewer's "Total:" from a screenshot: finds the window's "File" menu in
    tesseract's word boxes, then reads the legend below it as one block (whole-screen OCR loses
    the legend where the model shows through it)."""
    gray = work / "gray.png"
    subprocess.run(["convert", str(shot), "-colorspace", "Gray", "-negate", str(gray)], check=True)
    tsv = subprocess.run(["tesseract", str(gray), "-", "tsv"], capture_output=True,
                         text=True).stdout
    for row in tsv.splitlines():
        cols = row.split("\t")
        if len(cols) == 12 and cols[11] == "File":
            left, top = int(cols[6]), int(cols[7])
            legend = work / "legend.png"
            # The legend at GDK_SCALE=2: about 700 x 500 pixels under the menu bar.
            subprocess.run(["convert", str(gray), "+repage", "-crop",
                            f"720x520+{max(0, left - 15)}+{top + 43}", "+repage", str(legend)],
                           check=True)
            text = subprocess.run(["tesseract", str(legend), "-", "--psm", "6"],
                                  capture_output=True, text=True).stdout
            m = re.search(r"Total:[^0-9]*([0-9dhms ]+)", text)
            return seconds(m.group(1)) if m else None
    return None


def viewer_total(gcode, shot):
    """Opens gcode in the viewer, screenshots the display, returns the Total in seconds."""
    # GDK_SCALE=2 doubles the legend's font, which tesseract then reads reliably.
    env = {**os.environ, "DISPLAY": DISPLAY, "LC_ALL": "en_US.UTF-8", "LANG": "en_US.UTF-8",
           "GDK_SCALE": "2"}
    viewer = subprocess.Popen(["prusa-gcodeviewer", str(gcode)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        # The legend is drawn once the file is processed; a large file takes a while.
        for _ in range(40):
            time.sleep(3)
            subprocess.run(["import", "-window", "root", str(shot)], env=env, check=True)
            total = total_from_screen(shot, shot.parent)
            if total:
                return total
        return None
    finally:
        viewer.kill()
        viewer.wait()


def fmt_min(s):
    return "-" if s is None else f"{s / 60:.1f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--carve", default=str(ROOT / "build" / "carve"))
    ap.add_argument("--models", default="cat,elephant,fandisk,man,skull")
    ap.add_argument("--printers", default="generic,mk3s")
    ap.add_argument("--work", default="/tmp/viewer_bench")
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "viewer_estimate.md"))
    ap.add_argument("--install", action="store_true")
    args = ap.parse_args()
    if args.install:
        install()
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    xvfb = subprocess.Popen(["Xvfb", DISPLAY, "-screen", "0", "2400x1600x24"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(2)
    rows = []
    try:
        for model in args.models.split(","):
            for printer in args.printers.split(","):
                name = f"{model}_{printer}"
                gcode, stats = work / f"{name}.gcode", work / f"{name}.json"
                subprocess.run([args.carve, "slice", str(MODELS / f"{model}.stl"), "-o", str(gcode),
                                "--stats", str(stats), "--printer", printer, "-q"], check=True)
                carve_s = json.loads(stats.read_text())["estimated_print_time_s"]
                viewer_s = viewer_total(gcode, work / f"{name}.png")
                ratio = None if viewer_s is None else viewer_s / carve_s
                rows.append((model, printer, carve_s, viewer_s, ratio))
                print(f"{name}: carve {fmt_min(carve_s)} min, viewer {fmt_min(viewer_s)} min",
                      file=sys.stderr)
    finally:
        xvfb.kill()
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()
    viewer_version = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "prusa-slicer"],
                                    capture_output=True, text=True).stdout.strip()
    lines = [
        "# carve's estimate against PrusaSlicer's G-code viewer (#19)",
        "",
        f"Made by `bench/viewer_estimate.py` on {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, "
        f"carve from the tree at {head}, prusa-slicer {viewer_version}. The viewer's \"Total\" "
        "is read from a screenshot of the display (tesseract); it shows whole minutes, so ratios "
        "carry up to 2 % of rounding on the shortest files.",
        "",
        "| model | printer | carve min | viewer min | viewer / carve |",
        "|---|---|---:|---:|---:|",
    ]
    for model, printer, carve_s, viewer_s, ratio in rows:
        r = "-" if ratio is None else f"{ratio:.3f}"
        lines.append(f"| {model} | {printer} | {fmt_min(carve_s)} | {fmt_min(viewer_s)} | {r} |")
    Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
