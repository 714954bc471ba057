// Seam placement (see seam.hpp).
//
// A corner is measured over a window of about a millimetre on each side rather than at the
// vertex: on a finely tessellated curve every vertex turns a little and a real corner may be
// cut into several small turns, but the turn across the window is the same either way.
#include "toolpath/seam.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace carve {

namespace {

constexpr double kWindow = 1000.0;        // units on each side of a vertex for its turn
constexpr double kCornerDeg = 35.0;       // a turn at least this sharp is a corner
constexpr double kDirection = 1.0471976;  // aligned: 60 degrees, rear right of the bed

// Signed turn (radians, positive = left, convex for the region on the left) at each vertex,
// between the directions from the point about kWindow before it and to the point about kWindow
// after it.
std::vector<double> window_turns(const Path& loop) {
    const size_t n = loop.size();
    std::vector<double> turn(n, 0.0);
    double total = 0;
    for (size_t i = 0; i < n; ++i) total += distance(loop[i], loop[(i + 1) % n]);
    if (total <= 0 || n < 3) return turn;
    const double window = std::min(kWindow, total / 4);
    for (size_t i = 0; i < n; ++i) {
        size_t a = i, b = i;
        double da = 0, db = 0;
        for (size_t steps = 0; da < window && steps + 1 < n; ++steps) {
            const size_t prev = (a + n - 1) % n;
            da += distance(loop[a], loop[prev]);
            a = prev;
        }
        for (size_t steps = 0; db < window && steps + 1 < n; ++steps) {
            const size_t next = (b + 1) % n;
            db += distance(loop[b], loop[next]);
            b = next;
        }
        const Point& p = loop[i];
        const double ux = double(p.X - loop[a].X), uy = double(p.Y - loop[a].Y);
        const double vx = double(loop[b].X - p.X), vy = double(loop[b].Y - p.Y);
        turn[i] = std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
    }
    return turn;
}

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

}  // namespace

size_t seam_vertex(const Path& loop, SeamMode mode, int layer, size_t loop_index,
                   const Point& nozzle) {
    const size_t n = loop.size();
    if (n == 0) return 0;
    size_t best = 0;
    switch (mode) {
        case SeamMode::Nearest: {
            double d = distance(loop[0], nozzle);
            for (size_t i = 1; i < n; ++i)
                if (const double e = distance(loop[i], nozzle); e < d) d = e, best = i;
            return best;
        }
        case SeamMode::Random:
            return size_t(mix((std::uint64_t(std::max(layer, 0)) << 20) ^ loop_index) % n);
        case SeamMode::Rear: {
            // Slightly tilted so that a flat back edge resolves to the same end every layer.
            auto key = [&](const Point& p) { return double(p.Y) + 1e-3 * double(p.X); };
            for (size_t i = 1; i < n; ++i)
                if (key(loop[i]) > key(loop[best])) best = i;
            return best;
        }
        case SeamMode::Aligned:
            break;
    }
    const std::vector<double> turn = window_turns(loop);
    const double corner = kCornerDeg * std::numbers::pi / 180.0;
    const double cx = std::cos(kDirection), cy = std::sin(kDirection);
    // Rank: 2 = concave corner, 1 = convex corner, 0 = smooth; then furthest along the direction.
    auto rank = [&](size_t i) { return turn[i] <= -corner ? 2 : turn[i] >= corner ? 1 : 0; };
    auto along = [&](size_t i) { return double(loop[i].X) * cx + double(loop[i].Y) * cy; };
    int best_rank = rank(0);
    for (size_t i = 1; i < n; ++i) {
        const int r = rank(i);
        if (r > best_rank || (r == best_rank && along(i) > along(best))) best = i, best_rank = r;
    }
    if (best_rank == 0) return best;
    // Within the chosen corner (several vertices of one rounded corner share its rank), the
    // vertex that turns most, so the seam sits in the crease itself.
    size_t sharpest = best;
    for (size_t step = 1; step < n; ++step) {
        const size_t i = (best + step) % n;
        if (distance(loop[i], loop[best]) > kWindow) break;
        if (std::abs(turn[i]) > std::abs(turn[sharpest]) && rank(i) == best_rank) sharpest = i;
    }
    for (size_t step = 1; step < n; ++step) {
        const size_t i = (best + n - step) % n;
        if (distance(loop[i], loop[best]) > kWindow) break;
        if (std::abs(turn[i]) > std::abs(turn[sharpest]) && rank(i) == best_rank) sharpest = i;
    }
    return sharpest;
}

}  // namespace carve
