#!/usr/bin/python3
"""Seed corpora for the fuzz targets, made at run time from the shared models.

Usage: make_seeds.py MODELS_DIR OUT_DIR [PRUSA_BUNDLE]

Every STL found in MODELS_DIR, MODELS_DIR/bad and MODELS_DIR/synthetic is read (binary or
ASCII); files above 2 MB are skipped. Each is cut to its first 200 facets (keeps inputs small,
so that fuzzing stays fast) and written as a seed for every target in its format: binary STL,
ASCII STL, OBJ, 3MF (zipped, and as bare XML behind the marker byte that threemf_fuzz zips
itself) and a grid triangle soup for slicer_fuzz. The raw bad/ files go in unchanged too.

PrusaSlicer's own vendor bundle (PRUSA_BUNDLE, default Debian's
/usr/share/PrusaSlicer/profiles/PrusaResearch.ini, skipped if missing) seeds the profile,
placeholder and command-line targets: its sections as flat profiles (ini_fuzz), its start and
end G-code and printer conditions with the printer notes they test (placeholder_fuzz), and
command lines with its values (cli_fuzz). The bundle itself is not part of the repository.
"""
import io
import math
import os
import struct
import sys
import zipfile

MAX_BYTES = 2 * 1024 * 1024
MAX_FACETS = 200


def read_stl(data):
    """List of facets ((x,y,z)*3) or None if the bytes are neither binary nor ASCII STL."""
    if len(data) >= 84:
        n = struct.unpack_from("<I", data, 80)[0]
        if len(data) == 84 + 50 * n:
            return [struct.unpack_from("<9f", data, 84 + 50 * i + 12) for i in range(n)]
    try:
        words = data.decode("ascii").split()
    except UnicodeDecodeError:
        return None
    if not words or words[0].lower() != "solid":
        return None
    facets, loop = [], []
    for i, w in enumerate(words):
        if w.lower() == "vertex":
            try:
                loop.extend(float(v) for v in words[i + 1:i + 4])
            except ValueError:
                return None
            if len(loop) == 9:
                facets.append(tuple(loop))
                loop = []
    return facets


def binary_stl(facets):
    out = bytearray(b"carve fuzz seed".ljust(80, b" "))
    out += struct.pack("<I", len(facets))
    for f in facets:
        out += struct.pack("<3f9fH", 0, 0, 0, *f, 0)
    return bytes(out)


def ascii_stl(facets):
    lines = ["solid seed"]
    for f in facets:
        lines += ["facet normal 0 0 0", " outer loop"]
        lines += [f"  vertex {f[3*k]:.6g} {f[3*k+1]:.6g} {f[3*k+2]:.6g}" for k in range(3)]
        lines += [" endloop", "endfacet"]
    lines.append("endsolid seed")
    return ("\n".join(lines) + "\n").encode()


def indexed(facets):
    index, verts, tris = {}, [], []
    for f in facets:
        t = []
        for k in range(3):
            p = f[3 * k:3 * k + 3]
            if p not in index:
                index[p] = len(verts)
                verts.append(p)
            t.append(index[p])
        tris.append(t)
    return verts, tris


def obj(facets):
    verts, tris = indexed(facets)
    lines = [f"v {x:.6g} {y:.6g} {z:.6g}" for x, y, z in verts]
    lines += [f"f {a+1} {b+1} {c+1}" for a, b, c in tris]
    return ("\n".join(lines) + "\n").encode()


def model_xml(facets):
    verts, tris = indexed(facets)
    v = "".join(f'<vertex x="{x:.6g}" y="{y:.6g}" z="{z:.6g}"/>' for x, y, z in verts)
    t = "".join(f'<triangle v1="{a}" v2="{b}" v3="{c}"/>' for a, b, c in tris)
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<model unit="millimeter" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">'
            f'<resources><object id="1" type="model"><mesh><vertices>{v}</vertices>'
            f'<triangles>{t}</triangles></mesh></object></resources>'
            '<build><item objectid="1" transform="1 0 0 0 1 0 0 0 1 5 5 0"/></build></model>\n').encode()


def threemf(facets):
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("_rels/.rels",
                   '<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.'
                   'openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/'
                   '3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/'
                   '2013/01/3dmodel"/></Relationships>')
        z.writestr("3D/3dmodel.model", model_xml(facets))
    return buf.getvalue()


def soup(facets):
    """slicer_fuzz grid mode: byte 0 even, then one byte per coordinate (0.5 mm steps)."""
    coords = [c for f in facets for c in f if math.isfinite(c)]
    if not coords:
        return None
    lo, hi = min(coords), max(coords)
    scale = 255 / (hi - lo) if hi > lo else 1
    out = bytearray([0])
    for f in facets:
        out += bytes(min(255, max(0, round(((c if math.isfinite(c) else lo) - lo) * scale)))
                     for c in f)
    return bytes(out)


def bundle_sections(path):
    """[(header, [(key, value)])] of a PrusaSlicer vendor bundle."""
    sections, current = [], None
    for line in open(path, encoding="utf-8", errors="replace"):
        line = line.rstrip("\n")
        if line.startswith("["):
            current = (line, [])
            sections.append(current)
        elif current is not None and " = " in line:
            k, v = line.split(" = ", 1)
            current[1].append((k.strip(), v))
    return sections


def prusa_seeds(bundle, out):
    for t in ["ini_fuzz", "placeholder_fuzz", "cli_fuzz"]:
        os.makedirs(os.path.join(out, t), exist_ok=True)
    sections = bundle_sections(bundle)
    notes = [v for _, kv in sections for k, v in kv if k == "printer_notes"]
    notes = sorted(set(notes), key=len)[-8:] or ["PRINTER_VENDOR_PRUSA3D PRINTER_MODEL_MK3S"]
    n_ini = n_ph = n_cli = 0
    seen = set()
    for i, (head, kv) in enumerate(sections):
        text = head + "\n" + "".join(f"{k} = {v}\n" for k, v in kv)
        if 0 < len(kv) and len(text) < 65536 and (head.startswith("[printer:") or i % 6 == 0):
            open(os.path.join(out, "ini_fuzz", f"section{i:04d}.ini"), "w").write(text)
            n_ini += 1
        for k, v in kv:
            if k in ("start_gcode", "end_gcode", "start_filament_gcode", "layer_gcode"):
                gcode = v.strip('"').replace("\\n", "\n")
            elif k == "compatible_printers_condition" and v:
                gcode = "{if " + v.strip('"') + "}M117 ok{endif}\n"
            else:
                continue
            if gcode in seen or len(gcode) > 32768:
                continue
            seen.add(gcode)
            blob = notes[n_ph % len(notes)].encode() + b"\0" + gcode.encode()
            open(os.path.join(out, "placeholder_fuzz", f"gcode{n_ph:04d}"), "wb").write(blob)
            n_ph += 1
    # Command lines: the documented jobs, then options carrying the bundle's own values.
    options = {"layer_height": "--layer-height", "nozzle_diameter": "--nozzle",
               "temperature": "--temperature", "bed_temperature": "--bed-temperature",
               "travel_speed": "--travel-speed", "retract_length": "--retract-length",
               "filament_diameter": "--filament-diameter", "retract_lift": "--z-hop"}
    lines = [["slice", "m.stl", "-o", "m.gcode"], ["slice", "m.stl", "-o", "m.gcode", "--stats",
             "m.json", "--report", "r.html", "--preset", "3c1s", "--cavities", "auto"],
             ["info", "m.stl", "--json"], ["check", "m.gcode", "--far-radius", "2"],
             ["--help"], ["slice", "--help"], ["slice", "m.stl", "-o", "m.gcode", "--bed",
             "250x210", "--printer", "mk3s", "--walls", "double", "--timeout", "30"]]
    for head, kv in sections:
        args = ["slice", "m.stl", "-o", "m.gcode"]
        for k, v in kv:
            if k in options:
                args += [options[k], v.split(",")[0].strip()]
        if len(args) > 4 and len(lines) < 200:
            lines.append(args)
    for line in lines:
        open(os.path.join(out, "cli_fuzz", f"args{n_cli:04d}"), "wb").write(
            b"\0".join(a.encode() for a in line))
        n_cli += 1
    print(f"seeds from {bundle}: {n_ini} profiles, {n_ph} G-code texts, {n_cli} command lines")


def main():
    models, out = sys.argv[1], sys.argv[2]
    bundle = sys.argv[3] if len(sys.argv) > 3 else "/usr/share/PrusaSlicer/profiles/PrusaResearch.ini"
    if os.path.exists(bundle):
        prusa_seeds(bundle, out)
    targets = ["stl_binary_fuzz", "stl_ascii_fuzz", "obj_fuzz", "threemf_fuzz", "slicer_fuzz"]
    # Every target's folder, seeded or not: without the bundle the profile targets start empty.
    for t in targets + ["ini_fuzz", "placeholder_fuzz", "cli_fuzz"]:
        os.makedirs(os.path.join(out, t), exist_ok=True)
    count = 0
    # A clone alone has no ../shared/models: its seeds come from the bundled sample instead.
    folders = [(sub, os.path.join(models, sub)) for sub in ["bad", "synthetic", ""]]
    if not os.path.isdir(models):
        sample = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "sample")
        print(f"make_seeds: no {models}; seeding from {os.path.normpath(sample)} alone")
        folders = [("", sample)]
    for sub, folder in folders:
        if not os.path.isdir(folder):
            print(f"make_seeds: no {folder}, skipped")
            continue
        for name in sorted(os.listdir(folder)):
            path = os.path.join(folder, name)
            if not name.endswith(".stl") or os.path.getsize(path) > MAX_BYTES:
                continue
            data = open(path, "rb").read()
            stem = (sub + "_" if sub else "") + name[:-4]
            if sub == "bad":  # the broken files themselves, as they are
                for t in ["stl_binary_fuzz", "stl_ascii_fuzz"]:
                    open(os.path.join(out, t, stem + ".raw"), "wb").write(data)
            facets = read_stl(data)
            if not facets:
                continue
            facets = facets[:MAX_FACETS]
            seeds = {
                "stl_binary_fuzz": binary_stl(facets),
                "stl_ascii_fuzz": ascii_stl(facets),
                "obj_fuzz": obj(facets),
                "threemf_fuzz": threemf(facets),
                "slicer_fuzz": soup(facets),
            }
            for t, blob in seeds.items():
                if blob:
                    open(os.path.join(out, t, stem), "wb").write(blob)
            open(os.path.join(out, "threemf_fuzz", stem + ".xml"), "wb").write(
                b"\x01" + model_xml(facets))
            count += 1
    print(f"seeds from {count} models in {out}")


if __name__ == "__main__":
    main()
