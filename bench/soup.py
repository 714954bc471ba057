#!/usr/bin/python3
"""Writes a binary STL of N random, disconnected triangles in a 100 mm cube (a triangle soup).

Usage: soup.py OUT.stl [N] [SEED]   (default N = 3,000,000: a 150 MB file; seed 1)

carve slice refuses such a file (it is no solid); what the refusal costs (issue #22) is measured
with `/usr/bin/time -v build/carve slice OUT.stl -o /tmp/x.gcode` (Maximum resident set size).
Standard library only, so that it runs with the system Python.
"""
import random
import struct
import sys


def main():
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 3_000_000
    rng = random.Random(int(sys.argv[3]) if len(sys.argv) > 3 else 1)
    facet = struct.Struct("<12fH")
    with open(out, "wb") as f:
        f.write(b"random triangle soup (bench/soup.py)".ljust(80, b" "))
        f.write(struct.pack("<I", n))
        chunk = []
        for _ in range(n):
            c = [rng.uniform(0, 100) for _ in range(9)]
            chunk.append(facet.pack(0, 0, 0, *c, 0))
            if len(chunk) == 65536:
                f.write(b"".join(chunk))
                chunk.clear()
        f.write(b"".join(chunk))


if __name__ == "__main__":
    main()
