// Every parameter of a run, in millimetres, degrees and seconds as the user gives them.
// Stages convert to micrometres where they need integers. Defaults follow DESIGN.md.
#pragma once

#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

enum class WallMode { Single, Double };
enum class GcodeFlavor { Marlin, RepRap, Klipper };
// Travel (issue #18). Combing: off = straight travels, retracted when longer than
// retract_min_travel; inside = within the island but not over its covers (solid top and bottom
// layers, where a dragged nozzle marks the surface); all = anywhere within the island.
enum class Combing { Off, Inside, All };
// Where the outer wall's loops start: aligned = the same place layer after layer, in a concave
// corner where there is one (a convex one otherwise); nearest = where the nozzle is; rear = the
// back of the loop; random = anywhere (spreads the seam's bump).
enum class SeamMode { Aligned, Nearest, Rear, Random };
// Supports for the model's own overhangs (issue #20): none; auto = down to the bed or onto the
// model's top; buildplate = only where nothing of the model lies below, down to the bed.
enum class SupportMode { None, Auto, Buildplate };
// What joins the pieces of a --cut: nothing, dowel holes in both faces, or a pin on the piece
// below and a hole in the one above.
enum class CutConnectors { None, Dowel, Pin };
// How the interior is carved (issue #37).
// whole: carve's own scheme, the default. Each part of the volume to carve is one cavity, taken
//   whole from the slice where it appears; its ceilings are covers bridged from wall to wall and
//   held from below by ribs. Its options: --whole-width, --whole-width-max.
// report: Hornus & Lefebvre's method (RR-9083): ITERATIVECARVING seeded by the pruned medial
//   axis (SKEL), k nested cavities with single- or double-filament walls printed in cavity order
//   (4.2), local minima bridged (4.4). Its options: --tear-limit, --wall-extension.
// Both: --cavities, --walls, the bridge and rib options.
enum class CarvingScheme { Whole, Report };
// How the model lies on the bed (issue #48): given = as loaded; auto = of the axis-aligned turns
// and the convex hull's largest faces laid down, the one that carves with the least material.
enum class OrientMode { Given, Auto };

struct Settings {
    // Geometry of the process.
    double layer_height = 0.2;  // h
    double nozzle = 0.4;        // w = 2s, also the extrusion width
    // mm; the line width w when set (a profile's extrusion_width), else the nozzle diameter.
    double extrusion_width = 0;
    double max_overhang = 45.0;  // degrees; r = h * tan(max_overhang)
    // degrees from vertical; a slice sticking out further than h * tan(angle) beyond the one
    // below is the model's own overhang (0: max_overhang, what the cavities are carved with)
    double support_angle = 0.0;
    SupportMode support = SupportMode::None;
    // mm between the support's top and the overhang it holds (PrusaSlicer's contact distance),
    // rounded to whole layers; and between the support and the model's side (PrusaSlicer's
    // support_material_xy_spacing, 50 % of its 0.45 mm external perimeter for a 0.4 nozzle).
    double support_z_gap = 0.2;
    double support_xy_gap = 0.25;
    int support_interface_layers = 2;  // dense layers at the top of every support
    CarvingScheme carving = CarvingScheme::Whole;
    int cavities = 6;            // k; 0 = plain hollow shell
    bool cavities_auto = false;  // stop when V^j erodes away at radius w
    int covers = 2;
    int shells = 0;
    // 0 to 1, from carve's default to --preset strong: more shells and the report's nested
    // walls (config/presets.hpp), applied once every option is in.
    double strength = 0;
    // Ties (issue 49): a square grid of single-filament walls at +-45 degrees, this far apart
    // (mm), across the carvable interior on every layer, at the same place on each so that
    // they stack into vertical webs from wall to wall. 0 = none.
    double tie_spacing = 0;
    // The interior (inside the shells) narrower than this (mm) is printed solid rather than
    // carved (issue 49): a thin section in series with the rest decides the part's stiffness
    // and hollowing it saves little. 0 = every part carved.
    double solid_below = 0;
    // An island of a slice (a connected part, holes and all) smaller in area than this (mm2)
    // is printed solid (issue 49), as PrusaSlicer's solid_infill_below_area (70 in its
    // profiles) does: the thin top of a statue is where it bends and gives first. 0 = none.
    double solid_below_area = 0;
    WallMode walls = WallMode::Single;
    double restriction_factor = 1.4;  // t = 1.4 s
    double opening_factor = 0.9;      // s' = 0.9 s
    // mm, open single-filament walls extended along the walls printed before them (report 4.3,
    // --carving report only). The report's 1 mm: the open end of a new wall, on a 45-degree
    // slope with nothing beside it, sticks to the wall printed before it. An open wall already
    // ends with its centre t (< w) from the earlier wall, so the beads overlap without it; 0
    // saved cat 918 -> 811 mm3 of cavity walls, elephant 2,342 -> 2,138 (at 4 mm whole width).
    double wall_extension = 1.0;
    double bridge_angle_step = 5.0;  // degrees
    bool prune_bridges = true;
    double scale = 1.0;  // uniform scale applied to the model about its centre
    OrientMode orient = OrientMode::Given;
    // Copies of the model printed side by side as separate objects (a print farm's plate), and
    // the gap between them, mm (PrusaSlicer's default object distance).
    int copies = 1;
    double copy_gap = 6.0;
    int threads = 0;  // worker threads, 1 = all on the calling thread; 0 = every core
    // mm; the seed may tear a cavity open at most this far beyond the dilated cavity per slice
    // (the report's conclusion proposes r/2; --carving report only). 0: the whole pruned medial
    // axis opens in one slice, as in the report's algorithm. Smaller is better supported and
    // costs material.
    double tear_limit = 0.0;
    // mm (--carving whole only); a component of V^{j-1} that holds no disk this wide is carved
    // whole in one slice and its ceiling bridged (0 would tear every component along its medial
    // axis: that is --carving report, and refused here). A
    // component up to whole_width_max wide is carved whole too when the part of it under the
    // model's surface in the slice above holds no disk this wide. Before ribs it was 4 mm (and
    // 14 mm for that maximum): `carve check` counts the middle of a span more than 2 mm from its
    // anchors as hanging, and a flat 60 x 60 x 12 mm box hung 72 mm2 at 10 mm. With ribs under
    // whatever would hang (supports/ribs.hpp) no width hangs any more, so every part is carved
    // whole (1000 mm). Material at 4 / 1000 mm, both with ribs: fandisk 9.03 / 8.21 %, skull
    // 5.05 / 3.99, cat 7.69 / 7.15, elephant 7.01 / 6.37, skull x1.43 3.66 / 2.80, the flat
    // box 16.7 / 12.45, the bladed plate 24.8 / 20.4; hanging inside under 0.7 mm2 on each.
    // The print time fell on the models but rose on the flat shapes, whose one cavity takes
    // thousands of short rib lines (docs/measurements.md). Fandisk x2.5: 3.82 / 3.34 %, rib
    // material 1,099 / 1,011 mm3: a part carved whole still grows by at most r a slice
    // downwards, so its ceilings are no wider than the nested cavities' were.
    double whole_width = 1000.0;
    // mm; how wide that component may be (14 before ribs, see above).
    double whole_width_max = 1000.0;
    double max_bridge_length = 10.0;  // mm; a longer span would sag more than the minimum it holds
    // mm; what the slice above prints deeper than this inside a cavity gets a rib under it
    // (supports/ribs.hpp): `carve check` counts extrusion more than 2 mm from the layer below as
    // hanging. 0: no ribs.
    double rib_reach = 1.6;
    // mm; the lattice ribs are seeded on. 2.6 rather than 2: a point it must hold is then within
    // 1.84 mm of a rib; rib material fandisk 216 -> 174 mm3, skull 132 -> 106, nothing more
    // hanging (3.0: fandisk hangs 1.3 mm2).
    double rib_spacing = 2.6;
    double rib_piece = 0.8;  // mm; the line a rib prints on each layer (2 line widths at least)
    // mm; a part of what would hang that holds a disk this wide gets vault lines instead of ribs
    // where they print less (supports/vaults.hpp): parallel walls wall to wall, merging in pairs
    // going down. 0: ribs alone. At the rib lattice's spacing the narrow strips of a ceiling cut
    // up by what stands on it get them too (bladed plate 23.0 -> 22.4 % at 5.2 mm).
    double vault_width = 2.6;
    // Resource guard: a slice with more contour vertices stops the run (0 = no limit). Millions
    // of vertices per layer would make carving run for hours.
    long long max_vertices_per_layer = 5'000'000;
    // The same over the whole model (every slice's contour vertices added up): a model whose
    // slices stay under the per-layer limit can still be hours of work in all.
    long long max_vertices_total = 100'000'000;

    // The first layer and the flow, PrusaSlicer's meanings and keys (issue #36).
    double first_layer_height = 0;           // mm; 0 = the layer height
    double first_layer_extrusion_width = 0;  // mm; 0 = the line width
    double extrusion_multiplier = 1.0;       // every extrusion's flow (E) is scaled by it
    // mm^3/s every extrusion's width x height x speed is held to (PrusaSlicer's
    // max_volumetric_speed, or its filament's, the lower); 0 = none.
    double max_volumetric_speed = 0;
    double elephant_foot_compensation = 0;  // mm the first layer's slice is shrunk by
    double xy_size_compensation = 0;        // mm every slice grows (shrinks if negative) by
    double z_offset = 0;                    // mm added to every Z written

    // Thin walls (issue #47), PrusaSlicer's Arachne keys: a part of a slice narrower than two
    // lines prints as one line along its medial axis, as wide as the part, at least
    // min_bead_width; a part narrower than min_feature_size is not printed (and reported).
    int thin_walls = 1;
    double min_bead_width = 0;    // mm; 0 = 85 % of the nozzle, PrusaSlicer's default
    double min_feature_size = 0;  // mm; 0 = 25 % of the nozzle, PrusaSlicer's default

    // Skirt, brim and raft (PrusaSlicer's names and defaults).
    int skirts = 1;             // loops around the whole print on its first layers
    double skirt_distance = 6;  // mm from the print (its brim included)
    int skirt_height = 1;       // layers
    double brim_width = 0;      // mm of outer brim around each part on the first layer
    // mm between the part and its brim: PrusaSlicer's brim_separation, 0.1 as its own printer
    // profiles set it, so that the brim breaks off cleanly.
    double brim_separation = 0.1;
    // Layers of raft under the model (toolpath/raft.hpp): the raft's first layer is the print's
    // first layer (first_layer_height, first-layer width, speed and temperatures), the model's
    // first layer a normal layer raft_contact_distance above the raft's top. 0 = none.
    int raft_layers = 0;
    double raft_contact_distance = 0.1;       // mm of air between the raft's top and the model
    double raft_expansion = 1.5;              // mm the raft reaches beyond the model's first layer
    double raft_first_layer_expansion = 3.0;  // mm the raft's first layer reaches beyond that
    // Heights (mm of the model) before whose first layer at or above the print pauses (M600 on
    // Marlin, PAUSE on Klipper).
    std::vector<double> pause_at;
    // The command a pause writes, between its park and its return: "" = the flavour's (M600 on
    // Marlin and RepRap, PAUSE on Klipper, which needs [pause_resume] and a PAUSE macro).
    std::string pause_command;
    // --cut (issue #48): planes across z, mm above the model's bottom, or chosen (cut_auto);
    // the pieces print on plates of their own, joined by the connectors in their cut faces.
    std::vector<double> cut_at;
    bool cut_auto = false;
    // --cut-plane: planes in any direction, 6 numbers each (a point and a normal, mm of the
    // model's frame as loaded and placed).
    std::vector<double> cut_planes;
    CutConnectors cut_connectors = CutConnectors::Dowel;
    double dowel_diameter = 5, dowel_depth = 6;  // mm, of the dowel or pin and of each hole
    double connector_clearance = 0.15;           // mm added to a hole's radius
    bool cutting() const { return cut_auto || !cut_at.empty() || !cut_planes.empty(); }

    // Printer and filament.
    GcodeFlavor flavor = GcodeFlavor::Marlin;
    std::string printer_name = "generic";
    // What hosts show of the filament and printer (the configuration block's keys).
    std::string filament_type = "PLA", filament_settings_id, filament_colour = "#FF8000";
    std::string printer_model;
    double filament_diameter = 1.75;
    double filament_density = 1.24;   // g/cm^3 (PLA)
    double bed_x = 250, bed_y = 210;  // bed size; the model is centred on it
    // The highest a nozzle can print, mm (PrusaSlicer's max_print_height); checked with the
    // bed (bed_check), since a taller model is printed into the gantry.
    double max_print_height = 210;
    bool bed_check = true;
    bool relative_e = false;
    int nozzle_temperature = 210, first_layer_nozzle_temperature = 215;
    int bed_temperature = 60, first_layer_bed_temperature = 60;
    double perimeter_speed = 40, cavity_speed = 60, cover_speed = 50, bridge_speed = 25;
    double travel_speed = 150, first_layer_speed = 20, max_print_speed = 100;
    double acceleration = 1000, travel_acceleration = 1500;  // mm/s^2
    double retract_length = 0.8, retract_speed = 35, retract_min_travel = 2.0, z_hop = 0.0;
    Combing combing = Combing::All;
    bool avoid_crossing_perimeters = true;  // a travel leaving its island goes through it
    SeamMode seam = SeamMode::Aligned;
    bool wipe = false;                 // move back along the last path while retracting
    double wipe_distance = 1.0;        // mm
    bool arc_fitting = false;          // G2/G3 where a path follows a circle (gcode/arcs.hpp)
    double arc_tolerance = 0.02;       // mm the arcs may leave the path by
    bool firmware_retraction = false;  // G10/G11: the firmware's own length and speed
    double bridge_flow = 1.0;

    // Machine limits as PrusaSlicer names them (machine_max_*): written to the G-code as
    // M201/M203/M204/M205 and the very values the time estimate plans with. The defaults do not
    // bind below carve's default speeds and accelerations (print and travel accelerations above
    // are M204's P and T).
    double max_acceleration_x = 3000, max_acceleration_y = 3000;  // mm/s^2
    double max_acceleration_z = 200, max_acceleration_e = 5000;
    double retract_acceleration = 1500;                 // M204 R
    double max_feedrate_x = 500, max_feedrate_y = 500;  // mm/s
    double max_feedrate_z = 12, max_feedrate_e = 120;
    double max_jerk_x = 8, max_jerk_y = 8, max_jerk_z = 0.4, max_jerk_e = 4.5;  // mm/s
    // Marlin 2's cornering (M205 J); 0 = classic jerk (Prusa firmware, PrusaSlicer's viewer).
    double junction_deviation = 0.013;

    // Cooling, as PrusaSlicer does it (fan speeds in percent). A layer printed faster than
    // slowdown_below_layer_time has its extrusions slowed down to last that long, but not below
    // min_print_speed; the fan runs at min_fan_speed (fan_always_on) and rises to max_fan_speed
    // as the layer time falls from fan_below_layer_time to slowdown_below_layer_time.
    int cooling = 1;
    int fan_always_on = 1;
    int min_fan_speed = 100, max_fan_speed = 100, bridge_fan_speed = 100;  // percent
    double fan_below_layer_time = 60, slowdown_below_layer_time = 5;       // s
    double min_print_speed = 10;                                           // mm/s
    int disable_fan_first_layers = 1;

    // Host and printer conveniences.
    int m73 = 0;          // M73 P<percent> R<minutes> progress (PrusaSlicer's remaining_times)
    int silent_mode = 0;  // the printer has a stealth mode: M73 Q/S too (PrusaSlicer's key)
    // That mode's X/Y limits (the second values of a profile's machine_max_acceleration_x/y and
    // machine_max_feedrate_x/y, PrusaSlicer's "normal,stealth"); 0 = the normal limits.
    double stealth_max_acceleration = 0, stealth_max_feedrate = 0;  // mm/s^2, mm/s
    std::vector<std::pair<int, int>> thumbnails;  // sizes of the PNG previews, WxH
    std::string start_gcode = "G28 ; home all axes\nG1 Z5 F3000\nG92 E0\n";
    // The end lifts 10 mm clear of the part (within the printer's height, the offset
    // included: z_offset outside the min() wrote Z 215 on a 210 mm printer with --z-offset 10,
    // issue #52) and moves the head aside (G28 X0).
    std::string end_gcode =
        "M104 S0\nM140 S0\nM107\n{if max_layer_z < max_print_height}G1 "
        "Z{min(z_offset+max_layer_z+10, max_print_height)} F600 ; lift clear of the "
        "part{endif}\nG28 X0\nM84\n";
    // A profile's filament G-code (after the start G-code, before the end G-code) and layer-change
    // G-code (before and after ;LAYER_CHANGE, with [layer_num] and [layer_z]); empty = none.
    std::string start_filament_gcode, end_filament_gcode, before_layer_gcode, layer_gcode;
    // Raw values of the loaded profile's other keys (printer_model, max_print_height, ...): the
    // placeholders of its custom G-code may name them (gcode/placeholders.hpp).
    std::map<std::string, std::string> profile_values;

    // Derived quantities, in micrometres.
    double width_mm() const { return extrusion_width > 0 ? extrusion_width : nozzle; }
    // Layers are numbered as the model's: 0 is the model's first layer, and a raft's layers are
    // -raft_layers .. -1 below it. The print's first layer is first_print_layer(): it alone has
    // the first layer's height and width.
    int first_print_layer() const { return -raft_layers; }
    // The print's first layer thickness.
    double first_layer_mm() const {
        return first_layer_height > 0 ? first_layer_height : layer_height;
    }
    // The thickness of the model's layer i as sliced: its first layer's is the first layer's,
    // or the layer height on a raft.
    double model_layer_mm(int i) const {
        return i == 0 && raft_layers == 0 ? first_layer_mm() : layer_height;
    }
    // What layer i is printed as: the nozzle's height above what lies under it, which its
    // flow fills. The model's first layer on a raft fills the gap above the raft too.
    double layer_thickness_mm(int i) const {
        if (i == first_print_layer()) return first_layer_mm();
        return i == 0 && raft_layers > 0 ? layer_height + raft_contact_distance : layer_height;
    }
    // The raft's top above the bed, and where the model's first layer starts (0 without a raft).
    double raft_top_mm() const {
        return raft_layers > 0 ? first_layer_mm() + (raft_layers - 1) * layer_height : 0.0;
    }
    double model_base_mm() const {
        return raft_layers > 0 ? raft_top_mm() + raft_contact_distance : 0.0;
    }
    // The top of layer i above the bed (the nozzle's height, before z_offset); (i + 1) h as it
    // always was when the first layer is the layer height and there is no raft.
    double layer_top_mm(int i) const {
        if (raft_layers > 0)
            return i < 0 ? first_layer_mm() + (i + raft_layers) * layer_height
                         : model_base_mm() + (i + 1) * layer_height;
        return first_layer_height > 0 ? first_layer_height + i * layer_height
                                      : (i + 1) * layer_height;
    }
    // The middle of the model's layer i above the model's bottom, where the slicer cuts it:
    // (i + 0.5) h to the bit when its first layer is the layer height (their difference is then
    // exactly 0).
    double layer_middle_mm(int i) const {
        const double first = model_layer_mm(0);
        return i == 0 ? first / 2 : (first - layer_height) + (i + 0.5) * layer_height;
    }
    // The line width on layer i.
    double layer_width_mm(int i) const {
        return i == first_print_layer() && first_layer_extrusion_width > 0
                   ? first_layer_extrusion_width
                   : width_mm();
    }
    double min_bead_mm() const { return min_bead_width > 0 ? min_bead_width : 0.85 * nozzle; }
    double min_feature_mm() const {
        return min_feature_size > 0 ? min_feature_size : 0.25 * nozzle;
    }
    Coord nozzle_radius() const { return to_units(width_mm() / 2); }  // s
    Coord line_width() const { return to_units(width_mm()); }         // w
    Coord dilation_per_layer() const {                                // r
        return to_units(layer_height * std::tan(max_overhang * std::numbers::pi / 180.0));
    }
    Coord support_reach() const {
        const double angle = support_angle > 0 ? support_angle : max_overhang;
        return to_units(layer_height * std::tan(angle * std::numbers::pi / 180.0));
    }
    // Whole layers between a support's top and the overhang above it.
    int support_gap_layers() const {
        return static_cast<int>(std::lround(support_z_gap / layer_height));
    }
    bool report_scheme() const { return carving == CarvingScheme::Report; }
    // What the stages use: each option counts only under its scheme (validate_settings()
    // refuses one set under the other).
    double tear_limit_mm() const { return report_scheme() ? tear_limit : 0.0; }
    double wall_extension_mm() const { return report_scheme() ? wall_extension : 0.0; }
    double whole_width_mm() const { return report_scheme() ? 0.0 : whole_width; }
    double whole_width_max_mm() const { return report_scheme() ? 0.0 : whole_width_max; }
    Coord restriction() const { return to_units(restriction_factor * nozzle / 2); }  // t
    Coord opening() const { return to_units(opening_factor * nozzle / 2); }          // s'
};

}  // namespace carve
