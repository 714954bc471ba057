// Streaming top-down slicer: sorted triangles, an active set, segments chained by edge keys.
//
// A vertex exactly on the cutting plane counts as above it (symbolic perturbation: the plane is
// lowered by an infinitesimal), so a crossing triangle always has exactly two crossing edges and
// gives exactly one segment, and a neighbour sharing an edge agrees on whether that edge crosses.
// Segments are then chained through the key of the edge they end on, which makes the loops
// exact in topology whatever the rounding of the coordinates.
#include "slice/slicer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "base/error.hpp"
#include "base/stage_timer.hpp"
#include "geometry/simplify.hpp"

namespace carve {

namespace {

constexpr uint64_t kEmptyKey = std::numeric_limits<uint64_t>::max();
constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
// Slice contours are simplified within tolerance_ (12.5 um, PrusaSlicer's G-code resolution);
// an outline whose mean segment is still shorter than kCoarsestSegment is simplified more, up
// to kMaxTolerance (a quarter of a 0.4 mm line, which the nozzle smears anyway).
constexpr double kCoarsestSegment = 50.0;
constexpr double kMaxTolerance = 100.0;
constexpr size_t kFewVertices = 64;  // too few to be worth the coarse pass
// A vertex whose neighbours lie closer together than kSpikeBase, with the vertex more than
// twice that from them, is the tip of a spike or a slit no nozzle prints; each one is a local
// minimum that the booleans keep in their active edge list, so a comb of them made every
// boolean on the layer quadratic (10,000 teeth 0.02 mm wide: no layer done in 120 s).
constexpr double kSpikeBase = 50.0;
// Open chains beyond this count are closed on themselves instead of matched (quadratic cost).
constexpr size_t kMaxGreedyChains = 4096;

inline uint64_t edge_key(uint32_t a, uint32_t b) {
    return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

// One crossing triangle's segment: it starts on the edge where the triangle's boundary goes
// down through the plane and ends where it comes back up, which puts material on the left.
struct Segment {
    uint64_t start_key;
    uint64_t end_key;
    Point start;
    Point end;
    uint32_t next_same_start;  // other segments starting on the same (non-manifold) edge
    uint32_t chain;            // the open chain this segment heads, if any
    bool used;
};

// An open chain left over after exact chaining; `loop` indexes the loop pool.
struct OpenChain {
    size_t loop;
    bool absorbed;
};

// A triangle of the active set with its corners copied in, so that the per-plane loop reads
// contiguous memory instead of chasing indices into the mesh.
struct ActiveTriangle {
    std::array<uint32_t, 3> index;
    std::array<Vec3, 3> v;
};

ActiveTriangle gather(const Mesh& mesh, uint32_t t) {
    const auto& tri = mesh.triangles[t];
    return {tri, {mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]}};
}

// The smallest float not below x, as an unsigned key whose order is the floats' order: sorting
// these keys sorts the triangles' tops, and comparing a key with a plane never misses a
// triangle whose top is a hair above it. -0 and +0 get the same key, as they compare equal.
uint32_t top_key(double x) {
    float f = float(x);
    if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    if (f == 0) f = 0;
    const uint32_t bits = std::bit_cast<uint32_t>(f);
    return bits & 0x80000000u ? ~bits : bits | 0x80000000u;
}

// Sorts indices by descending key with a four-pass least-significant-digit radix sort.
std::vector<uint32_t> sort_descending(std::vector<uint32_t> keys) {
    const size_t n = keys.size();
    std::vector<uint32_t> order(n), tmp_order(n), tmp_keys(n);
    for (size_t i = 0; i < n; ++i) {
        order[i] = uint32_t(i);
        keys[i] = ~keys[i];
    }
    for (int shift = 0; shift < 32; shift += 8) {
        size_t count[257] = {};
        for (uint32_t k : keys) ++count[((k >> shift) & 0xFF) + 1];
        for (int b = 0; b < 256; ++b) count[b + 1] += count[b];
        for (size_t i = 0; i < n; ++i) {
            const size_t at = count[(keys[i] >> shift) & 0xFF]++;
            tmp_keys[at] = keys[i];
            tmp_order[at] = order[i];
        }
        keys.swap(tmp_keys);
        order.swap(tmp_order);
    }
    return order;
}

// Reusable per-plane state, so that slicing layer after layer allocates (almost) nothing.
class PlaneSlicer {
  public:
    // Adds the segment of triangle t if it crosses the plane; false if it lies entirely above.
    bool add_triangle(const ActiveTriangle& t, double z) {
        const bool above[3] = {t.v[0].z >= z, t.v[1].z >= z, t.v[2].z >= z};
        const int n_above = int(above[0]) + int(above[1]) + int(above[2]);
        if (n_above == 3) return false;
        if (n_above == 0) return true;  // below: not crossing yet
        // Edge i runs from vertex i to vertex i+1 in the triangle's own order.
        int down = -1, up = -1;
        for (int i = 0; i < 3; ++i) {
            const int j = i == 2 ? 0 : i + 1;
            if (above[i] && !above[j]) down = i;
            if (!above[i] && above[j]) up = i;
        }
        const int down_next = down == 2 ? 0 : down + 1;
        const int up_next = up == 2 ? 0 : up + 1;
        Segment s;
        s.start_key = edge_key(t.index[down], t.index[down_next]);
        s.end_key = edge_key(t.index[up], t.index[up_next]);
        s.start = crossing(t.v[down], t.v[down_next], z);
        s.end = crossing(t.v[up_next], t.v[up], z);
        s.next_same_start = kNone;
        s.chain = kNone;
        s.used = false;
        segments_.push_back(s);
        return true;
    }

    // The segments collected so far, for another PlaneSlicer to finish.
    std::vector<Segment> take_segments() {
        std::vector<Segment> out;
        out.reserve(segments_.size());
        out.swap(segments_);
        return out;
    }
    void give_segments(std::vector<Segment> segments) { segments_ = std::move(segments); }

    // Chains the collected segments into loops and unites them (non-zero fill).
    Paths finish() {
        build_table();
        n_loops_ = 0;
        chains_.clear();
        for (uint32_t s = 0; s < segments_.size(); ++s)
            if (!segments_[s].used) walk(s);
        close_open_chains();

        // Same as carve::unite (non-zero fill), fed straight from the loop pool so that the
        // pool keeps its capacity from one plane to the next.
        ClipperLib::Clipper clipper;
        for (size_t i = 0; i < n_loops_; ++i) {
            Path& p = pool_[i];
            drop_collinear(p);
            if (tolerance_ > 0 && p.size() > 3) {
                // A contour sampled more finely than any printer moves (a scan's noise) costs
                // every later Clipper pass per vertex: the tolerance doubles, up to a quarter
                // of a line width, until its vertices are kCoarsestSegment apart on average
                // along the outline's smooth length (its length at the coarsest tolerance: a
                // zigzag's own length would count the noise as detail).
                // A contour that spent the first pass's budget (a zig-zag whose teeth all
                // stay) would only spend it again at each coarser tolerance.
                double tolerance = tolerance_;
                const bool complete = douglas_peucker(p, true, tolerance, scratch_, simple_);
                if (complete && simple_.size() > kFewVertices) {
                    douglas_peucker(p, true, kMaxTolerance, scratch_, coarse_);
                    const double smooth_length = perimeter(coarse_);
                    while (tolerance<kMaxTolerance&& double(simple_.size()) * kCoarsestSegment>
                               smooth_length) {
                        tolerance = std::min(2 * tolerance, kMaxTolerance);
                        douglas_peucker(p, true, tolerance, scratch_, simple_);
                    }
                }
                p.swap(simple_);
            }
            drop_spikes(p);
            if (p.size() >= 3) clipper.AddPath(p, ClipperLib::ptSubject, true);
        }
        Paths region;
        clipper.Execute(ClipperLib::ctUnion, region, ClipperLib::pftNonZero,
                        ClipperLib::pftNonZero);
        segments_.clear();
        return region;
    }

  private:
    // The point where edge (a above, b below) meets the plane, computed from the edge alone so
    // that both triangles sharing the edge get the very same point.
    static Point crossing(const Vec3& a, const Vec3& b, double z) {
        const double t = (z - b.z) / (a.z - b.z);  // a.z >= z > b.z, so in (0, 1]
        const double x = b.x + t * (a.x - b.x);
        const double y = b.y + t * (a.y - b.y);
        return Point(round_units(x * kUnitsPerMm), round_units(y * kUnitsPerMm));
    }

    // std::llround without the library call (half away from zero, as to_units does).
    static Coord round_units(double u) { return u >= 0 ? Coord(u + 0.5) : -Coord(-u + 0.5); }

    static double perimeter(const Path& p) {
        double sum = 0;
        for (size_t i = 0; i < p.size(); ++i) {
            const Point& a = p[i];
            const Point& b = p[i + 1 < p.size() ? i + 1 : 0];
            sum += std::hypot(double(b.X - a.X), double(b.Y - a.Y));
        }
        return sum;
    }

    // Squared distance from q to the segment a-b, in square units.
    static double dist2_to_segment(const Point& q, const Point& a, const Point& b) {
        const double abx = double(b.X - a.X), aby = double(b.Y - a.Y);
        const double aqx = double(q.X - a.X), aqy = double(q.Y - a.Y);
        const double len2 = abx * abx + aby * aby;
        double t = len2 > 0 ? (aqx * abx + aqy * aby) / len2 : 0;
        t = std::clamp(t, 0.0, 1.0);
        const double dx = aqx - t * abx, dy = aqy - t * aby;
        return dx * dx + dy * dy;
    }

    // One greedy pass: a point goes if it and every point dropped since the last kept one lie
    // within kCleanTolerance of the segment from the last kept point to the next point, so the
    // contour moves by at most that much. Runs are capped to keep the pass linear.
    static void drop_collinear(Path& p) {
        constexpr double kTol2 = 1.0;  // (1 um)^2
        constexpr size_t kMaxRun = 32;
        if (p.size() < 4) return;
        const size_t n = p.size();
        size_t kept = 1, anchor = 0;  // anchor: original index of the last kept point
        for (size_t i = 1; i < n; ++i) {
            const Point& a = p[kept - 1];
            const Point& c = p[i + 1 < n ? i + 1 : 0];
            bool drop = i - anchor <= kMaxRun;
            for (size_t j = anchor + 1; drop && j <= i; ++j)
                drop = dist2_to_segment(p[j], a, c) <= kTol2;
            if (drop) continue;
            p[kept++] = p[i];
            anchor = i;
        }
        p.resize(kept);
    }

    // One pass with a stack: a tip taken off can make its neighbour the next tip (the teeth of a
    // comb go one after another, the taper of a wedge down to kSpikeBase wide).
    static void drop_spikes(Path& p) {
        if (p.size() < 4) return;
        size_t kept = 0;
        auto spike = [&](const Point& a, const Point& tip, const Point& b) {
            // Narrower than kSpikeBase, more than twice as long as wide and at least half
            // kSpikeBase long: a needle, not a vertex the simplification left on a curve.
            const double base2 = dist2(a, b);
            if (base2 >= kSpikeBase * kSpikeBase) return false;
            const double height2 = dist2_to_segment(tip, a, b);
            return height2 > 4 * base2 && height2 > kSpikeBase * kSpikeBase / 4;
        };
        for (size_t i = 0; i < p.size(); ++i) {
            p[kept++] = p[i];
            while (kept >= 3 && spike(p[kept - 3], p[kept - 2], p[kept - 1])) {
                p[kept - 2] = p[kept - 1];
                --kept;
            }
        }
        p.resize(kept);
    }

    static uint64_t hash(uint64_t key) { return key * 0x9E3779B97F4A7C15ull; }

    void build_table() {
        size_t cap = 16;
        while (cap < 2 * segments_.size()) cap <<= 1;
        shift_ = 64 - std::countr_zero(cap);
        mask_ = cap - 1;
        keys_.assign(cap, kEmptyKey);
        heads_.resize(cap);
        for (uint32_t s = 0; s < segments_.size(); ++s) {
            const uint64_t key = segments_[s].start_key;
            size_t h = hash(key) >> shift_;
            while (keys_[h] != kEmptyKey && keys_[h] != key) h = (h + 1) & mask_;
            if (keys_[h] == kEmptyKey) {
                keys_[h] = key;
                heads_[h] = s;
            } else {
                segments_[s].next_same_start = heads_[h];
                heads_[h] = s;
            }
        }
    }

    uint32_t head(uint64_t key) const {
        size_t h = hash(key) >> shift_;
        while (keys_[h] != kEmptyKey) {
            if (keys_[h] == key) return heads_[h];
            h = (h + 1) & mask_;
        }
        return kNone;
    }

    Path& new_loop() {
        if (n_loops_ == pool_.size()) pool_.emplace_back();
        Path& p = pool_[n_loops_++];
        p.clear();
        return p;
    }

    // An open chain appended to another gives its storage back: the pool keeps each loop's
    // capacity from plane to plane, and chains absorbed one into the next (an open mesh of
    // slivers: thousands a plane) would otherwise each keep a copy of all the ones before it,
    // quadratic in the chain (a 40 mm cube of 12,000 fanned slivers: 226 MB).
    static void release(Path& p) { Path().swap(p); }

    static void push_point(Path& p, const Point& q) {
        if (p.empty() || p.back() != q) p.push_back(q);
    }

    // Follows segments from `first` through shared edges until the loop closes or breaks off.
    void walk(uint32_t first) {
        const size_t loop_index = n_loops_;
        Path& loop = new_loop();
        uint32_t cur = first;
        segments_[cur].used = true;
        for (;;) {
            const Segment& s = segments_[cur];
            push_point(loop, s.start);
            if (s.end_key == segments_[first].start_key) break;  // closed
            uint32_t next = head(s.end_key);
            uint32_t open_chain = kNone;
            while (next != kNone && segments_[next].used) {
                const uint32_t c = segments_[next].chain;
                if (c != kNone && !chains_[c].absorbed) open_chain = c;
                next = segments_[next].next_same_start;
            }
            if (next != kNone) {
                segments_[next].used = true;
                cur = next;
                continue;
            }
            // Broken off: an open mesh. Append the open chain that starts here, if any, so
            // that open chains are maximal before they are matched by distance.
            push_point(loop, s.end);
            if (open_chain != kNone) {
                OpenChain& other = chains_[open_chain];
                other.absorbed = true;
                for (const Point& q : pool_[other.loop]) push_point(loop, q);
                release(pool_[other.loop]);
            }
            segments_[first].chain = uint32_t(chains_.size());
            chains_.push_back({loop_index, false});
            return;
        }
        if (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
    }

    static double dist2(const Point& a, const Point& b) {
        const double dx = double(a.X - b.X), dy = double(a.Y - b.Y);
        return dx * dx + dy * dy;
    }

    // Best effort for open meshes: repeatedly join a chain's end to the nearest chain start,
    // its own start included, which closes it.
    void close_open_chains() {
        std::vector<size_t> open;
        for (const OpenChain& c : chains_)
            if (!c.absorbed && !pool_[c.loop].empty()) open.push_back(c.loop);
        if (open.size() > kMaxGreedyChains) return;  // each closes on itself
        std::vector<bool> done(open.size(), false);
        for (size_t i = 0; i < open.size(); ++i) {
            if (done[i]) continue;
            Path& p = pool_[open[i]];
            for (;;) {
                size_t best = i;
                double best_d = dist2(p.back(), p.front());
                for (size_t j = i + 1; j < open.size(); ++j) {
                    if (done[j]) continue;
                    const double d = dist2(p.back(), pool_[open[j]].front());
                    if (d < best_d) best_d = d, best = j;
                }
                if (best == i) break;
                done[best] = true;
                for (const Point& q : pool_[open[best]]) push_point(p, q);
                release(pool_[open[best]]);
            }
            done[i] = true;
        }
    }

    double tolerance_ = 12.5;
    SimplifyScratch scratch_;
    Path simple_, coarse_;
    std::vector<Segment> segments_;
    std::vector<uint64_t> keys_;
    std::vector<uint32_t> heads_;
    int shift_ = 60;
    size_t mask_ = 15;
    std::vector<Path> pool_;
    size_t n_loops_ = 0;
    std::vector<OpenChain> chains_;
};

}  // namespace

struct TopDownSlicer::Impl {
    Impl(const Mesh& m, double h, double first) : mesh(m), layer_height(h), first_layer(first) {}

    // Where layer i is cut above zmin: the middle of the first layer, then of each layer above
    // it. (i + 0.5) h to the bit when the first layer is h (first_layer - h is then 0).
    double middle(int i) const {
        return i == 0 ? first_layer / 2 : (first_layer - layer_height) + (i + 0.5) * layer_height;
    }

    const Mesh& mesh;
    double layer_height;
    double first_layer;
    double zmin = 0, zmax = 0;
    int count = 0;
    int next_index = -1;
    std::vector<uint32_t> order;  // triangles by descending top z
    size_t next_in_order = 0;
    std::vector<ActiveTriangle> active;
    PlaneSlicer plane;
    std::function<void(const Slice&)> on_slice;
};

TopDownSlicer::TopDownSlicer(const Mesh& mesh, double layer_height, double first_layer_height)
    : impl_(std::make_unique<Impl>(mesh, layer_height,
                                   first_layer_height > 0 ? first_layer_height : layer_height)) {
    if (!(layer_height > 0) || !std::isfinite(layer_height))
        throw InputError("layer height must be a positive number of millimetres");
    if (!std::isfinite(first_layer_height) || first_layer_height < 0)
        throw InputError("first layer height must be a positive number of millimetres");
    Impl& m = *impl_;
    if (mesh.triangles.empty()) return;
    {
        std::vector<uint32_t> keys(mesh.triangles.size());
        m.zmin = std::numeric_limits<double>::infinity();
        m.zmax = -m.zmin;
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const auto& tri = mesh.triangles[t];
            const double a = mesh.vertices[tri[0]].z, b = mesh.vertices[tri[1]].z,
                         c = mesh.vertices[tri[2]].z;
            const double top = std::max({a, b, c});
            keys[t] = top_key(top);
            m.zmax = std::max(m.zmax, top);
            m.zmin = std::min({m.zmin, a, b, c});
        }
        m.order = sort_descending(std::move(keys));
    }
    // Planes strictly inside [zmin, zmax): a plane at zmax would only graze the top.
    const double span = m.zmax - m.zmin;
    if (span / layer_height > 1e7)
        throw InputError("layer height too small for a model this tall (over 10 million layers)");
    // The layers whose middle lies below the top.
    int n =
        int(std::max(0.0, std::ceil((span - (m.first_layer - layer_height)) / layer_height - 0.5)));
    while (n > 0 && m.middle(n - 1) >= span) --n;
    while (m.middle(n) < span) ++n;
    m.count = n;
    m.next_index = n - 1;
}

TopDownSlicer::~TopDownSlicer() = default;

int TopDownSlicer::layer_count() const {
    return impl_->count;
}

double TopDownSlicer::plane_z(int i) const {
    return impl_->zmin + impl_->middle(i);
}

std::vector<uint32_t> TopDownSlicer::plane_segments() const {
    const Impl& m = *impl_;
    // The very doubles next_cut() compares with, so that the counts are exact: a triangle
    // gives a segment on a plane at z when its lowest corner is below z and its highest at or
    // above it (a corner on the plane counts as above).
    std::vector<double> zs(size_t(m.count));
    for (int i = 0; i < m.count; ++i) zs[size_t(i)] = plane_z(i);
    std::vector<int64_t> change(zs.size() + 1, 0);
    for (const auto& tri : m.mesh.triangles) {
        const double a = m.mesh.vertices[tri[0]].z, b = m.mesh.vertices[tri[1]].z,
                     c = m.mesh.vertices[tri[2]].z;
        const auto first = std::upper_bound(zs.begin(), zs.end(), std::min({a, b, c}));
        const auto end = std::upper_bound(first, zs.end(), std::max({a, b, c}));
        ++change[size_t(first - zs.begin())];
        --change[size_t(end - zs.begin())];
    }
    std::vector<uint32_t> counts(zs.size());
    int64_t running = 0;
    for (size_t i = 0; i < zs.size(); ++i) counts[i] = uint32_t(running += change[i]);
    return counts;
}

struct PlaneCut::Impl {
    int index = 0;
    double z = 0;
    std::vector<Segment> segments;
};

PlaneCut::PlaneCut() : impl_(std::make_unique<Impl>()) {}
PlaneCut::~PlaneCut() = default;
PlaneCut::PlaneCut(PlaneCut&&) noexcept = default;
PlaneCut& PlaneCut::operator=(PlaneCut&&) noexcept = default;

Slice PlaneCut::chain() && {
    StageTimer timer(Stage::kSlice);
    // One per thread, so that chaining plane after plane allocates (almost) nothing.
    thread_local PlaneSlicer plane;
    Slice slice;
    slice.index = impl_->index;
    slice.z = impl_->z;
    plane.give_segments(std::move(impl_->segments));
    slice.region = plane.finish();
    return slice;
}

std::optional<PlaneCut> TopDownSlicer::next_cut() {
    StageTimer timer(Stage::kSlice);
    Impl& m = *impl_;
    if (m.next_index < 0) return std::nullopt;
    PlaneCut cut;
    cut.impl_->index = m.next_index--;
    cut.impl_->z = m.zmin + m.middle(cut.impl_->index);
    const double z = cut.impl_->z;

    // Triangles whose top reached the plane join the active set (a key may let one in a float
    // ulp early, which is harmless); those entirely above the plane (vertices on it count as
    // above) never cross again and leave it.
    const uint32_t plane_key = top_key(z);
    while (m.next_in_order < m.order.size()) {
        const uint32_t t = m.order[m.next_in_order];
        const ActiveTriangle a = gather(m.mesh, t);
        if (top_key(std::max({a.v[0].z, a.v[1].z, a.v[2].z})) < plane_key) break;
        ++m.next_in_order;
        if (std::min({a.v[0].z, a.v[1].z, a.v[2].z}) < z) m.active.push_back(a);
    }
    size_t kept = 0;
    for (size_t i = 0; i < m.active.size(); ++i)
        if (m.plane.add_triangle(m.active[i], z)) m.active[kept++] = m.active[i];
    m.active.resize(kept);
    cut.impl_->segments = m.plane.take_segments();
    return cut;
}

std::optional<Slice> TopDownSlicer::next() {
    std::optional<PlaneCut> cut = next_cut();
    if (!cut) return std::nullopt;
    Slice slice = std::move(*cut).chain();
    if (impl_->on_slice) impl_->on_slice(slice);
    return slice;
}

void TopDownSlicer::on_slice(std::function<void(const Slice&)> check) {
    impl_->on_slice = std::move(check);
}

Paths slice_at(const Mesh& mesh, double z) {
    PlaneSlicer plane;
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) plane.add_triangle(gather(mesh, t), z);
    return plane.finish();
}

}  // namespace carve
