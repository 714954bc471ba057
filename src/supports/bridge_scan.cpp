// The bridge's direction: lines spaced a line width over a minimum, scanned at every angle
// step, each clipped to the span it crosses wall to wall; the angle whose lines are shortest
// wins (plan_bridge, see bridges.hpp). The scans go edge by edge rather than line by line, so
// that 36 angles per minimum stay cheap.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "supports/bridges.hpp"

namespace carve {

namespace {

// Rounds half away from zero exactly like std::llround, without the library call: the bridge
// search rounds every vertex of the span for each of 36 angles. x - trunc(x) is exact in
// doubles, so the comparison with 0.5 is too.
Coord round_half_away(double x) {
    Coord t = static_cast<Coord>(x);  // truncates toward zero
    const double f = x - static_cast<double>(t);
    if (f >= 0.5) ++t;
    if (f <= -0.5) --t;
    return t;
}

struct Rotation {
    double c, s;
    explicit Rotation(double deg)
        : c(std::cos(deg * std::numbers::pi / 180)), s(std::sin(deg * std::numbers::pi / 180)) {}
    // The two coordinates are rounded separately, so a scan can rotate y alone first.
    Coord x(const Point& p) const { return round_half_away(c * p.X - s * p.Y); }
    Coord y(const Point& p) const { return round_half_away(s * p.X + c * p.Y); }
    Point undo(const Point& p) const {
        return Point(round_half_away(c * p.X + s * p.Y), round_half_away(-s * p.X + c * p.Y));
    }
};

Paths rotated_back(const Paths& region, const Rotation& rot) {
    Paths out = region;
    for (Path& p : out)
        for (Point& q : p) q = rot.undo(q);
    return out;
}

// The range of a region's vertex heights in the rotated frame; empty if it has no vertex.
struct HeightRange {
    Coord min_y = 0, max_y = 0;
    bool empty = true;
};

HeightRange height_range(const Paths& region, const Rotation& rot) {
    HeightRange h;
    for (const Path& p : region)
        for (const Point& q : p) {
            const Coord y = rot.y(q);
            h.min_y = h.empty ? y : std::min(h.min_y, y);
            h.max_y = h.empty ? y : std::max(h.max_y, y);
            h.empty = false;
        }
    return h;
}

// A run of consecutive edges of one path with the box of their ends. The runs are built once
// per minimum; at each angle a run whose box misses the band of scan lines is set aside in a
// few operations, and most of a span is far from the minimum.
struct EdgeRun {
    size_t path, begin, end;  // edges p[i] -> p[i + 1] for begin <= i < end, cyclically
    BBox2 box;
};

std::vector<EdgeRun> edge_runs(const Paths& region) {
    constexpr size_t kRun = 16;
    std::vector<EdgeRun> runs;
    for (size_t pi = 0; pi < region.size(); ++pi) {
        const Path& p = region[pi];
        const size_t n = p.size();
        for (size_t begin = 0; begin < n; begin += kRun) {
            EdgeRun r{pi, begin, std::min(n, begin + kRun), {}};
            r.box = {p[begin].X, p[begin].Y, p[begin].X, p[begin].Y, false};
            for (size_t i = begin + 1; i <= r.end; ++i) {
                const Point& q = p[i % n];
                r.box.min_x = std::min(r.box.min_x, q.X);
                r.box.min_y = std::min(r.box.min_y, q.Y);
                r.box.max_x = std::max(r.box.max_x, q.X);
                r.box.max_y = std::max(r.box.max_y, q.Y);
            }
            runs.push_back(r);
        }
    }
    return runs;
}

// A region to scan with its edge runs.
struct Scanned {
    const Paths& region;
    std::vector<EdgeRun> runs;
    explicit Scanned(const Paths& r) : region(r), runs(edge_runs(r)) {}
};

// The intervals [x0, x1] where each scan line is inside a region, row after row.
struct ScanRows {
    std::vector<std::pair<double, double>> intervals;
    std::vector<size_t> begin;  // row k holds intervals[begin[k] .. begin[k + 1])
    bool empty(int k) const { return begin[k] == begin[k + 1]; }
};

// For each of `count` horizontal lines y_k = first + k * spacing, the intervals where the line
// is inside a normalised region, once rotated by `rot`; only rows that `wanted` has intervals
// on, if given. Each edge goes straight to the lines it crosses, so the cost is edges plus
// crossings rather than lines times edges: the bridge search asks this for 36 angles per
// minimum. The lines are off integer heights, so no vertex lies on one.
ScanRows scan_lines(const Scanned& scanned, const Rotation& rot, double first, double spacing,
                    int count, const ScanRows* wanted = nullptr) {
    std::vector<std::pair<int, double>> crossings;  // (row, x)
    const double last = first + (count - 1) * spacing;
    for (const EdgeRun& run : scanned.runs) {
        // The heights of the run's vertices, before rounding, lie between these; rounding
        // moves them by half a unit at most, so a margin of one keeps the test exact.
        const BBox2& b = run.box;
        const double top = rot.s * double(rot.s >= 0 ? b.max_x : b.min_x) +
                           rot.c * double(rot.c >= 0 ? b.max_y : b.min_y);
        const double bottom = rot.s * double(rot.s >= 0 ? b.min_x : b.max_x) +
                              rot.c * double(rot.c >= 0 ? b.min_y : b.max_y);
        if (top + 1 <= first || bottom - 1 > last) continue;
        const Path& p = scanned.region[run.path];
        const size_t n = p.size();
        Coord by = rot.y(p[run.begin]);
        for (size_t i = run.begin; i < run.end; ++i) {
            const size_t j = (i + 1) % n;
            const Coord ay = by;
            by = rot.y(p[j]);
            if (ay == by) continue;
            const double lo = double(std::min(ay, by)), hi = double(std::max(ay, by));
            if (hi <= first || lo > last) continue;
            // Lines with lo <= y < hi cross the edge.
            const int k0 = std::max(0, static_cast<int>(std::ceil((lo - first) / spacing)));
            const int k1 =
                std::min(count - 1, static_cast<int>(std::floor((hi - first) / spacing)));
            if (k0 > k1) continue;
            const Coord ax = rot.x(p[i]), bx = rot.x(p[j]);
            for (int k = k0; k <= k1; ++k) {
                if (wanted && wanted->empty(k)) continue;
                const double y = first + k * spacing;
                if (y < lo || y >= hi) continue;
                crossings.emplace_back(k, ax + (y - ay) * double(bx - ax) / double(by - ay));
            }
        }
    }
    // Crossings go to their rows by counting, then each row, a handful of values, is sorted:
    // sorting them all as (row, x) pairs took a third of the scan.
    std::vector<size_t> at(count + 1, 0);
    for (const auto& c : crossings) ++at[c.first + 1];
    for (int k = 0; k < count; ++k) at[k + 1] += at[k];
    std::vector<double> xs(crossings.size());
    {
        std::vector<size_t> next(at.begin(), at.end() - 1);
        for (const auto& [k, x] : crossings) xs[next[k]++] = x;
    }
    ScanRows out;
    out.begin.assign(count + 1, 0);
    for (int k = 0; k < count; ++k) {
        std::sort(xs.begin() + at[k], xs.begin() + at[k + 1]);
        for (size_t i = at[k]; i + 1 < at[k + 1]; i += 2)
            out.intervals.emplace_back(xs[i], xs[i + 1]);
        out.begin[k + 1] = out.intervals.size();
    }
    return out;
}

// Lines over `need` in the frame turned by `rot`, where they are horizontal; returns their
// total length, or the sum of their squared lengths if `squared`. The lines are in the turned
// frame.
double horizontal_lines(const Scanned& need, const Scanned& span, const Rotation& rot,
                        Coord spacing, Paths* lines, bool squared = false) {
    const HeightRange b = height_range(need.region, rot);
    if (b.empty) return 0;
    double total = 0;
    const int count =
        std::max<int>(1, static_cast<int>(std::ceil(double(b.max_y - b.min_y) / spacing)));
    const double first = (b.min_y + b.max_y) / 2.0 - (count - 1) * spacing / 2.0 + 0.5;
    const ScanRows holes = scan_lines(need, rot, first, double(spacing), count);
    const ScanRows spans = scan_lines(span, rot, first, double(spacing), count, &holes);
    for (int k = 0; k < count; ++k) {
        if (holes.empty(k)) continue;
        const auto h0 = holes.intervals.begin() + holes.begin[k];
        const auto h1 = holes.intervals.begin() + holes.begin[k + 1];
        const double y = first + k * double(spacing);
        for (size_t s = spans.begin[k]; s < spans.begin[k + 1]; ++s) {
            const auto [x0, x1] = spans.intervals[s];
            // Bounds copied for the lambda: clang 14 cannot capture structured bindings.
            const bool over = std::any_of(h0, h1, [lo = x0, hi = x1](const auto& h) {
                return h.second > lo && h.first < hi;
            });
            if (!over) continue;
            total += squared ? (x1 - x0) * (x1 - x0) : x1 - x0;
            if (lines) {
                // Alternate directions so that the nozzle zig-zags across the bridge.
                Point a(static_cast<Coord>(std::llround(x0)), static_cast<Coord>(std::llround(y)));
                Point c(static_cast<Coord>(std::llround(x1)), static_cast<Coord>(std::llround(y)));
                lines->push_back(k % 2 ? Path{c, a} : Path{a, c});
            }
        }
    }
    return total;
}

}  // namespace

Bridge plan_bridge(const Paths& need, const Paths& span, const BridgeOptions& options,
                   bool shortest_spans) {
    Bridge best;
    double best_length = -1;
    const double step = options.angle_step_deg > 0 ? options.angle_step_deg : 5;
    const Scanned need_scan(need), span_scan(span);
    for (double angle = 0; angle < 180 - 1e-9; angle += step) {
        const Rotation rot(-angle);  // bring lines at `angle` to horizontal
        const double len = horizontal_lines(need_scan, span_scan, rot, options.line_width, nullptr,
                                            shortest_spans);
        if (len > 0 && (best_length < 0 || len < best_length)) {
            best_length = len;
            best.angle_deg = angle;
        }
    }
    best.region = need;
    if (best_length < 0) return best;
    const Rotation rot(-best.angle_deg);
    Paths lines;
    horizontal_lines(need_scan, span_scan, rot, options.line_width, &lines);
    best.lines = rotated_back(lines, rot);
    return best;
}

}  // namespace carve
