// SKEL (report section 5.2): pruned medial axis of a slice and its thickening into a seed.
//
// Per region component: clean the contours into integer polygons whose segments meet only at
// endpoints (contours.cpp; simplified within max_arc_error, since the builder's cost is per
// segment), build the inner medial axis from the segment Voronoi diagram (voronoi_axis.cpp),
// burn it with the extended grassfire and keep what has EDF - R >= prune_threshold (edf.cpp).
// Boost's builder fails on some inputs; a rejected diagram is rebuilt in a slightly rotated
// frame. Rotations are exact (a Pythagorean triple (a, b, c) maps (x, y) to (a x - b y,
// b x + a y), a rotation scaled by c), so the rotated input meets the same precondition; the
// axis is rotated back in doubles. A component whose every frame fails gets no axis (reported
// in last_stats()); nothing throws.
#include "skeleton/skeleton.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iterator>
#include <utility>
#include <vector>

#include "base/stage_timer.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "skeleton/axis_graph.hpp"
#include "skeleton/contours.hpp"
#include "skeleton/skeleton_detail.hpp"
#include "skeleton/voronoi_axis.hpp"

namespace carve {

namespace skel {

namespace {

struct Rotation {
    Coord a, b, c;
};
// Identity, then rotations by about 22.6, 36.9 and 12.7 degrees.
constexpr std::array<Rotation, 4> kFrames{{{1, 0, 1}, {12, 5, 13}, {4, 3, 5}, {40, 9, 41}}};

struct Frame {
    Coord cx = 0, cy = 0;
    Rotation rot{1, 0, 1};
    Point forward(const Point& p) const {
        const Coord x = p.X - cx, y = p.Y - cy;
        return Point(rot.a * x - rot.b * y, rot.b * x + rot.a * y);
    }
    Point back(const DPoint& q) const {
        const double c2 = double(rot.c) * double(rot.c);
        const double x = (double(rot.a) * q.x + double(rot.b) * q.y) / c2;
        const double y = (-double(rot.b) * q.x + double(rot.a) * q.y) / c2;
        return Point(cx + std::llround(x), cy + std::llround(y));
    }
};

struct Workspace {
    VoronoiWorkspacePtr voronoi = make_voronoi_workspace();
    AxisGraph graph;
    Burn burn;
    Paths frame_contours;
    std::vector<Polyline> lines;
    SkeletonStats stats;
};

Workspace& workspace() {
    thread_local Workspace ws;
    return ws;
}

void axis_of_component(const Paths& comp, const SkeletonOptions& options, const AxisTrace& trace,
                       Workspace& ws, Paths& out) {
    Coord min_x = comp[0][0].X, max_x = min_x, min_y = comp[0][0].Y, max_y = min_y;
    for (const Path& c : comp)
        for (const Point& p : c) {
            min_x = std::min(min_x, p.X), max_x = std::max(max_x, p.X);
            min_y = std::min(min_y, p.Y), max_y = std::max(max_y, p.Y);
        }
    Frame frame;
    frame.cx = min_x + (max_x - min_x) / 2;
    frame.cy = min_y + (max_y - min_y) / 2;
    const Coord half =
        std::max({max_x - frame.cx, frame.cx - min_x, max_y - frame.cy, frame.cy - min_y});

    for (size_t k = 0; k < kFrames.size(); ++k) {
        frame.rot = kFrames[(size_t(trace.first_frame) + k) % kFrames.size()];
        if (int(k) < trace.reject_attempts) {
            ws.stats.rejections.push_back("rejected by the caller");
            if (k + 1 < kFrames.size()) ++ws.stats.retries;
            continue;
        }
        AxisStatus status = AxisStatus::kOutOfRange;
        // |a x - b y| <= (a + b) * half must stay within Boost's int32 input (with margin).
        if ((frame.rot.a + frame.rot.b) * half < (Coord(1) << 30)) {
            const Paths& src = comp;
            ws.frame_contours.resize(src.size());
            for (size_t i = 0; i < src.size(); ++i) {
                Path& fc = ws.frame_contours[i];
                fc.resize(src[i].size());
                for (size_t j = 0; j < src[i].size(); ++j) fc[j] = frame.forward(src[i][j]);
            }
            const double scale = double(frame.rot.c);
            status = build_axis(ws.frame_contours, double(options.max_arc_error) * scale,
                                *ws.voronoi, ws.graph);
            if (status == AxisStatus::kOk) {
                ws.stats.nodes += int(ws.graph.nodes.size());
                ws.stats.edges += int(ws.graph.edges.size());
                burn(ws.graph, ws.burn);
                ws.lines.clear();
                prune(ws.graph, ws.burn, double(options.prune_threshold) * scale, ws.lines);
                for (const Polyline& line : ws.lines) {
                    Path path;
                    path.reserve(line.size());
                    for (const DPoint& q : line) {
                        const Point p = frame.back(q);
                        if (path.empty() || path.back() != p) path.push_back(p);
                    }
                    out.push_back(std::move(path));
                }
                return;
            }
        }
        ws.stats.rejections.push_back(to_string(status));
        if (k + 1 < kFrames.size()) ++ws.stats.retries;
    }
    ++ws.stats.abandoned;
}

}  // namespace

namespace {

// The axis of each component, in component order, with what building it went through; a
// component equal to one of `known` takes that one's axis and statistics.
Paths axes_of(const Paths& region, const SkeletonOptions& options, const AxisTrace& trace,
              const AxisMemo* known, AxisMemo* record) {
    StageTimer timer(Stage::kSkeleton);
    Workspace& ws = workspace();
    ws.stats = SkeletonStats{};
    Paths out;
    if (region.empty()) return out;
    // The contours may move by max_arc_error, the error already allowed on the arcs.
    std::vector<Paths> comps =
        prepare_components(region, std::max(1.0, double(options.max_arc_error)), &ws.stats.mended);
    ws.stats.components = int(comps.size());
    std::vector<Paths> axes(comps.size());
    std::vector<SkeletonStats> stats(comps.size());
    std::vector<size_t> todo;
    static const std::vector<Paths> kNone;
    const std::vector<Paths>& from = known ? known->components : kNone;
    for (size_t i = 0; i < comps.size(); ++i) {
        const auto same = std::find(from.begin(), from.end(), comps[i]);
        if (same == from.end()) {
            todo.push_back(i);
            continue;
        }
        const size_t at = size_t(same - from.begin());
        axes[i] = known->axes[at];
        stats[i] = known->stats[at];
    }
    auto build = [&](size_t i) {
        Workspace& own = workspace();  // the caller's too when it runs a task itself
        SkeletonStats outer = std::move(own.stats);
        own.stats = SkeletonStats{};
        axis_of_component(comps[i], options, trace, own, axes[i]);
        stats[i] = std::move(own.stats);
        own.stats = std::move(outer);
    };
    if (todo.size() < 2) {
        for (size_t i : todo) build(i);
    } else {
        // The axis of a component depends on its own contours only (the boundary nearest to a
        // point inside it is its own), so the components are done as parallel tasks, each in
        // the workspace of the thread that runs it, and joined in component order: the same
        // axis whatever the scheduling. Late carving iterations see dozens of components in a
        // slice, and the sweep that waits for them is the run's critical path. Isolated, so
        // that a thread waiting here only takes these tasks, not another layer's (which would
        // hold up this one).
        tbb::this_task_arena::isolate(
            [&] { tbb::parallel_for(size_t(0), todo.size(), [&](size_t k) { build(todo[k]); }); });
    }
    for (size_t i = 0; i < comps.size(); ++i) {
        if (record)
            out.insert(out.end(), axes[i].begin(), axes[i].end());
        else
            std::move(axes[i].begin(), axes[i].end(), std::back_inserter(out));
        SkeletonStats& t = ws.stats;
        t.retries += stats[i].retries;
        t.abandoned += stats[i].abandoned;
        t.nodes += stats[i].nodes;
        t.edges += stats[i].edges;
        t.rejections.insert(t.rejections.end(), stats[i].rejections.begin(),
                            stats[i].rejections.end());
    }
    if (record) *record = AxisMemo{std::move(comps), std::move(axes), std::move(stats)};
    return out;
}

}  // namespace

Paths medial_axis(const Paths& region, const SkeletonOptions& options, const AxisTrace& trace) {
    return axes_of(region, options, trace, nullptr, nullptr);
}

Paths medial_axis(const Paths& region, const SkeletonOptions& options, const AxisMemo* known,
                  AxisMemo* record) {
    return axes_of(region, options, AxisTrace{}, known, record);
}

const SkeletonStats& last_stats() {
    return workspace().stats;
}

int frame_count() {
    return int(kFrames.size());
}

}  // namespace skel

Paths medial_axis(const Paths& region, const SkeletonOptions& options) {
    return skel::medial_axis(region, options, skel::AxisTrace{});
}

Paths skeleton(const Paths& region, const SkeletonOptions& options) {
    if (options.thickness <= 0) return {};
    const Paths lines = medial_axis(region, options);
    if (lines.empty()) return {};
    return intersect(dilate_lines(lines, options.thickness), region);
}

}  // namespace carve
