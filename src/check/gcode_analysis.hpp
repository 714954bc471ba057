// Independent G-code analyser: judges printability and material from the G-code alone.
//
// It knows nothing about how a file was made, so the same measure applies to carve's output and
// to PrusaSlicer's or CuraEngine's (see shared/BASELINES.md). Each layer's footprint is rebuilt
// from the extruding moves, each widened to the line width that its E, the layer height and the
// filament area imply (by default PrusaSlicer's bead model, a rectangle with semicircular sides:
// w = E * A_f / (L * h) + h * (1 - pi / 4), which reproduces BASELINES.md). Unsupported extrusion
// is the part of a layer's footprint that lies farther than r from the previous layer's
// footprint; "far" unsupported uses 2 mm, so that short bridges and covers over close walls do
// not count but sagging spans and floating strands do. One pass, two layers' footprints held.
#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

// Cross-section assumed when a move's E is turned into a line width.
enum class BeadModel {
    kRounded,    // (w - h) * h + pi * h^2 / 4: PrusaSlicer's flow model, its ;WIDTH: comments
    kRectangle,  // w * h: CuraEngine's flow model; lines come out h * (1 - pi / 4) narrower
};

struct GcodeAnalysisOptions {
    double support_radius_mm = 0.2;  // r: overhang a layer may take over the one below
    double far_radius_mm = 2.0;      // distance beyond which extrusion counts as far-unsupported
    // A support's top holds what lies over it across a gap: the footprint of support extrusion
    // (a ;TYPE: with "support" in it) of the layers down to this far below the layer under the
    // current one counts as below too. Without it an overhang printed over a support with the
    // usual one-layer gap would count as hanging.
    double support_gap_mm = 0.2;
    double filament_diameter_mm = 1.75;
    BeadModel bead = BeadModel::kRounded;
    // Use "; filament_diameter = " (PrusaSlicer) or ";EXTRUDER_TRAIN.0.MATERIAL.DIAMETER:" (Cura
    // Griffin) when the file has it; turn off when the user gave a diameter explicitly.
    bool filament_diameter_from_header = true;
    bool keep_layers = true;  // fill GcodeAnalysis::per_layer

    // Optional shape check: the model's region at height z (mm, G-code coordinates; the analyser
    // asks at the middle of each layer), in micrometre units. Extrusion farther than
    // model_tolerance_mm outside it is reported; a negative tolerance means half of the layer's
    // mean line width.
    std::function<Paths(double z_mm)> model_slice;
    // The model's top (mm, G-code coordinates), when known: the model's layers above the last
    // one printed count as uncovered whole.
    double model_top_mm = -1;
    double model_tolerance_mm = -1;

    // carve check --strength: called once per layer holding the object, with its z, thickness,
    // the footprint of the object's own lines and their volume (mm3). Left out: support, skirt,
    // brim, ;TYPE:s naming custom G-code, a wipe or prime tower or a purge, and extrusion
    // before the first ;TYPE: comment unless untyped_is_object (a file without any).
    std::function<void(double z_mm, double height_mm, const Paths& footprint, double volume_mm3)>
        object_layer;
    bool untyped_is_object = true;

    // The look-ahead-free print time (stick_time_s): every move is a trapezoid from rest to rest
    // at its F, so that one measuring stick applies to every slicer whatever its planner.
    double stick_print_accel = 1000;         // mm/s^2, moves that extrude
    double stick_travel_accel = 1500;        // mm/s^2, the others
    double stick_firmware_retract_s = 0.03;  // G10 or G11: 0.8 mm at 35 mm/s, carve's default
};

// Extent of the extrusion, to place a mesh under G-code that moved it (see extrusion_bounds).
struct ExtrusionBounds {
    bool any = false;
    double min_x = 0, min_y = 0, max_x = 0, max_y = 0;  // mm, machine coordinates
    // Where the model's bottom lies when layers of supports alone are printed under its first
    // layer (a raft): that layer's Z less its thickness; -1 when the model starts on the bed.
    double model_bottom_z = -1;
};

struct LayerFigures {
    double z_mm = 0;
    double height_mm = 0;            // z minus the previous layer's z (first layer: z)
    double extruded_volume_mm3 = 0;  // from the moves that draw this layer
    double path_length_mm = 0;       // length of the extruding moves
    double footprint_area_mm2 = 0;
    double unsupported_area_mm2 = 0;      // footprint minus previous footprint dilated by r
    double far_unsupported_area_mm2 = 0;  // footprint minus previous footprint dilated by 2 mm
    double outside_area_mm2 = 0;          // with a model: footprint outside the dilated model slice
    double outside_support_mm2 = 0;       // of it, support extrusion (the rest: outside_other)
    double max_outside_model_mm = 0;      // with a model: farthest footprint point from the slice
    // With a model: the far-unsupported area split by the model's slice one layer down.
    // Inside lies over it (the interior could have held it); overhang is the rest (the model's
    // own external overhang, which only supports fix).
    double hanging_inside_mm2 = 0;
    double hanging_overhang_mm2 = 0;
    double hanging_support_mm2 = 0;  // of the far-unsupported area, support extrusion's own
    long long retractions = 0;
    double travel_length_mm = 0;   // travels that end at this layer's extrusions (see Analyser)
    double travel_inside_mm = 0;   // with a model: within the slice grown by the tolerance
    double travel_outside_mm = 0;  // with a model: the rest
    long long wall_crossings = 0;  // with a model: travels leaving the slice and coming back
    double stick_time_s = 0;
    double longest_bridge_mm = 0;  // see GcodeAnalysis::longest_bridge_mm
    double uncovered_mm2 = 0;      // with a model: see UncoveredFigures
};

// Issue 35's printability figures (definitions in check/printability.hpp and docs/check.md).
struct ColumnFigures {
    long long thin_interior = 0;  // columns of thin interior pieces, any height
    long long over_5mm = 0, over_10mm = 0;
    // The tallest column: height (layers x layer height), its layers, the median narrow side of
    // its pieces, where it starts and ends.
    double tallest_mm = 0, tallest_width_mm = 0;
    int tallest_layers = 0;
    double tallest_z_from_mm = 0, tallest_z_to_mm = 0;  // bottom of its first layer, top of last
    double tallest_x_mm = 0, tallest_y_mm = 0;          // its lowest piece's centre
    double tallest_top_x_mm = 0, tallest_top_y_mm = 0;  // its highest piece's centre
};

struct SkinFigures {
    double region_mm2 = 0;  // summed over the layers
    double open_mm2 = 0;
    long long holes_1mm2 = 0;  // connected open pieces of at least 1 mm2
    double largest_hole_mm2 = 0, largest_hole_z_mm = 0;
    double open_percent() const { return region_mm2 > 0 ? 100 * open_mm2 / region_mm2 : 0; }
};

// Issue 47: the model's slice not covered by the print (definitions in check/uncovered.hpp).
struct UncoveredPiece {
    double area_mm2 = 0;
    int layer = -1;  // index among the G-code's layers (GcodeAnalysis::per_layer), -1: none
    double z_mm = 0, x_mm = 0, y_mm = 0;  // the layer's top, the piece's centroid
};

struct UncoveredFigures {
    double slice_mm2 = 0;      // the model's slices shrunk by 0.1 mm, summed over the layers
    double uncovered_mm2 = 0;  // of it, not printed and open to the model's surface
    double enclosed_mm2 = 0;   // not printed but enclosed by printed lines (the interior)
    double deep_mm2 = 0;       // open, but farther than 1 mm from where it meets the surface
    UncoveredPiece largest;
    // Pieces that hold a disk of diameter line_width_mm (the --strict rule).
    double line_width_mm = 0;
    std::string line_width_source;  // "nozzle" (1.125 x the header's nozzle) or "measured"
    long long wide_pieces = 0;
    int wide_layers = 0;
    double wide_mm2 = 0;
    UncoveredPiece largest_wide;
    int layers_above_print = 0;  // the model's layers above the G-code's last, uncovered whole
    double percent() const { return slice_mm2 > 0 ? 100 * uncovered_mm2 / slice_mm2 : 0; }
};

struct PrintabilityFigures {
    ColumnFigures columns;
    SkinFigures top, bottom;
    UncoveredFigures uncovered;
};

// The rules of `carve check --strict` (issue 35).
constexpr double kStrictColumnMm = 5;            // no thin interior column taller
constexpr double kStrictSkinOpenPercent = 0.25;  // top and bottom skin left open, at most
constexpr double kStrictHangingInsideMm2 = 1;    // far-unsupported over the model's slice
// Issue 47: no uncovered piece holds a disk one line wide (1.125 x the nozzle, 0.45 mm at 0.4).
constexpr double kStrictLineWidthPerNozzle = 1.125;

struct GcodeAnalysis {
    std::string generator;  // from the first comments, e.g. "PrusaSlicer 2.5.0", "Cura_SteamEngine"
    int layers = 0;
    double filament_diameter_mm = 0;
    std::string filament_diameter_source;  // "header" or "option"
    double nozzle_diameter_mm = 0;         // from the header, 0 when it does not say
    double filament_length_mm = 0;         // net E fed (retractions and their recovery cancel)
    double extruded_volume_mm3 = 0;        // filament_length_mm * filament area
    double path_length_mm = 0;             // length of the extruding moves
    double travel_length_mm = 0;           // XY length of the non-extruding moves
    double mean_line_width_mm = 0;         // by the bead model, weighted by length
    std::string bead_model;                // "rounded" or "rectangle"
    double footprint_area_mm2 = 0;         // sum over layers
    double unsupported_area_mm2 = 0;
    double far_unsupported_area_mm2 = 0;
    double unsupported_fraction = 0;  // of footprint_area_mm2
    double far_unsupported_fraction = 0;
    double first_z_mm = 0, last_z_mm = 0;
    // Figures the slicer wrote in its comments, -1 when absent. Cura's are placeholders when
    // CuraEngine runs alone (the real ones are in its -v log).
    double estimated_time_from_header_s = -1;
    double filament_used_from_header_mm = -1;
    long long moves = 0;
    long long extruding_moves = 0;
    long long retractions = 0;           // moves with negative E, and G10 firmware retractions
    long long firmware_retractions = 0;  // G10 of them
    double stick_time_s = 0;             // see GcodeAnalysisOptions::stick_*
    // Extruded volume (moves that draw) per ;TYPE: comment, as written by the slicer; "none"
    // before the first one.
    std::map<std::string, double> volume_by_type_mm3;
    long long arcs = 0;   // G2/G3, approximated by chords
    int z_reversals = 0;  // extrusion at a lower z than the layer before (sequential prints)
    bool model_checked = false;
    double outside_area_mm2 = 0;
    double outside_support_mm2 = 0;  // of it, support extrusion
    double max_outside_model_mm = 0;
    double hanging_inside_mm2 = 0;  // see LayerFigures
    double hanging_overhang_mm2 = 0;
    double hanging_support_mm2 = 0;
    double support_volume_mm3 = 0;  // extruded under a ;TYPE: naming support
    double support_gap_mm = 0;      // GcodeAnalysisOptions::support_gap_mm as used
    double travel_inside_mm = 0;
    double travel_outside_mm = 0;
    long long wall_crossings = 0;
    double model_tolerance_mm = 0;  // mean over layers of the tolerance used
    // The longest bridge line (see check/printability.hpp): the longest stretch of one
    // extruding move over nothing printed on the layer below within the support radius, held
    // at both ends.
    double longest_bridge_mm = 0, longest_bridge_z_mm = 0;
    double longest_bridge_x_mm = 0, longest_bridge_y_mm = 0;  // its middle
    PrintabilityFigures printability;                         // with a model
    // How the model was placed under the G-code, when the caller says (carve check --mesh).
    std::string mesh_alignment;
    double mesh_offset_mm[3] = {0, 0, 0};
    // Automatic placement: how much the extrusion's extent (x or y, the larger) differs from the
    // mesh's; more than a few millimetres means the mesh is not at the print's scale. -1: unknown.
    double mesh_extent_mismatch_mm = -1;
    std::vector<LayerFigures> per_layer;
};

// Reads the file once; throws carve::InputError if it cannot be opened.
GcodeAnalysis analyse_gcode(const std::string& path, const GcodeAnalysisOptions& options = {});

// One cheap pass (no footprints) that finds the extent of the extruding moves above the first
// layer: the first layer is left out because prime lines, skirts and purge lines live there.
// Falls back to every layer when there is only one.
ExtrusionBounds extrusion_bounds(const std::string& path, const GcodeAnalysisOptions& options = {});

nlohmann::json to_json(const GcodeAnalysis& analysis, bool with_layers = false);

// The --strict rules the analysis fails, each said in one line; empty when it passes or has no
// model to judge by.
std::vector<std::string> failed_rules(const GcodeAnalysis& analysis);
// Issue 35's figures for people: columns, skins, bridge, hanging, the verdict.
std::string describe_printability(const GcodeAnalysis& analysis);

// "1d 2h 3m 4s", "2h 3m", "45s" (PrusaSlicer's estimate) -> seconds; -1 if nothing parses.
double parse_duration_s(std::string_view text);

}  // namespace carve
