#!/usr/bin/python3
"""Writes N random, disconnected triangles in a 100 mm cube (a triangle soup).

Usage: soup.py OUT [N] [SEED] [--ascii]   (default N = 3,000,000; seed 1)

OUT ending in .obj gives an OBJ with three vertex lines a face; otherwise a binary STL (150 MB
for the default N), or an ASCII STL with --ascii. carve slice refuses such a file (it is no
solid); what the refusal costs (issue #22) is measured with
`/usr/bin/time -v build/carve slice OUT -o /tmp/x.gcode` (Maximum resident set size).
Standard library only, so that it runs with the system Python.
"""
import random
import struct
import sys


def corners(rng):
    return [rng.uniform(0, 100) for _ in range(9)]


def write_binary(f, n, rng):
    facet = struct.Struct("<12fH")
    f.write(b"random triangle soup (bench/soup.py)".ljust(80, b" "))
    f.write(struct.pack("<I", n))
    chunk = []
    for _ in range(n):
        chunk.append(facet.pack(0, 0, 0, *corners(rng), 0))
        if len(chunk) == 65536:
            f.write(b"".join(chunk))
            chunk.clear()
    f.write(b"".join(chunk))


def write_text(f, n, rng, facet_text):
    chunk = []
    for i in range(n):
        chunk.append(facet_text(i, corners(rng)))
        if len(chunk) == 65536:
            f.write("".join(chunk).encode())
            chunk.clear()
    f.write("".join(chunk).encode())


def ascii_facet(_, c):
    v = "".join(f"   vertex {c[k]:.6f} {c[k + 1]:.6f} {c[k + 2]:.6f}\n" for k in (0, 3, 6))
    return f" facet normal 0 0 0\n  outer loop\n{v}  endloop\n endfacet\n"


def obj_facet(i, c):
    v = "".join(f"v {c[k]:.6f} {c[k + 1]:.6f} {c[k + 2]:.6f}\n" for k in (0, 3, 6))
    return f"{v}f {3 * i + 1} {3 * i + 2} {3 * i + 3}\n"


def main():
    args = [a for a in sys.argv[1:] if a != "--ascii"]
    out = args[0]
    n = int(args[1]) if len(args) > 1 else 3_000_000
    rng = random.Random(int(args[2]) if len(args) > 2 else 1)
    with open(out, "wb") as f:
        if out.lower().endswith(".obj"):
            write_text(f, n, rng, obj_facet)
        elif "--ascii" in sys.argv:
            f.write(b"solid soup\n")
            write_text(f, n, rng, ascii_facet)
            f.write(b"endsolid soup\n")
        else:
            write_binary(f, n, rng)


if __name__ == "__main__":
    main()
