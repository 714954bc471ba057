#!/usr/bin/python3
"""Issue 37: where the report scheme's cavity walls lie on a model, from the mesh alone.

The report's nested cavities line every wedge that a 45-degree cavity roof leaves under a surface
shallower than 45 degrees (a dome), once per iteration; so the cavity walls follow the model's
shallow upward-facing surface. This prints, for a model at a scale and in an orientation, its
surface area, the shallow upward (normal within 45 degrees of +z) and downward parts, per 10 mm
band of z, and writes the rotated mesh so that carve can slice it (carve has no rotation option).

    /usr/bin/python3 bench/skull_geometry.py skull --scale 1.43
    /usr/bin/python3 bench/skull_geometry.py skull --scale 1.43 --rotate x-90 --write /tmp/s.stl
    /usr/bin/python3 bench/skull_geometry.py skull --scale 1.43 --bands xband.txt

--bands reads the per-band wall volumes (lines "XBAND z c1 c2 ...", cm3 per 5 mm band and
cavity) that the measurement patch bench/patches/issue37_measure.patch prints on stderr with
CARVE_X_HIST=1, and puts them beside the areas.
"""
import argparse
import os

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS_DIR = os.path.join(os.path.dirname(ROOT), "shared", "models")
RECORD = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])


def rotation(spec):
    if not spec:
        return np.eye(3)
    axis, deg = spec[0], float(spec[1:])
    t = np.radians(deg)
    c, s = np.cos(t), np.sin(t)
    return {"x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])}[axis]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("model")
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--rotate", default="", help="x90, x-90, x180, y90 ...: about that axis, deg")
    ap.add_argument("--write", help="write the rotated (unscaled) mesh here, centred, on z = 0")
    ap.add_argument("--bands", help="XBAND lines from a CARVE_X_HIST=1 run")
    args = ap.parse_args()
    path = args.model if args.model.endswith(".stl") else os.path.join(MODELS_DIR,
                                                                       args.model + ".stl")
    data = open(path, "rb").read()
    n = int.from_bytes(data[80:84], "little")
    rec = np.frombuffer(data[84:84 + 50 * n], dtype=RECORD).copy()
    m = rotation(args.rotate)
    v = rec["v"].astype(np.float64) @ m.T
    lo, hi = v.reshape(-1, 3).min(0), v.reshape(-1, 3).max(0)
    v[:, :, 0] -= (lo[0] + hi[0]) / 2
    v[:, :, 1] -= (lo[1] + hi[1]) / 2
    v[:, :, 2] -= lo[2]
    if args.write:
        rec["v"] = v.astype(np.float32)
        rec["n"] = (rec["n"].astype(np.float64) @ m.T).astype(np.float32)
        open(args.write, "wb").write(data[:84] + rec.tobytes())
    v *= args.scale
    cross = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    norm = np.linalg.norm(cross, axis=1)
    area = norm / 2
    nz = cross[:, 2] / np.maximum(norm, 1e-30)
    volume = np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6
    up, down = nz > np.cos(np.pi / 4), nz < -np.cos(np.pi / 4)
    sphere = 4 * np.pi * (3 * volume / (4 * np.pi)) ** (2 / 3)
    print(f"{os.path.basename(path)} x{args.scale:g} {args.rotate or 'as stored'}: "
          f"{volume / 1000:.0f} cm3, surface {area.sum() / 100:.0f} cm2 "
          f"({area.sum() / sphere:.2f} x a sphere's), shallower than 45 deg: up "
          f"{area[up].sum() / 100:.0f} cm2, down {area[down].sum() / 100:.0f} cm2")
    bands = {}
    if args.bands:
        for line in open(args.bands):
            f = line.split()
            if f and f[0] == "XBAND":
                bands[int(f[1])] = [float(x) for x in f[2:]]
    zc = v[:, :, 2].mean(axis=1)
    print("| z mm | surface cm2 | shallow up cm2 | shallow down cm2 |"
          + (" walls C1 cm3 | walls C2..Ck cm3 |" if bands else ""))
    print("|---|---|---|---|" + ("---|---|" if bands else ""))
    for z in range(0, int(np.ceil(zc.max() / 10)) * 10, 10):
        b = (zc >= z) & (zc < z + 10)
        row = (f"| {z}-{z + 10} | {area[b].sum() / 100:.0f} | {area[b & up].sum() / 100:.1f} | "
               f"{area[b & down].sum() / 100:.1f} |")
        if bands:
            lo5, hi5 = bands.get(z, []), bands.get(z + 5, [])
            c1 = sum(x[0] for x in (lo5, hi5) if x)
            rest = sum(sum(x[1:]) for x in (lo5, hi5) if x)
            row += f" {c1:.2f} | {rest:.2f} |"
        print(row)


if __name__ == "__main__":
    main()
