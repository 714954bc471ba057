// The setting table's rows (setting_rows.hpp), in the table's order. The layers' shapes and paths:
// skirt, brim and raft, the first layer and the flow, thin walls, copies, bridges, ribs, vaults and
// travel.
#include "config/setting_rows.hpp"

namespace carve::setting_rows {

std::vector<SettingSpec> layer_rows() {
    return {
        // Skirt and brim (toolpath/skirt.hpp), PrusaSlicer's keys and defaults (its printer
        // profiles' brim_separation).
        {"skirts", "skirts", "loops", 0, 100, &S::skirts,
         "Loops of skirt around the first layers, priming the nozzle; 0 = none, loops [1]"},
        {"skirt-distance", "skirt_distance", "mm", 0.0, 500.0, &S::skirt_distance,
         "Gap between the skirt and the part (or its brim), mm [6]"},
        {"skirt-height", "skirt_height", "layers", 0, 10000, &S::skirt_height,
         "Layers the skirt rises, layers [1]"},
        {"brim-width", "brim_width", "mm", 0.0, 200.0, &S::brim_width,
         "Width of the brim around the outside of each part on the first layer (the brims of "
         "two copies join only where they touch); 0 = none, mm [0]"},
        {"brim-separation", "brim_separation", "mm", 0.0, 10.0, &S::brim_separation,
         "Gap between the part and its brim, so that it breaks off cleanly, mm [0.1]"},
        // The raft (toolpath/raft.hpp), PrusaSlicer's keys and defaults.
        {"raft-layers", "raft_layers", "layers", 0, 100, &S::raft_layers,
         "Layers of raft printed under the model, wider than its first layer, for a part that "
         "holds the bed poorly; the raft's first layer takes the first-layer settings, the "
         "model starts --raft-contact-distance above its top; 0 = none, layers [0]"},
        {"raft-contact-distance", "raft_contact_distance", "mm", 0.0, 2.0,
         &S::raft_contact_distance,
         "Gap between the raft's top and the model's first layer, so that the raft peels off "
         "(at most the layer height: the model's first layer fills it with its flow), mm [0.1]"},
        {"raft-expansion", "raft_expansion", "mm", 0.0, 100.0, &S::raft_expansion,
         "How far the raft reaches beyond the model's first layer, mm [1.5]"},
        {"raft-first-layer-expansion", "raft_first_layer_expansion", "mm", 0.0, 100.0,
         &S::raft_first_layer_expansion,
         "How far the raft's first layer reaches beyond the raft's other layers, mm [3]"},
        // The first layer and the flow (issue #36), PrusaSlicer's keys and meanings.
        {"first-layer-height", "first_layer_height", "mm", 0.0, 2.0, &S::first_layer_height,
         "Height of the first layer (no higher than the nozzle), mm; later layers stand on it "
         "at --layer-height [0 = the layer height]",
         true, "", "", first_layer_prusa()},
        {"first-layer-extrusion-width", "", "mm", 0.0, 3.0, &S::first_layer_extrusion_width,
         "Line width on the first layer (its E follows it; the paths keep their places), under "
         "3 nozzle widths as PrusaSlicer requires; a profile's first_layer_extrusion_width sets "
         "it, mm [0 = the line width]"},
        // 0.5 to 2 (issue #52): calibration moves it by a few percent; at half the flow the
        // lines no longer touch their neighbours or the layer below, at twice it each line
        // holds two lines' plastic, which the nozzle ploughs through on the next pass.
        {"extrusion-multiplier", "extrusion_multiplier", "ratio", 0.5, 2.0,
         &S::extrusion_multiplier,
         "Scales the filament fed by every extrusion (0.5 to 2: beyond, lines either no longer "
         "touch or overflow the line), ratio [1]"},
        {"max-volumetric-speed", "max_volumetric_speed", "mm^3/s", 0.0, 1000.0,
         &S::max_volumetric_speed,
         "Cap on every extrusion's flow: a line is printed no faster than this over its width "
         "x height, and a cap that would hold the widest line under 5 mm/s is refused; a "
         "profile's filament_max_volumetric_speed caps it too, mm^3/s [0 = none]"},
        {"elephant-foot-compensation", "elefant_foot_compensation", "mm", 0.0, 5.0,
         &S::elephant_foot_compensation,
         "The first layer's slice is shrunk by this, against the squashed first layer's bulge, "
         "mm [0]"},
        {"thin-walls", "", "0/1", 0, 1, &S::thin_walls,
         "Print the parts of a slice narrower than two lines (fins, rims, lettering) as one line "
         "along their middle, as wide as the part; --no-thin-walls: only what the outer wall "
         "holds [on]",
         false, "!--no-thin-walls,--thin-walls"},
        {"min-bead-width", "", "mm", 0.0, 3.0, &S::min_bead_width,
         "Narrowest line a thin part is printed with: a part narrower than this (and not than "
         "--min-feature-size) is widened to it; a profile's min_bead_width sets it, mm [0 = 85 % "
         "of the nozzle]"},
        {"min-feature-size", "", "mm", 0.0, 3.0, &S::min_feature_size,
         "A part of a slice narrower than this is not printed (carve slice reports what that "
         "leaves out); a profile's min_feature_size sets it, mm [0 = 25 % of the nozzle]"},
        {"xy-size-compensation", "xy_size_compensation", "mm", -5.0, 5.0, &S::xy_size_compensation,
         "Every slice grows by this (shrinks if negative), holes shrinking with it, mm [0]"},
        {"z-offset", "z_offset", "mm", -10.0, 10.0, &S::z_offset,
         "Added to every Z written to the G-code (the printer's bed height); the first layer "
         "it leaves is at least a quarter of the layer height (or of the nozzle, if thinner) "
         "and the highest Z within --max-print-height, mm [0]"},
        {"copies", "", "copies", 1, 400, &S::copies,
         "Print this many copies of the model side by side, each its own object (labelled for "
         "cancelling), copies [1]"},
        {"copy-gap", "", "mm", 0.0, 100.0, &S::copy_gap,
         "With --copies: the gap between two copies, mm [6]"},
        {"threads", "", "threads", 0, 512, &S::threads,
         "Threads the per-layer work runs on, from 1 (everything on one thread) up; the G-code "
         "is the same for every count, threads [0 = every core]"},
        {"prune-bridges", "", "0/1", 0, 1, &S::prune_bridges,
         "Keep bridges that the layer below already supports [off]", false, "!--keep-all-bridges"},
        {"max-bridge-length", "", "mm", 1.0, 500.0, &S::max_bridge_length,
         "Longest span a bridge may have, mm; a longer one is split into pieces bridged apart, "
         "and what no shorter line reaches is left out [10]"},
        {"rib-reach", "", "mm", 0.0, 100.0, &S::rib_reach,
         "What the layer above prints deeper than this inside a cavity gets a rib under it, a "
         "column grown down through the cavity leaning at most the overhang angle, mm; 0 = no "
         "ribs [1.6]"},
        {"rib-spacing", "", "mm", 0.5, 100.0, &S::rib_spacing,
         "Spacing of the lattice the ribs are seeded on, mm [2.6]"},
        {"rib-piece", "", "mm", 0.0, 100.0, &S::rib_piece,
         "Length of the line a rib prints on each layer (at least two line widths), mm [0.8]"},
        {"vault-width", "", "mm", 0.0, 1000.0, &S::vault_width,
         "What would hang over a part at least this wide gets vault lines instead of ribs where "
         "they print less: parallel walls across the cavity, wall to wall, merging in pairs "
         "going down, mm; 0 = ribs alone [2.6]"},
        {"max-vertices-per-layer", "", "vertices", 0, 1e9, &S::max_vertices_per_layer,
         "Give up when one slice has more contour vertices than this; 0 = no limit, vertices "
         "[5000000]"},
        {"max-vertices", "", "vertices", 0, 1e10, &S::max_vertices_total,
         "Give up when the slices hold more contour vertices than this in all; 0 = no limit, "
         "vertices [100000000]"},
        {"combing", "", "", 0, 0, words(&S::combing, {"off", "inside", "all"}),
         "Travel inside the part without retracting: off (straight travels), inside (not over "
         "covers) or all (anywhere in the island) [all]"},
        {"avoid-crossing-perimeters", "avoid_crossing_perimeters", "0/1", 0, 1,
         &S::avoid_crossing_perimeters,
         "A travel that must leave its island goes inside it to where the next island is "
         "closest, crosses the gap and goes on inside that one, instead of straight [on]",
         false, "!--no-avoid-crossing-perimeters,--avoid-crossing-perimeters"},
        {"seam", "seam_position", "", 0, 0,
         words(&S::seam, {"aligned", "nearest", "rear", "random"}),
         "Where outer wall loops start: aligned (one line, in concave corners where there are "
         "any), nearest, rear or random [aligned]"},
        {"wipe", "wipe", "0/1", 0, 1, &S::wipe,
         "Move back along the last path while retracting [off]"},
        {"retract-before-travel", "retract_before_travel", "mm", 0.0, 1000.0,
         &S::retract_min_travel,
         "Only a travel longer than this retracts (one that stays inside the part with combing "
         "never does), mm [2]"},
        {"firmware-retraction", "use_firmware_retraction", "0/1", 0, 1, &S::firmware_retraction,
         "Retract with G10/G11, length and speed set in the firmware [off]"},
        {"wipe-distance", "", "mm", 0.0, 50.0, &S::wipe_distance,
         "With --wipe: how far back, mm [1]"},
    };
}

}  // namespace carve::setting_rows
