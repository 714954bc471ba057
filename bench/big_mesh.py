#!/usr/bin/python3
"""Writes a closed 2-million-triangle binary STL: a rippled torus (1000 x 1000 quads).

Usage: big_mesh.py OUT.stl [SEGMENTS]   (2 * SEGMENTS^2 triangles; default 1000)

Major radius 60 mm, minor radius 22 mm with a 1 mm ripple, so that the model is about 165 mm
wide and 45 mm tall (fits the default 250 x 210 bed) and no two slices are alike.
"""
import sys

import numpy as np


def main():
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    u = np.linspace(0, 2 * np.pi, n, endpoint=False)
    v = np.linspace(0, 2 * np.pi, n, endpoint=False)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    r = 22 + 1.0 * np.sin(7 * uu) * np.cos(5 * vv)
    x = (60 + r * np.cos(vv)) * np.cos(uu) + 100
    y = (60 + r * np.cos(vv)) * np.sin(uu) + 100
    z = r * np.sin(vv) + 25
    p = np.stack([x, y, z], axis=-1).astype(np.float32)  # (n, n, 3)
    i1 = np.roll(np.arange(n), -1)
    a = p
    b = p[i1, :]        # next u
    c = p[i1][:, i1]    # next u, next v
    d = p[:, i1]        # next v
    # Outward (counter-clockwise seen from outside) for this parametrisation.
    t1 = np.stack([a, b, c], axis=2).reshape(-1, 3, 3)
    t2 = np.stack([a, c, d], axis=2).reshape(-1, 3, 3)
    tris = np.concatenate([t1, t2])
    rec = np.zeros(len(tris), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = tris
    with open(out, "wb") as f:
        f.write(b"carve big mesh bench".ljust(80, b" "))
        f.write(np.uint32(len(tris)).tobytes())
        rec.tofile(f)
    print(f"{out}: {len(tris)} triangles")


if __name__ == "__main__":
    main()
