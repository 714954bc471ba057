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

void douglas_peucker(const Path& path, bool closed, double tolerance, SimplifyScratch& scratch,
                     Path& out) {
    const size_t n = path.size();
    out.clear();
    if (n <= (closed ? 3u : 2u)) {
        out = path;
        return;
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
    while (!stack.empty()) {
        const auto [i, j] = stack.back();
        stack.pop_back();
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
}

Path douglas_peucker(const Path& path, bool closed, double tolerance) {
    SimplifyScratch scratch;
    Path out;
    douglas_peucker(path, closed, tolerance, scratch, out);
    return out;
}

}  // namespace carve
