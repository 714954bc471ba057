#!/usr/bin/python3
"""Seed corpora for the fuzz targets, made at run time from the shared models.

Usage: make_seeds.py MODELS_DIR OUT_DIR

Every STL found in MODELS_DIR, MODELS_DIR/bad and MODELS_DIR/synthetic is read (binary or
ASCII); files above 2 MB are skipped. Each is cut to its first 200 facets (keeps inputs small,
so that fuzzing stays fast) and written as a seed for every target in its format: binary STL,
ASCII STL, OBJ, 3MF (zipped, and as bare XML behind the marker byte that threemf_fuzz zips
itself) and a grid triangle soup for slicer_fuzz. The raw bad/ files go in unchanged too.
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


def main():
    models, out = sys.argv[1], sys.argv[2]
    targets = ["stl_binary_fuzz", "stl_ascii_fuzz", "obj_fuzz", "threemf_fuzz", "slicer_fuzz"]
    for t in targets:
        os.makedirs(os.path.join(out, t), exist_ok=True)
    count = 0
    for sub in ["bad", "synthetic", ""]:
        folder = os.path.join(models, sub)
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
