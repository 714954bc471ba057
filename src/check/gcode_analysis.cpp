// G-code analyser: rebuilds each layer's extruded footprint from the moves and measures what
// nothing below holds, plus material and the slicer's own header figures.
//
// Deliberately self-contained (Clipper, nlohmann-json and the standard library only) so that the
// baseline script can build it alone, without the rest of the pipeline. ClipperOffset is used
// here on purpose: this is a measuring tool, and round-capped offsets of open polylines are the
// natural model of a bead seen from above.
#include "check/gcode_analysis.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <numbers>

#include "base/error.hpp"
#include "gcode/motion.hpp"

namespace carve {

namespace {

using ClipperLib::Clipper;
using ClipperLib::ClipperOffset;

constexpr double kArcToleranceUnits = 5.0;  // 5 um: a 2 mm disk gets ~44 sides, a bead cap ~14
constexpr double kZTolerance = 1e-4;        // mm: same layer
constexpr double kMinMoveMm = 1e-6;         // shorter XY moves draw nothing
constexpr double kReliableMm = 0.05;      // shorter moves carry too much rounding to judge a width
constexpr double kWidthTolerance = 0.05;  // relative width change that starts a new polyline
constexpr double kArcSagittaMm = 0.005;

double region_area_mm2(const Paths& region) {
    double a = 0;
    for (const Path& p : region) a += ClipperLib::Area(p);
    return a / (kUnitsPerMm * kUnitsPerMm);
}

Paths dilate_round(const Paths& region, Coord delta) {
    if (region.empty() || delta <= 0) return region;
    ClipperOffset off(2.0, kArcToleranceUnits);
    off.AddPaths(region, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    Paths out;
    off.Execute(out, static_cast<double>(delta));
    return out;
}

Paths difference(const Paths& a, const Paths& b) {
    if (a.empty() || b.empty()) return a;
    Clipper c;
    c.AddPaths(a, ClipperLib::ptSubject, true);
    c.AddPaths(b, ClipperLib::ptClip, true);
    Paths out;
    c.Execute(ClipperLib::ctDifference, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    return out;
}

// Total length of open paths, mm.
double open_length_mm(const Paths& paths) {
    double l = 0;
    for (const Path& p : paths)
        for (size_t i = 1; i < p.size(); ++i)
            l += std::hypot(double(p[i].X - p[i - 1].X), double(p[i].Y - p[i - 1].Y));
    return l / kUnitsPerMm;
}

Paths intersection(const Paths& a, const Paths& b) {
    if (a.empty() || b.empty()) return {};
    Clipper c;
    c.AddPaths(a, ClipperLib::ptSubject, true);
    c.AddPaths(b, ClipperLib::ptClip, true);
    Paths out;
    c.Execute(ClipperLib::ctIntersection, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    return out;
}

// Cells of a coarse grid that hold a point of a region's boundary: a cheap, conservative proof
// that a point lies within some distance of the region.
class NearMap {
  public:
    NearMap(const Paths& region, double cell) : cell_(cell) {
        bool any = false;
        for (const Path& p : region) {
            for (const Point& q : p) {
                min_x_ = std::min(min_x_, double(q.X));
                min_y_ = std::min(min_y_, double(q.Y));
                max_x_ = std::max(max_x_, double(q.X));
                max_y_ = std::max(max_y_, double(q.Y));
                any = true;
            }
        }
        if (!any) return;
        nx_ = static_cast<long>((max_x_ - min_x_) / cell_) + 1;
        ny_ = static_cast<long>((max_y_ - min_y_) / cell_) + 1;
        marked_.assign(static_cast<size_t>(nx_ * ny_), 0);
        // Points every half cell along each edge: each marks a cell that truly holds boundary.
        for (const Path& p : region) {
            for (size_t i = 0; i < p.size(); ++i) {
                const Point& a = p[i];
                const Point& b = p[(i + 1) % p.size()];
                double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
                int n = std::max(1, static_cast<int>(std::ceil(2 * std::hypot(dx, dy) / cell_)));
                for (int k = 0; k <= n; ++k) mark(a.X + dx * k / n, a.Y + dy * k / n);
            }
        }
    }

    // True only if (x, y) is proven within `radius` of the region's boundary.
    bool within(double x, double y, double radius) const {
        if (marked_.empty()) return false;
        long rings = static_cast<long>(std::floor(radius / (cell_ * std::numbers::sqrt2))) - 1;
        long cx = static_cast<long>(std::floor((x - min_x_) / cell_));
        long cy = static_cast<long>(std::floor((y - min_y_) / cell_));
        for (long ring = 0; ring <= rings; ++ring) {
            for (long j = cy - ring; j <= cy + ring; ++j) {
                if (j < 0 || j >= ny_) continue;
                bool edge_row = j == cy - ring || j == cy + ring;
                for (long i = cx - ring; i <= cx + ring; i += edge_row ? 1 : 2 * ring) {
                    if (i >= 0 && i < nx_ && marked_[static_cast<size_t>(j * nx_ + i)]) return true;
                    if (ring == 0) break;
                }
            }
        }
        return false;
    }

  private:
    void mark(double x, double y) {
        long i = std::clamp(static_cast<long>((x - min_x_) / cell_), 0L, nx_ - 1);
        long j = std::clamp(static_cast<long>((y - min_y_) / cell_), 0L, ny_ - 1);
        marked_[static_cast<size_t>(j * nx_ + i)] = 1;
    }

    double cell_;
    double min_x_ = std::numeric_limits<double>::max(), min_y_ = std::numeric_limits<double>::max();
    double max_x_ = std::numeric_limits<double>::lowest();
    double max_y_ = std::numeric_limits<double>::lowest();
    long nx_ = 0, ny_ = 0;
    std::vector<unsigned char> marked_;
};

// Consecutive extruding moves of one width, drawn without a travel in between.
struct Polyline {
    Path points;
    double e = 0;       // filament mm
    double length = 0;  // mm
};

double line_width(double volume_per_mm, double height, BeadModel bead) {
    double w = volume_per_mm / height;
    return bead == BeadModel::kRounded ? w + height * (1 - std::numbers::pi / 4) : w;
}

Paths widen(const std::vector<Polyline>& lines, double height_mm, double filament_area,
            BeadModel bead) {
    // One offset per integer half-width (in um) keeps the count of Clipper runs small while the
    // width stays exact to the unit.
    std::map<Coord, Paths> by_half_width;
    for (const Polyline& l : lines) {
        if (l.length <= 0 || l.points.empty()) continue;
        double width = line_width(l.e * filament_area / l.length, height_mm, bead);
        Coord half = static_cast<Coord>(std::llround(width * kUnitsPerMm / 2));
        if (half < 1) continue;
        by_half_width[half].push_back(l.points);
    }
    Clipper all;
    for (auto& [half, paths] : by_half_width) {
        ClipperOffset off(2.0, kArcToleranceUnits);
        off.AddPaths(paths, ClipperLib::jtRound, ClipperLib::etOpenRound);
        Paths out;
        off.Execute(out, static_cast<double>(half));
        all.AddPaths(out, ClipperLib::ptSubject, true);
    }
    Paths footprint;
    all.Execute(ClipperLib::ctUnion, footprint, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    return footprint;
}

// Uniform grid over a region's edges, for distances from many points to its boundary.
class EdgeGrid {
  public:
    explicit EdgeGrid(const Paths& region, double cell_units = 1000.0) : cell_(cell_units) {
        for (const Path& p : region) {
            for (size_t i = 0; i < p.size(); ++i) {
                const Point& a = p[i];
                const Point& b = p[(i + 1) % p.size()];
                edges_.push_back({a, b});
                min_x_ = std::min({min_x_, a.X, b.X});
                min_y_ = std::min({min_y_, a.Y, b.Y});
                max_x_ = std::max({max_x_, a.X, b.X});
                max_y_ = std::max({max_y_, a.Y, b.Y});
            }
        }
        if (edges_.empty()) return;
        nx_ = static_cast<long>((max_x_ - min_x_) / cell_) + 1;
        ny_ = static_cast<long>((max_y_ - min_y_) / cell_) + 1;
        cells_.assign(static_cast<size_t>(nx_ * ny_), {});
        for (size_t k = 0; k < edges_.size(); ++k) {
            auto [a, b] = edges_[k];
            long x0 = cx(std::min(a.X, b.X)), x1 = cx(std::max(a.X, b.X));
            long y0 = cy(std::min(a.Y, b.Y)), y1 = cy(std::max(a.Y, b.Y));
            for (long y = y0; y <= y1; ++y)
                for (long x = x0; x <= x1; ++x)
                    cells_[static_cast<size_t>(y * nx_ + x)].push_back(k);
        }
    }

    // Distance in units from p to the nearest edge; infinity if the region is empty.
    double distance(const Point& p) const {
        if (edges_.empty()) return std::numeric_limits<double>::infinity();
        long px = cx(p.X), py = cy(p.Y);
        double best = std::numeric_limits<double>::infinity();
        for (long ring = 0;; ++ring) {
            for (long y = py - ring; y <= py + ring; ++y) {
                for (long x = px - ring; x <= px + ring; ++x) {
                    if (std::max(std::labs(x - px), std::labs(y - py)) != ring) continue;
                    if (x < 0 || y < 0 || x >= nx_ || y >= ny_) continue;
                    for (size_t k : cells_[static_cast<size_t>(y * nx_ + x)])
                        best =
                            std::min(best, segment_distance(p, edges_[k].first, edges_[k].second));
                }
            }
            // Every edge not yet seen lies at least `ring` whole cells away.
            if (best <= ring * cell_) break;
            if (ring > nx_ + ny_ + 2) break;
        }
        return best;
    }

  private:
    long cx(Coord x) const {
        return std::clamp(static_cast<long>((x - min_x_) / cell_), 0L, std::max(0L, nx_ - 1));
    }
    long cy(Coord y) const {
        return std::clamp(static_cast<long>((y - min_y_) / cell_), 0L, std::max(0L, ny_ - 1));
    }
    static double segment_distance(const Point& p, const Point& a, const Point& b) {
        double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
        double qx = double(p.X - a.X), qy = double(p.Y - a.Y);
        double len2 = dx * dx + dy * dy;
        double t = len2 > 0 ? std::clamp((qx * dx + qy * dy) / len2, 0.0, 1.0) : 0.0;
        return std::hypot(qx - t * dx, qy - t * dy);
    }

    double cell_;
    std::vector<std::pair<Point, Point>> edges_;
    Coord min_x_ = std::numeric_limits<Coord>::max(), min_y_ = std::numeric_limits<Coord>::max();
    Coord max_x_ = std::numeric_limits<Coord>::min(), max_y_ = std::numeric_limits<Coord>::min();
    long nx_ = 0, ny_ = 0;
    std::vector<std::vector<size_t>> cells_;
};

bool starts_with(std::string_view s, std::string_view prefix) {
    return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

std::string_view trim(std::string_view s) {
    size_t b = s.find_first_not_of(" \t\r");
    if (b == std::string_view::npos) return {};
    size_t e = s.find_last_not_of(" \t\r");
    return s.substr(b, e - b + 1);
}

// Leading number of s (a '+' sign allowed); false if none.
bool parse_number(std::string_view s, double& value, size_t* used = nullptr) {
    size_t skip = (!s.empty() && s[0] == '+') ? 1 : 0;
    const char* begin = s.data() + skip;
    auto [ptr, ec] = std::from_chars(begin, s.data() + s.size(), value);
    if (ec != std::errc() || !std::isfinite(value)) return false;
    if (used) *used = static_cast<size_t>(ptr - s.data());
    return true;
}

// The value after "key" in the first line of `text` that starts with it (after ';' and spaces).
bool find_header_value(std::string_view text, std::string_view key, double& value) {
    size_t pos = 0;
    while ((pos = text.find(key, pos)) != std::string_view::npos) {
        size_t line_start = text.rfind('\n', pos);
        line_start = line_start == std::string_view::npos ? 0 : line_start + 1;
        std::string_view before = trim(text.substr(line_start, pos - line_start));
        if (before == ";" && parse_number(trim(text.substr(pos + key.size(), 32)), value))
            return true;
        pos += key.size();
    }
    return false;
}

struct Words {
    bool has[26] = {};
    double v[26] = {};
    bool any(char c) const { return has[c - 'A']; }
    double get(char c) const { return v[c - 'A']; }
};

class Analyser {
  public:
    // scan_only: parse and track the extent of the extrusion, build no footprint.
    Analyser(const GcodeAnalysisOptions& o, double filament_diameter, bool scan_only = false)
        : opt_(o), scan_only_(scan_only) {
        result_.filament_diameter_mm = filament_diameter;
        filament_area_ = std::numbers::pi * filament_diameter * filament_diameter / 4;
        r_units_ = to_units(o.support_radius_mm);
        far_units_ = to_units(o.far_radius_mm);
    }

    void line(std::string_view s) {
        s = trim(s);
        if (s.empty()) return;
        size_t semi = s.find(';');
        if (semi != std::string_view::npos) {
            comment(trim(s.substr(semi + 1)));
            s = trim(s.substr(0, semi));
            if (s.empty()) return;
        }
        Words w;
        char command = 0;
        int code = -1;
        size_t i = 0;
        while (i < s.size()) {
            char c = s[i];
            if (c == '*') break;  // checksum
            if (c == ' ' || c == '\t') {
                ++i;
                continue;
            }
            if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
            ++i;
            double value = 0;
            size_t used = 0;
            if (c < 'A' || c > 'Z' || !parse_number(s.substr(i), value, &used)) {
                while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
                continue;
            }
            i += used;
            if (command == 0 && (c == 'G' || c == 'M')) {
                command = c;
                code = static_cast<int>(value);
                if (value != code) code = -1;  // G29.1 and friends: not ours
            } else if (command != 0) {
                w.has[c - 'A'] = true;
                w.v[c - 'A'] = value;
            }
        }
        if (command == 'G') g_code(code, w);
        if (command == 'M') {
            if (code == 82) rel_e_ = false;
            if (code == 83) rel_e_ = true;
        }
    }

    GcodeAnalysis finish() {
        // Moves after the last extrusion (retraction, lift, park) belong to the last layer; the
        // travel path they draw ends nowhere, so it cannot cross the wall.
        end_travel();
        if (have_layer_) {
            take_pending();
            finish_layer();
        }
        GcodeAnalysis& r = result_;
        r.extruded_volume_mm3 = r.filament_length_mm * filament_area_;
        if (r.footprint_area_mm2 > 0) {
            r.unsupported_fraction = r.unsupported_area_mm2 / r.footprint_area_mm2;
            r.far_unsupported_fraction = r.far_unsupported_area_mm2 / r.footprint_area_mm2;
        }
        if (width_weight_ > 0) r.mean_line_width_mm = width_sum_ / width_weight_;
        if (r.model_checked && r.layers > 0) r.model_tolerance_mm = tolerance_sum_ / r.layers;
        return std::move(r);
    }

    ExtrusionBounds bounds() const { return above_first_.any ? above_first_ : all_layers_; }

  private:
    void comment(std::string_view c) {
        GcodeAnalysis& r = result_;
        if (r.generator.empty()) {
            if (starts_with(c, "generated by ")) {
                std::string_view g = c.substr(13);
                r.generator = std::string(g.substr(0, g.find(" on ")));
            } else if (starts_with(c, "Generated with ")) {
                r.generator = std::string(trim(c.substr(15)));
            }
        }
        if (starts_with(c, "TYPE:")) {
            type_ = std::string(trim(c.substr(5)));
            return;
        }
        double v = 0;
        if (starts_with(c, "TIME:")) {
            if (r.estimated_time_from_header_s < 0 && parse_number(trim(c.substr(5)), v))
                r.estimated_time_from_header_s = v;
        } else if (starts_with(c, "estimated printing time (normal mode) =")) {
            r.estimated_time_from_header_s = parse_duration_s(c.substr(39));
        } else if (starts_with(c, "filament used [mm] =")) {
            if (parse_number(trim(c.substr(20)), v)) r.filament_used_from_header_mm = v;
        } else if (starts_with(c, "Filament used:")) {
            // Cura: "Filament used: 1.23456m" (one value per extruder, comma separated).
            size_t used = 0;
            std::string_view rest = trim(c.substr(14));
            if (parse_number(rest, v, &used)) {
                bool metres = used < rest.size() && rest[used] == 'm' &&
                              (used + 1 == rest.size() || rest[used + 1] != 'm');
                r.filament_used_from_header_mm = metres ? v * 1000 : v;
            }
        }
    }

    void g_code(int code, const Words& w) {
        switch (code) {
            case 0:
            case 1:
                move(w);
                break;
            case 2:
            case 3:
                arc(w, code == 2);
                break;
            case 4:  // dwell: P milliseconds or S seconds
                add_time(w.any('S') ? w.get('S') : w.any('P') ? w.get('P') / 1000 : 0);
                break;
            case 10:  // firmware retraction (RepRap, Klipper, Marlin with FWRETRACT)
                if (!w.any('P') && !w.any('L')) {  // G10 P/L sets tool offsets on RepRapFirmware
                    ++result_.retractions;
                    ++result_.firmware_retractions;
                    ++pending_.retractions;
                    add_time(opt_.stick_firmware_retract_s);
                }
                break;
            case 11:
                add_time(opt_.stick_firmware_retract_s);
                break;
            case 20:
                unit_ = 25.4;
                break;
            case 21:
                unit_ = 1.0;
                break;
            case 28: {
                bool all = !w.any('X') && !w.any('Y') && !w.any('Z');
                double* pos[3] = {&x_, &y_, &z_};
                for (int a = 0; a < 3; ++a) {
                    if (all || w.any(static_cast<char>('X' + a))) {
                        *pos[a] = 0;
                        offset_[a] = 0;
                    }
                }
                drawing_ = false;
                break;
            }
            case 90:  // Marlin: G90/G91 switch every axis, E included; M82/M83 then override E
                rel_xyz_ = rel_e_ = false;
                break;
            case 91:
                rel_xyz_ = rel_e_ = true;
                break;
            case 92: {
                double pos[3] = {x_, y_, z_};
                for (int a = 0; a < 3; ++a) {
                    char c = static_cast<char>('X' + a);
                    if (w.any(c)) offset_[a] = pos[a] - w.get(c) * unit_;
                }
                if (w.any('E')) e_register_ = w.get('E') * unit_;
                break;
            }
            default:
                break;
        }
    }

    // Target of an axis word in machine coordinates.
    double target(const Words& w, char axis, double current) const {
        if (!w.any(axis)) return current;
        double v = w.get(axis) * unit_;
        return rel_xyz_ ? current + v : v + offset_[axis - 'X'];
    }

    double e_delta(const Words& w) {
        if (!w.any('E')) return 0;
        double v = w.get('E') * unit_;
        double d = rel_e_ ? v : v - e_register_;
        e_register_ = rel_e_ ? e_register_ + v : v;
        return d;
    }

    void feed(const Words& w) {
        if (w.any('F') && w.get('F') > 0) feed_mm_s_ = w.get('F') * unit_ / 60;
    }

    // One move of the measuring stick: from rest to rest at its feed rate.
    void stick_move(double length, double de, bool extrudes) {
        if (length > kMinMoveMm) {
            add_time(trapezoid_time(length, 0, feed_mm_s_, 0,
                                    extrudes ? opt_.stick_print_accel : opt_.stick_travel_accel));
        } else if (de != 0) {
            add_time(std::fabs(de) / feed_mm_s_);  // retraction or its recovery, at F
        }
    }

    void add_time(double seconds) {
        result_.stick_time_s += seconds;
        pending_.stick_time_s += seconds;
    }

    void count_retraction(double de) {
        if (de >= 0) return;
        ++result_.retractions;
        ++pending_.retractions;
    }

    void move(const Words& w) {
        feed(w);
        double nx = target(w, 'X', x_), ny = target(w, 'Y', y_), nz = target(w, 'Z', z_);
        double de = e_delta(w);
        ++result_.moves;
        count_retraction(de);
        double xy = std::hypot(nx - x_, ny - y_);
        stick_move(std::hypot(xy, nz - z_), de, de > 0 && xy > kMinMoveMm);
        segment(nx, ny, nz, de);
    }

    void arc(const Words& w, bool clockwise) {
        ++result_.arcs;
        ++result_.moves;
        feed(w);
        double nx = target(w, 'X', x_), ny = target(w, 'Y', y_), nz = target(w, 'Z', z_);
        double de = e_delta(w);
        count_retraction(de);
        double cx, cy;
        if (w.any('R')) {
            // Centre on the chord's bisector; negative R takes the long way round.
            double rr = w.get('R') * unit_;
            double mx = (x_ + nx) / 2, my = (y_ + ny) / 2;
            double dx = nx - x_, dy = ny - y_, d = std::hypot(dx, dy);
            if (d < kMinMoveMm) {
                stick_move(std::hypot(d, nz - z_), de, de > 0 && d > kMinMoveMm);
                return segment(nx, ny, nz, de);
            }
            double h = std::sqrt(std::max(0.0, rr * rr - d * d / 4));
            double side = ((clockwise ? 1 : -1) * (rr < 0 ? -1 : 1));
            cx = mx + side * h * dy / d;
            cy = my - side * h * dx / d;
        } else {
            cx = x_ + w.get('I') * unit_;
            cy = y_ + w.get('J') * unit_;
        }
        double radius = std::hypot(x_ - cx, y_ - cy);
        double a0 = std::atan2(y_ - cy, x_ - cx), a1 = std::atan2(ny - cy, nx - cx);
        double sweep = a1 - a0;
        if (clockwise) {
            if (sweep >= -1e-12) sweep -= 2 * std::numbers::pi;
        } else if (sweep <= 1e-12) {
            sweep += 2 * std::numbers::pi;
        }
        double step = radius > kArcSagittaMm ? 2 * std::acos(1 - kArcSagittaMm / radius) : 1.0;
        int n = std::clamp(static_cast<int>(std::ceil(std::fabs(sweep) / step)), 1, 10000);
        double arc_xy = std::fabs(sweep) * radius;
        stick_move(std::hypot(arc_xy, nz - z_), de, de > 0 && arc_xy > kMinMoveMm);
        double z0 = z_;
        for (int k = 1; k <= n; ++k) {
            double t = static_cast<double>(k) / n;
            double a = a0 + sweep * t;
            double px = k == n ? nx : cx + radius * std::cos(a);
            double py = k == n ? ny : cy + radius * std::sin(a);
            segment(px, py, z0 + (nz - z0) * t, de / n);
        }
    }

    void segment(double nx, double ny, double nz, double de) {
        double length = std::hypot(nx - x_, ny - y_);
        result_.filament_length_mm += de;
        if (de > 0 && length > kMinMoveMm) {
            end_travel();
            extrude(nx, ny, nz, de, length);
        } else {
            if (length > kMinMoveMm) {
                result_.travel_length_mm += length;
                pending_.travel_length_mm += length;
                if (!scan_only_) {
                    if (travel_.empty()) travel_.push_back(Point(to_units(x_), to_units(y_)));
                    travel_.push_back(Point(to_units(nx), to_units(ny)));
                }
                drawing_ = false;
            }
            if (std::fabs(nz - z_) > 1e-9) drawing_ = false;
        }
        x_ = nx;
        y_ = ny;
        z_ = nz;
    }

    // A travel path is every XY move between two extrusions (z hops included, seen from above).
    // It belongs with what is pending to the layer of the extrusion that ends it: the way to a
    // new layer's first line is part of that layer's travel.
    void end_travel() {
        if (travel_.size() >= 2) {
            pending_.travel.push_back(std::move(travel_));
        }
        travel_.clear();
    }

    void take_pending() {
        layer_.retractions += pending_.retractions;
        layer_.travel_length_mm += pending_.travel_length_mm;
        layer_.stick_time_s += pending_.stick_time_s;
        for (Path& p : pending_.travel) layer_travel_.push_back(std::move(p));
        pending_ = Pending{};
    }

    void extrude(double nx, double ny, double nz, double de, double length) {
        ++result_.extruding_moves;
        if (!have_layer_ || std::fabs(nz - layer_z_) > kZTolerance) {
            start_layer(nz);
            drawing_ = false;
        }
        take_pending();
        result_.volume_by_type_mm3[type_.empty() ? "none" : type_] += de * filament_area_;
        auto grow = [&](ExtrusionBounds& box) {
            for (auto [px, py] : {std::pair{x_, y_}, std::pair{nx, ny}}) {
                if (!box.any) box = {true, px, py, px, py};
                box.min_x = std::min(box.min_x, px), box.max_x = std::max(box.max_x, px);
                box.min_y = std::min(box.min_y, py), box.max_y = std::max(box.max_y, py);
            }
        };
        grow(all_layers_);
        if (!on_bed_) grow(above_first_);
        if (scan_only_) {
            layer_.extruded_volume_mm3 += de * filament_area_;
            layer_.path_length_mm += length;
            drawing_ = true;
            return;
        }
        bool extend = drawing_ && !lines_.empty();
        if (extend) {
            const Polyline& p = lines_.back();
            double pw = p.e / p.length;  // width up to the common factor A_f / h
            double sw = de / length;
            if (length >= kReliableMm && p.length >= kReliableMm &&
                std::fabs(sw - pw) > kWidthTolerance * pw)
                extend = false;
        }
        if (!extend) {
            lines_.emplace_back();
            lines_.back().points.push_back(Point(to_units(x_), to_units(y_)));
        }
        Polyline& p = lines_.back();
        p.points.push_back(Point(to_units(nx), to_units(ny)));
        p.e += de;
        p.length += length;
        layer_.extruded_volume_mm3 += de * filament_area_;
        layer_.path_length_mm += length;
        drawing_ = true;
    }

    void start_layer(double z) {
        if (have_layer_) finish_layer();
        on_bed_ = false;
        double height;
        if (!have_prev_) {
            height = z;
            on_bed_ = true;
            first_z_ = z;
        } else if (z > prev_z_ + kZTolerance) {
            height = z - prev_z_;
        } else {
            // Going down again: a sequential print starting its next object, or odd output.
            ++result_.z_reversals;
            if (z <= first_z_ + kZTolerance) {
                height = z;
                on_bed_ = true;
            } else {
                height = prev_height_;
            }
        }
        have_layer_ = true;
        layer_z_ = z;
        layer_ = LayerFigures{};
        layer_.z_mm = z;
        layer_.height_mm = height;
    }

    void finish_layer() {
        have_layer_ = false;
        double h = layer_.height_mm;
        if (h <= kZTolerance) h = prev_height_ > 0 ? prev_height_ : 0.2;
        if (scan_only_) {
            ++result_.layers;
            have_prev_ = true;
            prev_z_ = layer_.z_mm;
            prev_height_ = h;
            layer_travel_.clear();
            return;
        }
        Paths footprint = widen(lines_, h, filament_area_, opt_.bead);
        lines_.clear();
        layer_.footprint_area_mm2 = region_area_mm2(footprint);
        if (!on_bed_ && have_prev_) {
            Paths unsupported = difference(footprint, dilate_round(prev_footprint_, r_units_));
            layer_.unsupported_area_mm2 = region_area_mm2(unsupported);
            if (!unsupported.empty()) {
                Paths far = far_region(unsupported);
                layer_.far_unsupported_area_mm2 = region_area_mm2(far);
                if (opt_.model_slice && have_prev_model_ && !far.empty()) {
                    // Over the model's slice one layer down: something inside the object could
                    // have held it. The rest hangs beyond the model itself.
                    layer_.hanging_inside_mm2 = region_area_mm2(intersection(far, prev_model_));
                    layer_.hanging_overhang_mm2 =
                        std::max(0.0, layer_.far_unsupported_area_mm2 - layer_.hanging_inside_mm2);
                } else {
                    layer_.hanging_overhang_mm2 = layer_.far_unsupported_area_mm2;
                }
            }
        }
        if (layer_.path_length_mm > 0) {
            double width =
                line_width(layer_.extruded_volume_mm3 / layer_.path_length_mm, h, opt_.bead);
            width_sum_ += width * layer_.path_length_mm;
            width_weight_ += layer_.path_length_mm;
        }
        if (opt_.model_slice) check_model(footprint, h);
        layer_travel_.clear();

        GcodeAnalysis& r = result_;
        if (r.layers == 0) r.first_z_mm = layer_.z_mm;
        r.last_z_mm = std::max(r.last_z_mm, layer_.z_mm);
        ++r.layers;
        r.path_length_mm += layer_.path_length_mm;
        r.footprint_area_mm2 += layer_.footprint_area_mm2;
        r.unsupported_area_mm2 += layer_.unsupported_area_mm2;
        r.far_unsupported_area_mm2 += layer_.far_unsupported_area_mm2;
        r.outside_area_mm2 += layer_.outside_area_mm2;
        r.max_outside_model_mm = std::max(r.max_outside_model_mm, layer_.max_outside_model_mm);
        r.hanging_inside_mm2 += layer_.hanging_inside_mm2;
        r.hanging_overhang_mm2 += layer_.hanging_overhang_mm2;
        r.travel_inside_mm += layer_.travel_inside_mm;
        r.travel_outside_mm += layer_.travel_outside_mm;
        r.wall_crossings += layer_.wall_crossings;
        if (opt_.keep_layers) r.per_layer.push_back(layer_);

        prev_footprint_ = std::move(footprint);
        have_prev_ = true;
        prev_z_ = layer_.z_mm;
        prev_height_ = h;
    }

    // Unsupported extrusion farther than the far radius from the previous layer. Offsetting a
    // whole layer by 2 mm is the expensive part of the analysis, and most unsupported extrusion
    // (slopes, skins over infill) lies well within 2 mm of the layer below, so that is first
    // proven with samples: every point of U lies within m = s (1/sqrt2 + 1/2) of a sample (grid
    // points inside U at spacing s, points every s along its edges), and distance is 1-Lipschitz,
    // so a far point needs a sample farther than R - m. Only the tiles holding such samples go
    // through the exact Clipper computation, on the previous footprint clipped near them.
    Paths far_region(const Paths& unsupported) const {
        constexpr double kSampleMm = 0.2, kCellMm = 0.25, kTileMm = 1.0;
        const double s = kSampleMm * kUnitsPerMm;
        const double margin = s * (std::numbers::sqrt2 / 2 + 0.5) + 2;
        const double threshold = static_cast<double>(far_units_) - margin;
        if (threshold <= 0)
            return difference(unsupported, dilate_round(prev_footprint_, far_units_));

        const NearMap near(prev_footprint_, kCellMm * kUnitsPerMm);
        const double tile = kTileMm * kUnitsPerMm;
        std::vector<std::pair<long, long>> tiles;
        auto test = [&](double x, double y) {
            if (near.within(x, y, threshold)) return;
            tiles.emplace_back(static_cast<long>(std::floor(x / tile)),
                               static_cast<long>(std::floor(y / tile)));
        };
        // Along the edges.
        std::vector<std::pair<long, double>> crossings;  // (grid row, x) where an edge crosses it
        for (const Path& p : unsupported) {
            for (size_t i = 0; i < p.size(); ++i) {
                const Point& a = p[i];
                const Point& b = p[(i + 1) % p.size()];
                double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
                int n = std::max(1, static_cast<int>(std::ceil(std::hypot(dx, dy) / s)));
                for (int k = 0; k < n; ++k) test(a.X + dx * k / n, a.Y + dy * k / n);
                if (a.Y == b.Y) continue;
                // Rows y = j*s with min(a.Y, b.Y) <= y < max(a.Y, b.Y): even-odd crossings.
                double lo = std::min(a.Y, b.Y), hi = std::max(a.Y, b.Y);
                for (long j = static_cast<long>(std::ceil(lo / s)); j * s < hi; ++j) {
                    double y = j * s;
                    crossings.emplace_back(j, a.X + (y - a.Y) * dx / dy);
                }
            }
        }
        // Inside: grid points between pairs of crossings of each row (Clipper's output has no
        // overlapping contours, so even-odd parity is the region).
        std::sort(crossings.begin(), crossings.end());
        for (size_t i = 0; i + 1 < crossings.size(); i += 2) {
            if (crossings[i].first != crossings[i + 1].first) {
                --i;  // unpaired crossing (numerical): resynchronise on the next row
                continue;
            }
            double y = crossings[i].first * s;
            for (long k = static_cast<long>(std::ceil(crossings[i].second / s));
                 k * s <= crossings[i + 1].second; ++k)
                test(k * s, y);
        }
        if (tiles.empty()) return {};

        std::sort(tiles.begin(), tiles.end());
        tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
        // Runs of tiles along x become one rectangle each.
        auto rectangles = [&](double grow) {
            Paths rects;
            for (size_t i = 0; i < tiles.size();) {
                size_t j = i;
                while (j + 1 < tiles.size() && tiles[j + 1].first == tiles[i].first &&
                       tiles[j + 1].second == tiles[j].second + 1)
                    ++j;
                // tiles are (tx, ty) sorted by tx then ty: runs go along y
                Coord x0 = static_cast<Coord>(tiles[i].first * tile - grow);
                Coord x1 = static_cast<Coord>((tiles[i].first + 1) * tile + grow);
                Coord y0 = static_cast<Coord>(tiles[i].second * tile - grow);
                Coord y1 = static_cast<Coord>((tiles[j].second + 1) * tile + grow);
                rects.push_back({Point(x0, y0), Point(x1, y0), Point(x1, y1), Point(x0, y1)});
                i = j + 1;
            }
            return rects;
        };
        Paths suspect = intersection(unsupported, rectangles(margin + 2));
        Paths local = intersection(prev_footprint_, rectangles(margin + far_units_ + 20));
        return difference(suspect, dilate_round(local, far_units_));
    }

    void check_model(const Paths& footprint, double h) {
        result_.model_checked = true;
        Paths model = opt_.model_slice(layer_.z_mm - h / 2);
        double tolerance = opt_.model_tolerance_mm;
        if (tolerance < 0) {
            tolerance = layer_.path_length_mm > 0
                            ? 0.5 * line_width(layer_.extruded_volume_mm3 / layer_.path_length_mm,
                                               h, opt_.bead)
                            : 0.2;
        }
        tolerance_sum_ += tolerance;
        Paths grown = dilate_round(model, to_units(tolerance));
        Paths outside_tol = difference(footprint, grown);
        layer_.outside_area_mm2 = region_area_mm2(outside_tol);
        check_travel(grown);
        prev_model_ = model;
        have_prev_model_ = true;
        // The farthest point outside lies at a vertex of footprint minus model (up to the
        // polygonal approximation); its distance to the model's boundary is what we report.
        Paths outside = difference(footprint, std::move(model));
        if (outside.empty()) return;
        EdgeGrid grid(model);
        double best = 0;
        for (const Path& p : outside)
            for (const Point& q : p) best = std::max(best, grid.distance(q));
        if (std::isfinite(best))
            layer_.max_outside_model_mm = best / kUnitsPerMm;
        else
            layer_.max_outside_model_mm = std::numeric_limits<double>::infinity();
    }

    // Travel against the model's slice grown by the outside tolerance (the outer wall's bead
    // centres lie half a line width inside the slice, so travel along the wall stays in).
    // A wall crossing is a piece of a travel path outside the grown slice that has the path
    // inside at both of its ends: the nozzle leaves the object through its outer wall and comes
    // back through it within one travel, e.g. across the mouth of a C, or from one island of a
    // layer to another (the cat's legs): a strand can be dragged over the outside of the print
    // either way. A path that starts outside (from a prime line, the home position) or ends
    // outside (parking) is not a crossing.
    void check_travel(const Paths& grown) {
        double total = 0;
        for (const Path& p : layer_travel_) total += open_length_mm(Paths{p});
        if (layer_travel_.empty()) return;
        Clipper c;
        c.AddPaths(layer_travel_, ClipperLib::ptSubject, false);
        c.AddPaths(grown, ClipperLib::ptClip, true);
        ClipperLib::PolyTree tree;
        c.Execute(ClipperLib::ctDifference, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
        Paths out;
        ClipperLib::OpenPathsFromPolyTree(tree, out);
        layer_.travel_outside_mm = open_length_mm(out);
        layer_.travel_inside_mm = std::max(0.0, total - layer_.travel_outside_mm);
        // Ends of the paths: a piece ending at one did not come back in (or never was in).
        std::vector<Point> ends;
        for (const Path& p : layer_travel_) {
            ends.push_back(p.front());
            ends.push_back(p.back());
        }
        std::sort(ends.begin(), ends.end(), [](const Point& a, const Point& b) {
            return a.X != b.X ? a.X < b.X : a.Y < b.Y;
        });
        auto is_end = [&](const Point& q) {
            auto it = std::lower_bound(
                ends.begin(), ends.end(), Point(q.X - 1, q.Y - 1),
                [](const Point& a, const Point& b) { return a.X != b.X ? a.X < b.X : a.Y < b.Y; });
            for (; it != ends.end() && it->X <= q.X + 1; ++it)
                if (std::llabs(it->Y - q.Y) <= 1) return true;
            return false;
        };
        for (const Path& piece : out) {
            if (piece.size() < 2 || open_length_mm(Paths{piece}) < 0.01) continue;
            if (!is_end(piece.front()) && !is_end(piece.back())) ++layer_.wall_crossings;
        }
    }

    const GcodeAnalysisOptions& opt_;
    bool scan_only_ = false;
    GcodeAnalysis result_;
    double filament_area_ = 0;
    Coord r_units_ = 0, far_units_ = 0;

    // Machine state, in machine coordinates (G92 shifts the logical frame by offset_).
    double x_ = 0, y_ = 0, z_ = 0, e_register_ = 0;
    double offset_[3] = {0, 0, 0};
    bool rel_xyz_ = false, rel_e_ = false;
    double unit_ = 1.0;
    bool drawing_ = false;  // the last move extruded and ended where the next one starts

    // The layer being read.
    bool have_layer_ = false, on_bed_ = false;
    double layer_z_ = 0;
    LayerFigures layer_;
    std::vector<Polyline> lines_;

    // The layer below.
    bool have_prev_ = false;
    double prev_z_ = 0, prev_height_ = 0, first_z_ = 0;
    Paths prev_footprint_;

    double width_sum_ = 0, width_weight_ = 0, tolerance_sum_ = 0;

    // Model slice of the layer below (for the inside / overhang split).
    bool have_prev_model_ = false;
    Paths prev_model_;

    double feed_mm_s_ = 50;  // until the file sets F
    std::string type_;       // the last ;TYPE: comment

    // Moves since the last extrusion, waiting for the layer that the next extrusion opens.
    struct Pending {
        long long retractions = 0;
        double travel_length_mm = 0, stick_time_s = 0;
        Paths travel;
    };
    Pending pending_;
    Path travel_;  // the travel path being drawn, from the last extrusion's end
    Paths layer_travel_;

    ExtrusionBounds above_first_, all_layers_;
};

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

// PrusaSlicer prints its configuration at the end of the file and Cura (Griffin) at the start,
// so the filament diameter is looked for in both ends before the single pass.
bool header_filament_diameter(std::FILE* f, double& diameter) {
    auto read_at = [&](long offset, size_t size) {
        std::string text(size, '\0');
        std::fseek(f, offset, SEEK_SET);
        text.resize(std::fread(text.data(), 1, size, f));
        return text;
    };
    std::fseek(f, 0, SEEK_END);
    long size = std::ftell(f);
    constexpr long kHead = 64 * 1024, kTail = 512 * 1024;
    std::string head = read_at(0, static_cast<size_t>(std::min(size, kHead)));
    std::string tail = size > kHead
                           ? read_at(std::max(kHead, size - kTail),
                                     static_cast<size_t>(size - std::max(kHead, size - kTail)))
                           : std::string();
    std::fseek(f, 0, SEEK_SET);
    for (const std::string* text : {&head, &tail}) {
        if (find_header_value(*text, "filament_diameter =", diameter) ||
            find_header_value(*text, "EXTRUDER_TRAIN.0.MATERIAL.DIAMETER:", diameter))
            if (diameter > 0) return true;
    }
    return false;
}

}  // namespace

double parse_duration_s(std::string_view text) {
    double total = 0;
    bool any = false;
    size_t i = 0;
    while (i < text.size()) {
        if (!(std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '.')) {
            ++i;
            continue;
        }
        double v = 0;
        size_t used = 0;
        if (!parse_number(text.substr(i), v, &used)) {
            ++i;
            continue;
        }
        i += used;
        while (i < text.size() && text[i] == ' ') ++i;
        char unit = i < text.size() ? text[i] : 's';
        double scale = unit == 'd' ? 86400 : unit == 'h' ? 3600 : unit == 'm' ? 60 : 1;
        total += v * scale;
        any = true;
        if (i < text.size()) ++i;
    }
    return any ? total : -1;
}

namespace {

// Opens the file and settles the filament diameter (header or option).
std::unique_ptr<std::FILE, FileCloser> open_gcode(const std::string& path,
                                                  const GcodeAnalysisOptions& options,
                                                  double& diameter, std::string& source) {
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file) throw InputError("cannot open G-code file '" + path + "'");
    diameter = options.filament_diameter_mm;
    source = "option";
    if (options.filament_diameter_from_header) {
        double from_header = 0;
        if (header_filament_diameter(file.get(), from_header)) {
            diameter = from_header;
            source = "header";
        }
    }
    if (!(diameter > 0)) throw InputError("filament diameter must be positive");
    return file;
}

void feed_lines(std::FILE* file, const std::string& path, Analyser& analyser) {
    std::vector<char> buffer(1 << 20);
    std::string carry;
    size_t n;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), file)) > 0) {
        std::string_view chunk(buffer.data(), n);
        size_t start = 0;
        size_t nl;
        while ((nl = chunk.find('\n', start)) != std::string_view::npos) {
            if (!carry.empty()) {
                carry.append(chunk.substr(start, nl - start));
                analyser.line(carry);
                carry.clear();
            } else {
                analyser.line(chunk.substr(start, nl - start));
            }
            start = nl + 1;
        }
        carry.append(chunk.substr(start));
    }
    if (!carry.empty()) analyser.line(carry);
    if (std::ferror(file)) throw InputError("cannot read G-code file '" + path + "'");
}

}  // namespace

GcodeAnalysis analyse_gcode(const std::string& path, const GcodeAnalysisOptions& options) {
    double diameter = 0;
    std::string source;
    auto file = open_gcode(path, options, diameter, source);
    Analyser analyser(options, diameter);
    feed_lines(file.get(), path, analyser);
    GcodeAnalysis result = analyser.finish();
    result.filament_diameter_source = source;
    result.bead_model = options.bead == BeadModel::kRounded ? "rounded" : "rectangle";
    return result;
}

ExtrusionBounds extrusion_bounds(const std::string& path, const GcodeAnalysisOptions& options) {
    double diameter = 0;
    std::string source;
    auto file = open_gcode(path, options, diameter, source);
    GcodeAnalysisOptions scan = options;
    scan.model_slice = nullptr;
    Analyser analyser(scan, diameter, true);
    feed_lines(file.get(), path, analyser);
    analyser.finish();
    return analyser.bounds();
}

nlohmann::json to_json(const GcodeAnalysis& a, bool with_layers) {
    nlohmann::json j = {
        {"generator", a.generator},
        {"layers", a.layers},
        {"first_z_mm", a.first_z_mm},
        {"last_z_mm", a.last_z_mm},
        {"filament_diameter_mm", a.filament_diameter_mm},
        {"filament_diameter_source", a.filament_diameter_source},
        {"filament_length_mm", a.filament_length_mm},
        {"extruded_volume_mm3", a.extruded_volume_mm3},
        {"path_length_mm", a.path_length_mm},
        {"travel_length_mm", a.travel_length_mm},
        {"mean_line_width_mm", a.mean_line_width_mm},
        {"bead_model", a.bead_model},
        {"footprint_area_mm2", a.footprint_area_mm2},
        {"unsupported_area_mm2", a.unsupported_area_mm2},
        {"far_unsupported_area_mm2", a.far_unsupported_area_mm2},
        {"unsupported_percent", 100 * a.unsupported_fraction},
        {"far_unsupported_percent", 100 * a.far_unsupported_fraction},
        {"estimated_time_from_header_s", a.estimated_time_from_header_s},
        {"filament_used_from_header_mm", a.filament_used_from_header_mm},
        {"moves", a.moves},
        {"extruding_moves", a.extruding_moves},
        {"retractions", a.retractions},
        {"firmware_retractions", a.firmware_retractions},
        {"stick_time_s", a.stick_time_s},
        {"arcs", a.arcs},
        {"z_reversals", a.z_reversals},
        {"model_checked", a.model_checked},
    };
    {
        double total = 0;
        for (const auto& [type, v] : a.volume_by_type_mm3) total += v;
        nlohmann::json types = nlohmann::json::object();
        for (const auto& [type, v] : a.volume_by_type_mm3)
            types[type] = {{"volume_mm3", v}, {"percent", total > 0 ? 100 * v / total : 0.0}};
        j["material_by_type"] = std::move(types);
    }
    if (a.model_checked) {
        j["outside_area_mm2"] = a.outside_area_mm2;
        j["max_outside_model_mm"] = a.max_outside_model_mm;
        j["hanging_inside_mm2"] = a.hanging_inside_mm2;
        j["hanging_overhang_mm2"] = a.hanging_overhang_mm2;
        j["travel_inside_mm"] = a.travel_inside_mm;
        j["travel_outside_mm"] = a.travel_outside_mm;
        j["wall_crossings"] = a.wall_crossings;
        j["model_tolerance_mm"] = a.model_tolerance_mm;
        if (!a.mesh_alignment.empty()) {
            j["mesh_alignment"] = a.mesh_alignment;
            j["mesh_offset_mm"] = {a.mesh_offset_mm[0], a.mesh_offset_mm[1], a.mesh_offset_mm[2]};
            if (a.mesh_extent_mismatch_mm >= 0)
                j["mesh_extent_mismatch_mm"] = a.mesh_extent_mismatch_mm;
        }
    }
    if (with_layers) {
        nlohmann::json layers = nlohmann::json::array();
        for (const LayerFigures& l : a.per_layer) {
            nlohmann::json lj = {{"z_mm", l.z_mm},
                                 {"height_mm", l.height_mm},
                                 {"extruded_volume_mm3", l.extruded_volume_mm3},
                                 {"path_length_mm", l.path_length_mm},
                                 {"footprint_area_mm2", l.footprint_area_mm2},
                                 {"unsupported_area_mm2", l.unsupported_area_mm2},
                                 {"far_unsupported_area_mm2", l.far_unsupported_area_mm2},
                                 {"retractions", l.retractions},
                                 {"travel_length_mm", l.travel_length_mm},
                                 {"stick_time_s", l.stick_time_s}};
            if (a.model_checked) {
                lj["outside_area_mm2"] = l.outside_area_mm2;
                lj["max_outside_model_mm"] = l.max_outside_model_mm;
                lj["hanging_inside_mm2"] = l.hanging_inside_mm2;
                lj["hanging_overhang_mm2"] = l.hanging_overhang_mm2;
                lj["travel_inside_mm"] = l.travel_inside_mm;
                lj["travel_outside_mm"] = l.travel_outside_mm;
                lj["wall_crossings"] = l.wall_crossings;
            }
            layers.push_back(std::move(lj));
        }
        j["per_layer"] = std::move(layers);
    }
    return j;
}

}  // namespace carve
