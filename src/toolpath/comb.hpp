// Combing (issue #18): travel paths that stay inside the part, so that a travel needs no
// retraction and leaves no string on the visible surface.
//
// The comb region is the layer's slice eroded by about a line width, as islands (connected
// components, with their holes). A travel between two points of one island goes straight when
// the segment stays inside, otherwise around the boundary contours it would cross and is then
// pulled tight; cavity walls are not obstacles (they are not in the region's boundary), holes
// through the model are. A travel that must leave its island goes inside it to the point where
// the straight line leaves it for the last time, crosses outside, and continues inside the
// target island from where the line first enters it ("avoid crossing perimeters").
#pragma once

#include <optional>
#include <vector>

#include "config/settings.hpp"
#include "geometry/types.hpp"

namespace carve {

class Comber {
  public:
    // `region`: a normalised region (outer contours counter-clockwise, holes clockwise).
    explicit Comber(const Paths& region);

    bool empty() const { return contours_.empty(); }
    int islands() const { return islands_; }
    // Island (index of a connected component of the region) strictly inside which p lies, or -1.
    int island_of(const Point& p) const;
    // p itself if it lies in an island, else the nearest point strictly inside the region within
    // `reach` of p (a wall point lies on or beyond the eroded boundary); with its island.
    struct Located {
        Point p;
        int island = -1;
    };
    std::optional<Located> locate(const Point& p, Coord reach) const;
    // Whether the segment a-b meets no boundary edge (touching counts): with a inside the
    // region, the whole segment then is.
    bool visible(const Point& a, const Point& b) const;
    // Waypoints after a up to and including b of a path inside the region, for a and b inside
    // the same island; nothing when none was found.
    std::optional<Path> route(const Point& a, const Point& b) const;
    // The last point where the segment a-b leaves island `island` (moved just inside it), or
    // nothing when the segment never crosses its boundary.
    std::optional<Point> last_exit(const Point& a, const Point& b, int island) const;
    // The first point where the segment a-b enters island `island` (moved just inside it).
    std::optional<Point> first_entry(const Point& a, const Point& b, int island) const;
    // The point of island `island`'s boundary nearest p, moved just inside it.
    std::optional<Point> nearest_in(const Point& p, int island) const;
    // The shortest distance between the boundaries of islands a and b (the gap a travel from
    // one to the other must cross), in units, and a nearest pair of boundary points. Exact up
    // to kFarGap; beyond, the distance between the islands' boxes (a lower bound), which is
    // enough to order islands that far apart and spares comparing their every edge.
    struct Gap {
        double d = 0;
        Point on_a, on_b;
    };
    static constexpr double kFarGap = 20e3;
    Gap closest(int a, int b) const;
    double gap(int a, int b) const { return closest(a, b).d; }
    // The islands a travel from a to b passes through (a first, b last) when it crosses the
    // least outside in sum: another island may be a stepping stone across a wide gap.
    std::vector<int> stepping_stones(int a, int b) const;

  private:
    struct Hit {
        double t;  // along a-b, 0..1
        int contour;
        int edge;
        Point at;  // the crossing, moved just inside the region
    };
    std::vector<Hit> crossings(const Point& a, const Point& b) const;
    Gap find_closest(int a, int b) const;
    // Visits every edge whose cell the segment passes; stops when f returns true. Returns
    // whether it was stopped.
    template <class F>
    bool for_edges_along(const Point& a, const Point& b, F&& f) const;
    Point inside_vertex(int contour, int vertex) const;
    Point inside_edge_point(int contour, int edge, double x, double y) const;

    struct Contour {
        Path pts;
        int island = 0;
        bool hole = false;
        double length = 0;
        std::vector<double> arc;  // arc length at each vertex from vertex 0
    };
    std::vector<Contour> contours_;
    std::vector<std::pair<int, int>> edges_;  // (contour, first vertex)
    std::vector<std::vector<int>> cells_;     // edge indices per grid cell
    double x0_ = 0, y0_ = 0, cell_ = 1;
    int nx_ = 0, ny_ = 0;
    mutable std::vector<unsigned> stamp_;  // per edge: last query that visited it
    mutable unsigned query_ = 0;
    int islands_ = 0;
    std::vector<std::vector<int>> island_contours_;
    std::vector<BBox2> island_box_;
    mutable std::vector<double> gaps_;  // islands_ x islands_, on first use
    // closest() of each pair, found once: a layer's entry and its travels ask for the same
    // pairs again and again (a Comber is one thread's, per layer).
    mutable std::vector<std::optional<Gap>> closest_;
};

// One planned travel: the points to pass through after the start, up to the target (which is
// not in `via`), and whether it leaves the part (and so retracts).
struct TravelPlan {
    Path via;
    bool leaves = true;
};

struct TravelOptions {
    Coord reach = 0;                 // how far a wall point may lie outside the comb region
    bool avoid_crossing = true;      // route a leaving travel through its islands
    double max_detour_factor = 3;    // a combed path longer than this times the straight line
    double max_detour_extra = 20e3;  // plus this (units) leaves the part instead
};

// `thin`, if given, is a wider region (inside the outer wall's centreline) tried for the
// travels the comb region cannot keep inside: a part too thin for it, a neck where it splits.
TravelPlan plan_travel(const Comber& comber, const Point& from, const Point& to,
                       const TravelOptions& options, const Comber* thin = nullptr);

// The layer's comb region: the region inside the outer wall's centreline (`wall_region`) eroded
// by half a line width, so travel keeps off the outer wall, simplified (a few vertices of a
// curve cost more segment tests than they save detour); without the covers for
// Combing::Inside.
Paths comb_region(const Paths& wall_region, const Paths& covers, const Settings& settings);
TravelOptions travel_options(const Settings& settings);

}  // namespace carve
