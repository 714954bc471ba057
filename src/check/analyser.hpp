// The G-code analyser of carve check, shared by its two halves: gcode_analysis.cpp interprets
// the file (machine state, moves and arcs, travel, the polylines of the layer being read) and
// layer_analysis.cpp measures each layer once it is read (its footprint against the layers
// below and the model's slice, summed into the result). Internal to src/check.
#pragma once

#include <deque>
#include <string>
#include <string_view>
#include <vector>

#include "check/footprint.hpp"
#include "check/gcode_analysis.hpp"
#include "check/printability.hpp"
#include "check/uncovered.hpp"

namespace carve::check {

constexpr double kZTolerance = 1e-4;  // mm: same layer

// The words of one G-code line after its command, by letter.
struct Words {
    bool has[26] = {};
    double v[26] = {};
    bool any(char c) const { return has[c - 'A']; }
    double get(char c) const { return v[c - 'A']; }
};

class Analyser {
  public:
    // scan_only: parse and track the extent of the extrusion, build no footprint.
    Analyser(const GcodeAnalysisOptions& o, double filament_diameter, bool scan_only = false);

    void line(std::string_view s);
    GcodeAnalysis finish();

    // The nozzle's diameter the header names (mm; 0: it does not), for the uncovered check.
    void set_nozzle(double mm) { result_.nozzle_diameter_mm = mm; }

    ExtrusionBounds bounds() const {
        ExtrusionBounds b = above_first_.any ? above_first_ : all_layers_;
        b.model_bottom_z = model_bottom_z_;
        return b;
    }

  private:
    // Reading the file (gcode_analysis.cpp).
    void comment(std::string_view c);
    void g_code(int code, const Words& w);
    double target(const Words& w, char axis, double current) const;
    double e_delta(const Words& w);
    void feed(const Words& w);
    void stick_move(double length, double de, bool extrudes);
    void add_time(double seconds);
    void count_retraction(double de);
    void move(const Words& w);
    void arc(const Words& w, bool clockwise);
    void segment(double nx, double ny, double nz, double de);
    void end_travel();
    void take_pending();
    void extrude(double nx, double ny, double nz, double de, double length);

    // Measuring a layer once it is read (layer_analysis.cpp).
    void start_layer(double z);
    void finish_layer();
    // finish_layer()'s phases, in order.
    const Paths& below_layer(double reach_z, Paths& merged);
    void measure_hanging(const Paths& footprint, const Paths& support_footprint, const Paths& below,
                         double reach_z);
    void add_layer_sums();
    void keep_as_below(Paths footprint, Paths support_footprint, double h);
    void check_model(const Paths& footprint, const Paths& support_footprint, double h);
    double disk_width_mm() const;
    void model_above_print();
    void report_object(const Paths& footprint, double h);
    // The lines being drawn are the object's (GcodeAnalysisOptions::object_layer).
    bool object_type() const { return type_.empty() ? opt_.untyped_is_object : !other_type_; }

    static constexpr long long kMaxArcSegments = 10'000'000;
    // What no printer's file comes near, refused before it reaches the footprints, whose work
    // and memory grow with the numbers in the file (a move to z = -1e9 made a layer a billion
    // millimetres thick, its lines as wide, and took gigabytes): coordinates within 1 km (the
    // mesh loader's bound), one move's filament within 1 km, layers and the points of one layer
    // as many as `carve slice` would write.
    static constexpr double kMaxCoordinateMm = 1e6;
    static constexpr long long kMaxLayers = 1'000'000;
    static constexpr long long kMaxLayerPoints = 5'000'000;
    void refuse_move(double x, double y, double z, double de) const;
    long long line_no_ = 0;
    long long layer_points_ = 0;

    const GcodeAnalysisOptions& opt_;
    bool scan_only_ = false;
    GcodeAnalysis result_;
    double filament_area_ = 0;
    long long arc_segments_ = 0;
    Coord r_units_ = 0, far_units_ = 0;

    // Machine state, in machine coordinates (G92 shifts the logical frame by offset_).
    double x_ = 0, y_ = 0, z_ = 0, e_register_ = 0;
    double offset_[3] = {0, 0, 0};
    bool rel_xyz_ = false, rel_e_ = false;
    double unit_ = 1.0;
    bool drawing_ = false;  // the last move extruded and ended where the next one starts

    // The layer being read.
    bool have_layer_ = false, on_bed_ = false;
    bool mid_air_ = false;  // farther above what is below than a layer is thick
    double layer_z_ = 0;
    LayerFigures layer_;
    std::vector<Polyline> lines_;

    // The layer below.
    bool have_prev_ = false;
    double prev_z_ = 0, prev_height_ = 0, first_z_ = 0;
    Paths prev_footprint_;
    // The last layers, bottom up: their z, footprint (empty for the last one, which is
    // prev_footprint_) and support footprint, for layers interleaved thinner than this one and for
    // support_gap_mm.
    struct Recent {
        double z = 0;
        Paths footprint, support;
    };
    std::deque<Recent> recent_;

    double width_sum_ = 0, width_weight_ = 0, tolerance_sum_ = 0;

    // Model slice of the layer below (for the inside / overhang split).
    bool have_prev_model_ = false;
    Paths prev_model_;
    PrintabilityMeter printability_;
    UncoveredMeter uncovered_;

    double feed_mm_s_ = 50;      // until the file sets F
    std::string type_;           // the last ;TYPE: comment
    bool support_type_ = false;  // it names support
    bool skirt_type_ = false;    // it names a skirt or brim (PrusaSlicer's "Skirt/Brim")
    bool other_type_ = false;    // custom G-code, a wipe or prime tower, a purge: not the object
    double line_height_ = 0;     // the last ;HEIGHT: comment (PrusaSlicer), 0 = none
    bool have_model_z_ = false;  // a layer with more than support was read
    double model_z_ = 0;         // the last one's z

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
    bool model_seen_ = false;     // an extrusion that is neither support nor skirt
    double model_bottom_z_ = -1;  // ExtrusionBounds::model_bottom_z
};

}  // namespace carve::check
