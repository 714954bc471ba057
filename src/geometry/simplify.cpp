// The closed case splits the loop at the vertex farthest from its first one, so that both
// halves are ordinary chords; index n stands for vertex 0 closing the loop.
#include "geometry/simplify.hpp"

#include <algorithm>
#include <cmath>

namespace carve {

double segment_distance(const Point& p, const Point& a, const Point& b) {
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
    const double l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? (double(p.X - a.X) * dx + double(p.Y - a.Y) * dy) / l2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(double(p.X) - (double(a.X) + t * dx), double(p.Y) - (double(a.Y) + t * dy));
}

bool douglas_peucker(const Path& path, bool closed, double tolerance, SimplifyScratch& scratch,
                     Path& out) {
    const size_t n = path.size();
    out.clear();
    if (n <= (closed ? 3u : 2u)) {
        out = path;
        return true;
    }
    std::vector<uint8_t>& keep = scratch.keep;
    std::vector<std::pair<size_t, size_t>>& stack = scratch.stack;
    keep.assign(n, 0);
    stack.clear();
    keep[0] = 1;
    if (closed) {
        size_t far = 0;
        double far_d = -1;
        for (size_t k = 1; k < n; ++k) {
            const double d =
                std::hypot(double(path[k].X - path[0].X), double(path[k].Y - path[0].Y));
            if (d > far_d) far_d = d, far = k;
        }
        keep[far] = 1;
        stack.push_back({0, far});
        stack.push_back({far, n});
    } else {
        keep[n - 1] = 1;
        stack.push_back({0, n - 1});
    }
    // Each range costs its length, and a range split next to one of its ends leaves nearly all
    // of it for the next round: a zig-zag whose every tooth must stay (issue #38: 800,000
    // vertices a slice) made that quadratic, hours for one slice. The budget is far above what
    // real contours take (at most 10 a vertex on the shared models' slices, 40 in the report's
    // drawings); once it is spent, the ranges left keep all their vertices, which moves nothing.
    const double log_n = std::log2(double(n));
    size_t budget = static_cast<size_t>(double(n) * (32.0 + 4.0 * log_n));
    bool complete = true;
    while (!stack.empty()) {
        const auto [i, j] = stack.back();
        stack.pop_back();
        if (j - i > budget) {
            complete = false;
            for (size_t k = i + 1; k < j; ++k) keep[k] = 1;
            continue;
        }
        budget -= j - i;
        const Point& a = path[i];
        const Point& b = path[j % n];
        double best = -1;
        size_t at = 0;
        for (size_t k = i + 1; k < j; ++k) {
            const double d = segment_distance(path[k], a, b);
            if (d > best) best = d, at = k;
        }
        if (best > tolerance) {
            keep[at] = 1;
            stack.push_back({i, at});
            stack.push_back({at, j});
        }
    }
    for (size_t k = 0; k < n; ++k)
        if (keep[k]) out.push_back(path[k]);
    return complete;
}

Path douglas_peucker(const Path& path, bool closed, double tolerance) {
    SimplifyScratch scratch;
    Path out;
    douglas_peucker(path, closed, tolerance, scratch, out);
    return out;
}

}  // namespace carve
