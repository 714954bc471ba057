// The setting table's rows (setting_rows.hpp), in the table's order. What is printed and on what:
// the carving, the supports, the machine, the filament, the speeds, and the model's scale and
// orientation.
#include "config/setting_rows.hpp"

namespace carve::setting_rows {

std::vector<SettingSpec> print_rows() {
    return {
        {"layer-height", "layer_height", "mm", 0.01, 2.0, &S::layer_height,
         "Layer height h, mm [0.2]"},
        {"nozzle", "nozzle_diameter", "mm", 0.05, 3.0, &S::nozzle,
         "Nozzle diameter = line width w, mm [0.4]"},
        {"max-overhang", "", "degrees", 5.0, 75.0, &S::max_overhang,
         "Largest overhang from vertical the printer bridges, degrees; the per-layer dilation "
         "is r = h * tan(angle) [45]"},
        {"carving", "", "", 0, 0, words(&S::carving, {"whole", "report"}),
         "How the interior is carved: whole (each part of it one cavity, its ceilings bridged "
         "and held by ribs; the least material) or report (Hornus & Lefebvre's iterative "
         "carving: nested cavities torn open along the medial axis, single-filament walls) "
         "[whole]",
         false, "", "carving_scheme"},
        {"cavities", "", "", 0, 0, cavities_field(),
         "Carving iterations k, or 'auto' (stop when the remainder erodes away at the line "
         "width); 0 = a plain hollow shell [6]"},
        {"walls", "", "", 0, 0, words(&S::walls, {"single", "double"}),
         "Cavity walls: single (one filament, report 4.3) or double (4.1) [single]"},
        {"support", "", "", 0, 0, words(&S::support, {"none", "auto", "buildplate"}),
         "Supports under the model's own overhangs: none, auto (down to the bed or onto the "
         "model) or buildplate (only where nothing of the model lies below) [none]"},
        {"support-angle", "", "degrees", 0.0, 85.0, &S::support_angle,
         "Overhang from vertical beyond which the model's own surface needs support; with "
         "--support none carve measures that overhang and warns when it will hang, degrees [0 = "
         "--max-overhang]"},
        {"support-z-gap", "support_material_contact_distance", "mm", 0.0, 2.0, &S::support_z_gap,
         "Gap between a support's top and the overhang it holds, rounded to whole layers, mm "
         "[0.2]"},
        {"support-xy-gap", "", "mm", 0.0, 10.0, &S::support_xy_gap,
         "Gap between a support and the model's side, mm [0.25]"},
        {"support-interface-layers", "support_material_interface_layers", "layers", 0, 10,
         &S::support_interface_layers,
         "Dense layers at the top of every support, under the overhang, layers [2]"},
        {"covers", "", "layers", 0, 50, &S::covers, "Solid layers at tops and bottoms, layers [2]"},
        {"shells", "", "lines", 0, 20, &S::shells,
         "Extra perimeters inside the outer wall, lines [0]"},
        {"strong", "", "ratio", 0.0, 1.0, &S::strength,
         "How strong to print, a ratio of --preset strong's interior, from carve's default (0) "
         "to it (1): on a squat model round(2 x S) shells and --ties 5.5 / S, on a slender "
         "one (height over the side of its mean section 4 or more) round(4 x S) shells; "
         "--shells and --ties given win [0]"},
        {"ties", "", "mm", 0.0, 100.0, &S::tie_spacing,
         "Walls tied across the cavities: a square grid of single-filament walls at +-45 "
         "degrees this far apart, stacked layer on layer from wall to wall, mm; --strong sets "
         "it [0 = none]"},
        {"solid-below", "", "mm", 0.0, 100.0, &S::solid_below,
         "Interior narrower than this (inside the shells) printed solid instead of carved, "
         "mm [0 = none]"},
        {"solid-below-area", "", "mm2", 0.0, 1e6, &S::solid_below_area,
         "A part of a slice (an island) smaller in area than this printed solid instead of "
         "carved, as PrusaSlicer's solid_infill_below_area, mm2 [0 = none]"},
        {"extrusion-width", "", "mm", 0.0, 3.0, &S::extrusion_width,
         "Line width w of every wall and cover, mm; a profile's perimeter_extrusion_width or "
         "extrusion_width sets it [0 = the nozzle diameter]"},
        {"flavor", "gcode_flavor", "", 0, 0, words(&S::flavor, {"marlin", "reprap", "klipper"}),
         "G-code flavour: marlin, reprap or klipper [marlin]", false, "", "", flavor_prusa()},
        {"relative-e", "use_relative_e_distances", "0/1", 0, 1, &S::relative_e,
         "Relative extrusion distances (M83) [off: absolute, M82]"},
        {"bed", "bed_shape", "mm", 0, 0, bed_field(),
         "Bed size WxH, mm; the model is centred on it [250x210]", false, "", "",
         bed_shape_field()},
        {"max-print-height", "max_print_height", "mm", 1.0, 10000.0, &S::max_print_height,
         "Highest the printer prints, mm; a taller model is refused [210]"},
        {"bed-check", "", "0/1", 0, 1, &S::bed_check,
         "Allow a model larger than the bed or taller than --max-print-height [off]", false,
         "!--no-bed-check"},
        {"filament-diameter", "filament_diameter", "mm", 0.5, 5.0, &S::filament_diameter,
         "Filament diameter, mm [1.75]"},
        {"temperature", "temperature", "C", 0, 450, &S::nozzle_temperature,
         "Nozzle temperature after the first layer, C [210]"},
        {"bed-temperature", "bed_temperature", "C", 0, 150, &S::bed_temperature,
         "Bed temperature after the first layer, C [60]"},
        {"first-layer-temperature", "first_layer_temperature", "C", 0, 450,
         &S::first_layer_nozzle_temperature, "Nozzle temperature on the first layer, C [215]"},
        {"first-layer-bed-temperature", "first_layer_bed_temperature", "C", 0, 150,
         &S::first_layer_bed_temperature, "Bed temperature on the first layer, C [60]"},
        {"filament-density", "filament_density", "g/cm^3", 0.1, 20.0, &S::filament_density,
         "Filament density for the weight estimate, g/cm^3 [1.24]"},
        {"travel-speed", "travel_speed", "mm/s", 1.0, 1000.0, &S::travel_speed,
         "Travel speed, mm/s [150]"},
        {"perimeter-speed", "external_perimeter_speed", "mm/s", 1.0, 1000.0, &S::perimeter_speed,
         "Outer wall speed, mm/s [40]", true},
        {"cavity-speed", "perimeter_speed", "mm/s", 1.0, 1000.0, &S::cavity_speed,
         "Cavity wall speed, mm/s [60]"},
        {"cover-speed", "solid_infill_speed", "mm/s", 1.0, 1000.0, &S::cover_speed,
         "Cover (solid) speed, mm/s [50]", true},
        {"bridge-speed", "bridge_speed", "mm/s", 1.0, 1000.0, &S::bridge_speed,
         "Bridge speed, mm/s [25]"},
        {"first-layer-speed", "first_layer_speed", "mm/s", 1.0, 1000.0, &S::first_layer_speed,
         "First layer speed, mm/s [20]", true},
        {"acceleration", "machine_max_acceleration_extruding", "mm/s^2", 10.0, 100000.0,
         &S::acceleration, "Print acceleration, mm/s^2 [1000]"},
        {"travel-acceleration", "machine_max_acceleration_travel", "mm/s^2", 10.0, 100000.0,
         &S::travel_acceleration, "Travel acceleration, mm/s^2 [1500]"},
        {"max-print-speed", "max_print_speed", "mm/s", 1.0, 1000.0, &S::max_print_speed,
         "Cap on every printing speed, mm/s [100]"},
        {"retract-length", "retract_length", "mm", 0.0, 20.0, &S::retract_length,
         "Retraction, mm [0.8]"},
        {"retract-speed", "retract_speed", "mm/s", 1.0, 500.0, &S::retract_speed,
         "Retraction speed, mm/s [35]"},
        {"z-hop", "retract_lift", "mm", 0.0, 10.0, &S::z_hop,
         "Lift on travel with retraction, mm [0]"},
        only(kReport, {"tear-limit", "", "mm", 0.0, 1000.0, &S::tear_limit,
                       "With --carving report: how far a cavity may tear open along its seed "
                       "per slice beyond the dilated cavity, mm; smaller leaves less unsupported "
                       "but uses more material (the report proposes r/2 = 0.1) [0 = no limit]"}),
        only(kReport, {"wall-extension", "", "mm", 0.0, 10.0, &S::wall_extension,
                       "With --carving report: an open single-filament cavity wall is extended "
                       "this far along the walls printed before it at each end, to stick to "
                       "them (report 4.3), mm [1]"}),
        only(kWhole, {"whole-width", "", "mm", 0.0, 1000.0, &S::whole_width,
                      "With --carving whole: a part of the volume to carve narrower than this is "
                      "carved whole and its ceiling printed as bridges, mm; also a part up to "
                      "--whole-width-max wide whose ceiling (what lies under the model's "
                      "surface) is narrower than this; the ribs hold ceilings of any width; 0, "
                      "which would tear every part, is refused: that is --carving report [1000]"}),
        only(kWhole, {"whole-width-max", "", "mm", 0.0, 1000.0, &S::whole_width_max,
                      "With --carving whole: how wide a part whose ceiling is narrower than "
                      "--whole-width may be and still be carved whole, mm [1000]"}),
        {"scale", "", "ratio", 0.01, 100.0, &S::scale,
         "Scale the model uniformly by this factor, ratio [1]"},
        {"orient", "", "", 0, 0, words(&S::orient, {"given", "auto"}),
         "How the model lies on the bed: given (as loaded) or auto (the axis-aligned turns and "
         "the largest faces of its convex hull laid down, each carved at coarse layers with "
         "supports; the least material wins, then the shorter print, then less overhang) "
         "[given]"},
    };
}

}  // namespace carve::setting_rows
