#!/usr/bin/python3
"""Thin shapes (issue #47): parts of a model narrower than two lines, which a hollow print must
still print. Writes the meshes into a folder:

- fins.stl: a 70 x 24 x 2 mm plate carrying fins 20 mm long and 10 mm tall, 0.2, 0.25, 0.3,
  0.35, 0.45, 0.6, 0.8 and 1.0 mm thick, 8 mm apart (x of fin k: 5 + 8 k);
- slots.stl: a comb, a 2 mm base under teeth 3 mm wide and 10 mm tall, the slots between them
  0.2, 0.3, 0.45, 0.6, 0.8 and 1.0 mm wide;
- vase.stl: a tube of radius 15 mm with a 0.3 mm wall, 20 mm tall, on a 1 mm floor;
- lettering.stl: a 40 x 20 x 4 mm block with "HIL" embossed on its top, strokes 0.3 mm wide
  and 0.6 mm tall.

    bench/thin_shapes.py OUT_DIR

Each fin, slot and stroke is a box of its own, overlapping what it stands on by 0.1 mm (the
slicer takes the union), so the widths are exact. The same shapes are built by the tests
(tests/support/stl_boxes.hpp).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from flat_shapes import box, write_stl  # noqa: E402


def tube(r_out, r_in, z0, z1, n=180):
    tris = []
    for k in range(n):
        a, b = 2 * math.pi * k / n, 2 * math.pi * ((k + 1) % n) / n
        o0 = (r_out * math.cos(a), r_out * math.sin(a))
        o1 = (r_out * math.cos(b), r_out * math.sin(b))
        i0 = (r_in * math.cos(a), r_in * math.sin(a))
        i1 = (r_in * math.cos(b), r_in * math.sin(b))
        tris += [((*o0, z0), (*o1, z0), (*o1, z1)), ((*o0, z0), (*o1, z1), (*o0, z1))]
        tris += [((*i0, z0), (*i1, z1), (*i1, z0)), ((*i0, z0), (*i0, z1), (*i1, z1))]
        tris += [((*o0, z1), (*o1, z1), (*i1, z1)), ((*o0, z1), (*i1, z1), (*i0, z1))]
        tris += [((*o0, z0), (*i1, z0), (*o1, z0)), ((*o0, z0), (*i0, z0), (*i1, z0))]
    return tris


def disk(r, z0, z1, n=180):
    tris = []
    for k in range(n):
        a, b = 2 * math.pi * k / n, 2 * math.pi * ((k + 1) % n) / n
        p0 = (r * math.cos(a), r * math.sin(a))
        p1 = (r * math.cos(b), r * math.sin(b))
        tris += [((0, 0, z1), (*p0, z1), (*p1, z1)), ((0, 0, z0), (*p1, z0), (*p0, z0))]
        tris += [((*p0, z0), (*p1, z0), (*p1, z1)), ((*p0, z0), (*p1, z1), (*p0, z1))]
    return tris


FIN_WIDTHS = [0.2, 0.25, 0.3, 0.35, 0.45, 0.6, 0.8, 1.0]
SLOT_WIDTHS = [0.2, 0.3, 0.45, 0.6, 0.8, 1.0]


def fins():
    tris = box(0, 0, 0, 70, 24, 2)
    for k, t in enumerate(FIN_WIDTHS):
        x = 5 + 8 * k
        tris += box(x - t / 2, 2, 1.9, x + t / 2, 22, 12)
    return tris


def slots():
    tris, x = [], 0.0
    tris += box(0, 0, 0, 3 * (len(SLOT_WIDTHS) + 1) + sum(SLOT_WIDTHS), 10, 2)
    for k in range(len(SLOT_WIDTHS) + 1):
        tris += box(x, 0, 1.9, x + 3, 10, 12)
        x += 3 + (SLOT_WIDTHS[k] if k < len(SLOT_WIDTHS) else 0)
    return tris


def vase():
    return disk(15, 0, 1) + tube(15, 14.7, 0.9, 21)


def lettering():
    s, h, z = 0.3, 0.6, 4
    tris = box(0, 0, 0, 40, 20, z)
    strokes = [  # H, I, L: 8 mm tall letters
        (8, 6, 8 + s, 14), (12, 6, 12 + s, 14), (8, 10 - s / 2, 12 + s, 10 + s / 2),
        (18, 6, 18 + s, 14),
        (24, 6, 24 + s, 14), (24, 6, 29, 6 + s)]
    for x0, y0, x1, y1 in strokes:
        tris += box(x0, y0, z - 0.1, x1, y1, z + h)
    return tris


SHAPES = {'fins': fins, 'slots': slots, 'vase': vase, 'lettering': lettering}


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else '/tmp/carve_thin'
    os.makedirs(out, exist_ok=True)
    for name, make in SHAPES.items():
        write_stl(os.path.join(out, name + '.stl'), make())
        print(os.path.join(out, name + '.stl'))


if __name__ == '__main__':
    main()
