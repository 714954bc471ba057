#!/usr/bin/python3
"""The before/after table of bench/results/travel.md from two bench/travel.sh output folders.

    travel_table.py BEFORE_DIR AFTER_DIR [--json OUT.json]
"""
import argparse
import json

MODELS = ["cat", "elephant", "fandisk", "man", "skull"]
# The figures at e2f7bc9 (carve check travel_outside_mm).
E2F7BC9 = {"cat": 19023, "elephant": 49299, "fandisk": 645, "man": 32145, "skull": 21814}


def figures(folder, m):
    b = json.load(open(f"{folder}/{m}.bound.json"))
    c = json.load(open(f"{folder}/{m}.check.json"))
    home = b["layers"][0]["first"] if b["layers"] else 0.0
    t = b["totals"]
    return {
        "travel_outside_mm": round(c["travel_outside_mm"], 1),
        "retractions": c["retractions"],
        "header_time_s": c["estimated_time_from_header_s"],
        "travel_mm": round(c["travel_length_mm"], 1),
        "wall_crossings": c["wall_crossings"],
        "home_to_first_point_mm": round(home, 1),
        "layer_entries_mm": round(t["first"] - home, 1),
        "within_layers_mm": round(t["retracted"] + t["combed"], 1),
        "lower_bound_mm": round(t["bound"], 1),
        "far_unsupported_mm2": round(c["far_unsupported_area_mm2"], 2),
        "extruded_volume_mm3": round(c["extruded_volume_mm3"], 1),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--json")
    args = ap.parse_args()
    out = {m: {"before": figures(args.before, m), "after": figures(args.after, m)}
           for m in MODELS}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
    print("| model | e2f7bc9 | 10x target | before | after | lower bound | bound + home "
          "| retractions | header time s | travel m | wall crossings |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for m, v in out.items():
        a, b = v["before"], v["after"]
        print(f"| {m} | {E2F7BC9[m]:,} | {round(E2F7BC9[m] / 10):,} | {a['travel_outside_mm']:,.0f} "
              f"| **{b['travel_outside_mm']:,.0f}** | {b['lower_bound_mm']:,.0f} "
              f"| {b['lower_bound_mm'] + b['home_to_first_point_mm']:,.0f} "
              f"| {a['retractions']} → {b['retractions']} "
              f"| {a['header_time_s']:.0f} → {b['header_time_s']:.0f} "
              f"| {a['travel_mm'] / 1000:.1f} → {b['travel_mm'] / 1000:.1f} "
              f"| {a['wall_crossings']} → {b['wall_crossings']} |")
    print()
    print("| model | home → first point | layer entries | within layers | lower bound |")
    print("|---|---:|---:|---:|---:|")
    for m, v in out.items():
        a, b = v["before"], v["after"]
        print(f"| {m} | {b['home_to_first_point_mm']:,.0f} "
              f"| {a['layer_entries_mm']:,.0f} → {b['layer_entries_mm']:,.0f} "
              f"| {a['within_layers_mm']:,.0f} → {b['within_layers_mm']:,.0f} "
              f"| {b['lower_bound_mm']:,.0f} |")


if __name__ == "__main__":
    main()
