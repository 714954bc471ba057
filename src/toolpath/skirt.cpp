// Skirt and brim loops (skirt.hpp).
#include "toolpath/skirt.hpp"

#include <algorithm>
#include <cmath>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

namespace carve {

namespace {

// The outer contours of `region` dilated by `d`: one loop per part at that distance.
Paths loops_at(const Paths& region, Coord d) {
    return without_holes(dilate(region, d));
}

// Andrew's monotone chain: the convex hull, counter-clockwise.
Path convex_hull(const Paths& region) {
    std::vector<Point> pts;
    for (const Path& p : region) pts.insert(pts.end(), p.begin(), p.end());
    std::sort(pts.begin(), pts.end(), [](const Point& a, const Point& b) {
        return a.X < b.X || (a.X == b.X && a.Y < b.Y);
    });
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    if (pts.size() < 3) return pts;
    auto cross = [](const Point& o, const Point& a, const Point& b) {
        return double(a.X - o.X) * double(b.Y - o.Y) - double(a.Y - o.Y) * double(b.X - o.X);
    };
    Path hull(2 * pts.size());
    size_t k = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
        hull[k++] = pts[i];
    }
    for (size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
        hull[k++] = pts[i];
    }
    hull.resize(k - 1);
    return hull;
}

}  // namespace

FirstLayerLoops plan_skirt_and_brim(const Paths& first_slice, const Settings& s,
                                    const std::vector<Point>& above) {
    FirstLayerLoops out;
    const Paths parts = without_holes(first_slice);
    if (parts.empty()) return out;
    const double w = s.layer_width_mm(s.first_print_layer());
    Paths footprint = parts;
    if (s.brim_width > 0) {
        // PrusaSlicer's count: as many lines as fit in the width, one at least.
        const int n = std::max(1, int(std::floor(s.brim_width / w + 1e-9)));
        for (int k = n - 1; k >= 0; --k)
            for (const Path& p : loops_at(parts, to_units(s.brim_separation + w / 2 + k * w)))
                out.brim.push_back(p);
        footprint = unite(parts, loops_at(parts, to_units(s.brim_separation + n * w)));
    }
    if (s.skirts > 0 && s.skirt_height > 0) {
        Paths around = footprint;
        if (above.size() >= 3) {
            // The layers above as sliced: grown by --xy-size-compensation as every slice is.
            Paths higher{convex_hull({Path(above.begin(), above.end())})};
            if (s.xy_size_compensation > 0)
                higher = dilate(higher, to_units(s.xy_size_compensation));
            around = unite(around, higher);
        }
        const Paths hull{convex_hull(around)};
        for (int k = s.skirts - 1; k >= 0; --k)
            for (const Path& p : loops_at(hull, to_units(s.skirt_distance + w / 2 + k * w)))
                out.skirt.push_back(p);
    }
    return out;
}

void add_skirt_and_brim(LayerToolpaths& layer, const FirstLayerLoops& loops, const Settings& s) {
    std::vector<Extrusion> first;
    auto add = [&](const Paths& paths, Feature feature) {
        for (const Path& p : paths) {
            if (p.size() < 3) continue;
            Extrusion e;
            e.feature = feature;
            e.points = p;
            e.closed = true;
            first.push_back(std::move(e));
        }
    };
    // Counted in the print's layers: a raft's first layer is the first.
    const int printed_below = layer.index - s.first_print_layer();
    if (printed_below < s.skirt_height) add(loops.skirt, Feature::Skirt);
    if (printed_below == 0) add(loops.brim, Feature::Brim);
    if (first.empty()) return;
    const size_t n = first.size();
    layer.extrusions.insert(layer.extrusions.begin(), std::make_move_iterator(first.begin()),
                            std::make_move_iterator(first.end()));
    if (!layer.travels.empty()) layer.travels.insert(layer.travels.begin(), n, Travel{});
    layer.island_starts.clear();
}

}  // namespace carve
