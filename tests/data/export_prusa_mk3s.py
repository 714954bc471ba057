#!/usr/bin/python3
"""Regenerates tests/data/prusa_mk3s.ini, the real PrusaSlicer profile the loader tests read.

PrusaSlicer's command line cannot select a system preset by name, so this script resolves the
inheritance chain of three presets in Debian's PrusaResearch vendor bundle (printer, print,
filament) into one flat file, loads it into prusa-slicer and lets prusa-slicer --save write its
complete configuration (every key it knows, in its own formatting).

usage: tests/data/export_prusa_mk3s.py   (needs /usr/bin/prusa-slicer)
"""
import configparser
import os
import subprocess
import sys
import tempfile

BUNDLE = "/usr/share/PrusaSlicer/profiles/PrusaResearch.ini"
PRESETS = [("printer", "Original Prusa i3 MK3S & MK3S+"),
           ("print", "0.20mm QUALITY @MK3"),
           ("filament", "Prusament PLA")]
# Keys that belong to the bundle's bookkeeping, not to a configuration.
SKIP = {"inherits", "renamed_from", "alias", "compatible_printers_condition",
        "compatible_prints_condition", "default_print_profile",
        "default_filament_profile", "printer_variant"}


def main():
    bundle = configparser.RawConfigParser(strict=False, interpolation=None)
    bundle.optionxform = str
    bundle.read(BUNDLE, encoding="utf-8")

    def resolve(kind, name, seen=()):
        section = f"{kind}:{name}"
        if section in seen:
            sys.exit(f"inheritance loop at {section}")
        keys = {}
        own = dict(bundle[section])
        for parent in own.get("inherits", "").split(";"):
            parent = parent.strip().strip('"')
            if parent:
                keys.update(resolve(kind, parent, seen + (section,)))
        keys.update({k: v for k, v in own.items() if k not in SKIP})
        return keys

    flat = {}
    for kind, name in PRESETS:
        flat.update(resolve(kind, name))
        # As PrusaSlicer's GUI records them on export; custom G-code tests these names.
        flat[f"{kind}_settings_id"] = f'"{name}"' if kind == "filament" else name
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "prusa_mk3s.ini")
    with tempfile.TemporaryDirectory() as tmp:
        flat_path = os.path.join(tmp, "flat.ini")
        with open(flat_path, "w", encoding="utf-8") as f:
            for k, v in flat.items():
                f.write(f"{k} = {v}\n")
        subprocess.run(["prusa-slicer", "--datadir", tmp, "--load", flat_path, "--save", out],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    print(out)


if __name__ == "__main__":
    main()
