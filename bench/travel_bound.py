#!/usr/bin/python3
"""Travel outside the model (issue #18): where it comes from, and how low it could go.

    travel_bound.py MODEL.stl OUT.gcode CHECK.json [--out RESULT.json]

CHECK.json is `carve check OUT.gcode --mesh MODEL.stl --json --layers` (for the mesh offset and
the layers' heights). The model is sliced here at each layer's mid-height, as carve check does,
and grown by the check's tolerance (half the line width). Every travel (the XY moves between two
extrusions, wipes included) is then measured outside that region and put in one of three bins:
the travel into a layer (the first of the layer), travel that retracted, and combed travel that
did not.

The bound: on each layer every component of the grown slice that holds an extrusion must be
visited, and a travel from one component to another lies outside for at least the gap between
them; so the pieces outside connect those components, and their length is at least the
minimum Steiner tree over them with the gaps as weights, the components without an extrusion
as optional stepping stones (the least spanning tree over every choice of those). The travel into a layer can be wholly inside (a layer may
start in the component where the one below ended), so the bound adds nothing for it.
"""
import argparse
import json
import math
import re
import struct
import sys

import numpy as np
from scipy.sparse.csgraph import minimum_spanning_tree, shortest_path
from shapely.geometry import LineString, Point, Polygon
from shapely.prepared import prep


def load_stl(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:5] == b"solid" and b"facet" in data[:1000]:
        nums = re.findall(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)", data)
        tri = np.array(nums, dtype=float).reshape(-1, 3, 3)
    else:
        n = struct.unpack_from("<I", data, 80)[0]
        rec = np.frombuffer(data, dtype=np.uint8, count=n * 50, offset=84).reshape(n, 50)
        tri = rec[:, 12:48].copy().view("<f4").reshape(n, 3, 3).astype(float)
    # Shared vertices, so that the points where the plane cuts an edge can be chained by edge.
    verts, idx = np.unique(np.round(tri.reshape(-1, 3), 6), axis=0, return_inverse=True)
    return verts, idx.reshape(-1, 3)


def slice_mesh(verts, faces, z):
    """The region of the plane at height z inside the mesh (even-odd), as a shapely geometry."""
    zs = verts[:, 2]
    fz = zs[faces]
    hit = (fz.min(axis=1) < z) & (fz.max(axis=1) > z)
    segs = []
    for f in faces[hit]:
        pts = []
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            za, zb = zs[a], zs[b]
            if (za < z) != (zb < z):
                key = (min(a, b), max(a, b))
                t = (z - za) / (zb - za)
                p = verts[a] + t * (verts[b] - verts[a])
                pts.append((key, (p[0], p[1])))
        if len(pts) == 2:
            segs.append(pts)
    # Chain by edge key: each cut edge is shared by two faces.
    adj = {}
    where = {}
    for (k1, p1), (k2, p2) in segs:
        adj.setdefault(k1, []).append(k2)
        adj.setdefault(k2, []).append(k1)
        where[k1], where[k2] = p1, p2
    seen = set()
    rings = []
    for start in adj:
        if start in seen:
            continue
        ring = [start]
        seen.add(start)
        prev, cur = None, start
        while True:
            nxt = [k for k in adj[cur] if k != prev and k not in seen]
            if not nxt:
                break
            prev, cur = cur, nxt[0]
            seen.add(cur)
            ring.append(cur)
        if len(ring) >= 3:
            rings.append([where[k] for k in ring])
    region = None
    for r in rings:
        poly = Polygon(r).buffer(0)
        if poly.is_empty:
            continue
        region = poly if region is None else region.symmetric_difference(poly)
    return region


def parse_gcode(path):
    """Per layer (keyed by the z of its extrusions): extrusion points, and the travels that end
    at one of its extrusions, each as (points, retracted)."""
    x = y = z = e = 0.0
    rel_e = False
    layers = {}
    order = []
    travel = None
    retracted = False
    for line in open(path):
        line = line.split(";", 1)[0].strip()
        if not line:
            continue
        words = line.split()
        cmd = words[0]
        if cmd == "M83":
            rel_e = True
            continue
        if cmd == "M82":
            rel_e = False
            continue
        if cmd == "G92":
            for w in words[1:]:
                if w[0] == "E":
                    e = float(w[1:])
            continue
        if cmd in ("G10",):
            retracted = True
            continue
        if cmd not in ("G0", "G1", "G2", "G3"):
            continue
        vals = {w[0]: float(w[1:]) for w in words[1:] if w[0] in "XYZEIJF"}
        nx, ny, nz = vals.get("X", x), vals.get("Y", y), vals.get("Z", z)
        de = 0.0
        if "E" in vals:
            de = vals["E"] if rel_e else vals["E"] - e
            e = e + de if rel_e else vals["E"]
        moved = math.hypot(nx - x, ny - y) > 1e-4
        if de > 0 and moved:
            key = round(nz, 3)
            if key not in layers:
                layers[key] = {"points": [], "travels": []}
                order.append(key)
            if travel is not None and len(travel) >= 2:
                layers[key]["travels"].append((travel, retracted))
            travel = None
            retracted = False
            layers[key]["points"].append((x, y))
            layers[key]["points"].append((nx, ny))
        else:
            if de < 0:
                retracted = True
            if moved:
                if travel is None:
                    travel = [(x, y)]
                travel.append((nx, ny))
        x, y, z = nx, ny, nz
    return [(k, layers[k]) for k in order]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("gcode")
    ap.add_argument("check")
    ap.add_argument("--out")
    args = ap.parse_args()
    check = json.load(open(args.check))
    off = check["mesh_offset_mm"]
    verts, faces = load_stl(args.model)
    verts = verts + np.array(off)
    tol = check.get("model_tolerance_mm", 0.2)
    layers = parse_gcode(args.gcode)
    totals = {"first": 0.0, "retracted": 0.0, "combed": 0.0, "bound": 0.0}
    per_layer = []
    prev_z = None
    for z, data in layers:
        h = z - prev_z if prev_z is not None and z > prev_z else z
        prev_z = z
        region = slice_mesh(verts, faces, z - h / 2 + 1e-7)
        if region is None or region.is_empty:
            continue
        grown = region.buffer(tol, 16)
        comps = list(grown.geoms) if grown.geom_type == "MultiPolygon" else [grown]
        # Components holding an extrusion must be visited; the others may be passed through
        # (a speck too small to print), so the bound is the Steiner tree over the first with
        # any of the others as stepping stones: the least MST over every choice of them.
        pts = np.array(data["points"])
        used, spare = [], []
        for c in comps:
            minx, miny, maxx, maxy = c.bounds
            sel = pts[(pts[:, 0] >= minx) & (pts[:, 0] <= maxx) & (pts[:, 1] >= miny) &
                      (pts[:, 1] <= maxy)]
            inside = prep(c)
            (used if any(inside.contains(Point(p)) for p in sel) else spare).append(c)
        bound = 0.0
        if len(used) > 1:
            nodes = used + spare
            n = len(nodes)
            d = np.zeros((n, n))
            for i in range(n):
                for j in range(i + 1, n):
                    d[i, j] = d[j, i] = max(nodes[i].distance(nodes[j]), 1e-9)

            def mst(idx):
                return float(minimum_spanning_tree(np.triu(d[np.ix_(idx, idx)])).sum())

            m = len(used)
            if len(spare) <= 10:
                bound = min(mst(list(range(m)) + [m + k for k in range(len(spare)) if mask >> k & 1])
                            for mask in range(1 << len(spare)))
            else:  # the MST of the metric closure is at most twice the Steiner tree
                closure = shortest_path(d, directed=False)
                bound = float(minimum_spanning_tree(np.triu(closure[:m, :m])).sum()) / 2
        fig = {"z": z, "components": len(used), "spare": len(spare), "bound": bound, "first": 0.0, "retracted": 0.0,
               "combed": 0.0}
        for k, (t, retr) in enumerate(data["travels"]):
            out = LineString(t).difference(grown).length if len(t) >= 2 else 0.0
            b = "first" if k == 0 else ("retracted" if retr else "combed")
            fig[b] += out
        for b in ("first", "retracted", "combed", "bound"):
            totals[b] += fig[b]
        per_layer.append(fig)
    totals["outside"] = totals["first"] + totals["retracted"] + totals["combed"]
    result = {"model": args.model, "gcode": args.gcode, "tolerance_mm": tol, "totals": totals,
              "check_travel_outside_mm": check.get("travel_outside_mm"), "layers": per_layer}
    if args.out:
        with open(args.out, "w") as f:
            json.dump(result, f, indent=1)
    print(json.dumps({k: round(v, 1) for k, v in totals.items()}),
          "check:", check.get("travel_outside_mm"))


if __name__ == "__main__":
    sys.exit(main())
