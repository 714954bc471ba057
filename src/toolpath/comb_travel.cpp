// Travel planning over the comb region (see comb.hpp): which way a travel goes, given what
// Comber answers about the region. Inside one island, the route around the contours in the
// way unless it is a long detour; between islands, out where they are closest, or else along
// the straight line, inside each island as far as it goes ("avoid crossing perimeters"); and
// the comb region of a layer with the options the settings give.
#include <optional>
#include <utility>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "toolpath/comb.hpp"

namespace carve {

namespace {

double polyline_length(const Point& from, const Path& via, const Point& to) {
    double len = 0;
    Point cur = from;
    for (const Point& p : via) len += distance(cur, p), cur = p;
    return len + distance(cur, to);
}

void append_route(Path& via, const Path& route) {
    for (const Point& p : route)
        if (via.empty() || via.back() != p) via.push_back(p);
}

// The waypoints of a travel inside one island of `comber`, or nothing when the ends are not in
// one island or the path inside is much longer than the straight line.
std::optional<Path> inside_route(const Comber& comber, const Point& from, const Point& to,
                                 const TravelOptions& options) {
    const auto la = comber.locate(from, options.reach);
    if (!la) return std::nullopt;
    const auto lb = comber.locate(to, options.reach);
    if (!lb || la->island != lb->island) return std::nullopt;
    auto r = comber.route(la->p, lb->p);
    if (!r) return std::nullopt;
    Path via;
    if (la->p != from) via.push_back(la->p);
    append_route(via, *r);
    if (!via.empty() && via.back() == to) via.pop_back();
    if (polyline_length(from, via, to) >
        options.max_detour_factor * distance(from, to) + options.max_detour_extra)
        return std::nullopt;
    return via;
}

}  // namespace

namespace {

// A travel that leaves its island (or starts or ends outside the region): across the
// narrowest gaps, inside the islands on the way as far as it can.
TravelPlan leave(const Comber& comber, const std::optional<Comber::Located>& la,
                 const std::optional<Comber::Located>& lb, const Point& from, const Point& to,
                 const TravelOptions& options) {
    TravelPlan plan;
    const double straight = distance(from, to);
    if (la && lb) {
        // Across a wide gap through the islands beside it, when the narrower gaps that way are
        // less outside in sum (skull's small islands round its big one at 40-50 mm): in each
        // island from the point nearest the island before to the point nearest the next.
        const std::vector<int> hops = comber.stepping_stones(la->island, lb->island);
        if (hops.size() > 2) {
            Path via;
            if (la->p != from) via.push_back(la->p);
            Point cur = la->p;
            bool ok = true;
            for (size_t h = 0; ok && h + 1 < hops.size(); ++h) {
                const Comber::Gap g = comber.closest(hops[h], hops[h + 1]);
                std::optional<Point> x, y;
                if (g.d <= Comber::kFarGap) {
                    x = comber.nearest_in(g.on_a, hops[h]);
                    y = comber.nearest_in(g.on_b, hops[h + 1]);
                } else if ((x = comber.nearest_in(lb->p, hops[h]))) {
                    y = comber.nearest_in(*x, hops[h + 1]);
                }
                std::optional<Path> r;
                if (x && y) r = comber.route(cur, *x);
                ok = r.has_value();
                if (!ok) break;
                append_route(via, *r);
                append_route(via, Path{*y});
                cur = *y;
            }
            std::optional<Path> last;
            if (ok) last = comber.route(cur, lb->p);
            if (last) {
                append_route(via, *last);
                if (!via.empty() && via.back() == to) via.pop_back();
                if (polyline_length(from, via, to) <=
                    options.max_detour_factor * straight + options.max_detour_extra) {
                    plan.via = std::move(via);
                    return plan;
                }
            }
        }
        // Leave where the two islands are closest (alternating nearest points, from the
        // target), so that the part outside, where the string is drawn, is the gap between
        // them; the parts inside cost only travel time, retracted.
        std::optional<Point> x = comber.nearest_in(lb->p, la->island), y;
        for (int round = 0; round < 2 && x; ++round) {
            y = comber.nearest_in(*x, lb->island);
            if (!y) break;
            x = comber.nearest_in(*y, la->island);
        }
        if (x && y) {
            auto r1 = comber.route(la->p, *x);
            auto r2 = comber.route(*y, lb->p);
            if (r1 && r2) {
                Path via;
                if (la->p != from) via.push_back(la->p);
                append_route(via, *r1);
                append_route(via, Path{*y});
                append_route(via, *r2);
                if (!via.empty() && via.back() == to) via.pop_back();
                if (polyline_length(from, via, to) <=
                    options.max_detour_factor * straight + options.max_detour_extra) {
                    plan.via = std::move(via);
                    return plan;
                }
            }
        }
    }
    // Inside the start island to where the line towards the target leaves it for good, across,
    // and inside the target island from where the line first enters it.
    Path via;
    Point cur = from;
    const Point target = lb ? lb->p : to;
    if (la) {
        if (la->p != from) via.push_back(la->p);
        cur = la->p;
        if (auto x = comber.last_exit(la->p, target, la->island)) {
            if (auto r = comber.route(la->p, *x)) {
                append_route(via, *r);
                cur = *x;
            }
        }
    }
    if (lb) {
        if (auto y = comber.first_entry(cur, lb->p, lb->island)) {
            if (auto r = comber.route(*y, lb->p)) {
                append_route(via, Path{*y});
                append_route(via, *r);
            }
        }
        append_route(via, Path{lb->p});
    }
    if (!via.empty() && via.back() == to) via.pop_back();
    plan.via = std::move(via);
    return plan;
}

}  // namespace

TravelPlan plan_travel(const Comber& comber, const Point& from, const Point& to,
                       const TravelOptions& options, const Comber* thin) {
    TravelPlan plan;
    if (from == to) {
        plan.leaves = false;
        return plan;
    }
    if (comber.empty()) return plan;
    const auto la = comber.locate(from, options.reach);
    const auto lb = comber.locate(to, options.reach);
    const bool same_island = la && lb && la->island == lb->island;
    if (same_island || thin) {
        // Parts too thin for the comb region (a blade two lines thick), and necks where it
        // comes apart, are still inside the part: through them along the outer wall.
        std::optional<Path> via = same_island ? inside_route(comber, from, to, options)
                                              : inside_route(*thin, from, to, options);
        if (!via && same_island && thin) via = inside_route(*thin, from, to, options);
        if (via) {
            plan.via = std::move(*via);
            plan.leaves = false;
            return plan;
        }
        if (same_island) return plan;  // no reasonable way inside: straight, retracted
    }
    if (!options.avoid_crossing) return plan;
    // Ends the comb region does not reach (a part too thin for it, cover lines on a steep thin
    // shell) crossed straight: from the region inside the outer wall's centreline instead, when
    // it holds them in two islands (one, and inside_route above found no way).
    if ((!la || !lb) && thin) {
        const auto ta = thin->locate(from, options.reach);
        const auto tb = thin->locate(to, options.reach);
        if (ta && tb && ta->island != tb->island) return leave(*thin, ta, tb, from, to, options);
    }
    return leave(comber, la, lb, from, to, options);
}

Paths comb_region(const Paths& wall_region, const Paths& covers, const Settings& settings) {
    if (settings.combing == Combing::Off || wall_region.empty()) return {};
    Paths region = erode(wall_region, settings.nozzle_radius());
    if (settings.combing == Combing::Inside && !covers.empty()) region = subtract(region, covers);
    return simplify(region, double(settings.line_width()) / 8);
}

TravelOptions travel_options(const Settings& settings) {
    TravelOptions o;
    // A wall point lies half a line width outside the region (the outer wall's centreline), or
    // on a cover's edge; the simplification moves the boundary a little more.
    o.reach = settings.line_width() + settings.line_width() / 4;
    o.avoid_crossing = settings.avoid_crossing_perimeters;
    return o;
}

}  // namespace carve
