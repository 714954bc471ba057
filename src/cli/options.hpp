// The options of `carve slice`, `info` and `check` that are not settings, as rows in the order
// --help lists them: each bound to the member of its command it sets, whose own initial value is
// the default, and with its help text ending in that default in brackets. main.cpp declares the
// options from these rows (a slice's settings come from config/setting_table.hpp, where the
// kSettingsHere row stands), and tests/cli/help_test.cpp checks each bracket against the member.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "check/gcode_analysis.hpp"
#include "check/strength.hpp"
#include "config/presets.hpp"
#include "config/profiles.hpp"
#include "config/resolve.hpp"
#include "run/pipeline.hpp"

namespace CLI {
class Option;
}

namespace carve::cli {

// What `carve slice` was given.
struct SliceCommand {
    RunOptions run;
    GivenSettings given;  // printer, profile, preset and the table's options (config/resolve.hpp)
    std::string printer;  // --printer, into `given` when it was given
    bool quiet = false;
    double timeout_s = 0;
    // Each switch's option and where CLI11 leaves its value: one that was given is added to
    // given.options after parsing (the last of --m73 and --no-m73 wins).
    std::map<const SettingSpec*, std::pair<CLI::Option*, bool>> switches;
};

struct InfoCommand {
    std::string model;
    bool json = false;
};

struct CheckCommand {
    std::string gcode;
    GcodeAnalysisOptions analysis;
    bool json = false;
    double timeout_s = 0;
    bool layers = false;
    std::string mesh, mesh_offset;
    bool strict = false;
    bool strength = false;
    StrengthOptions strength_options;
    std::string law = "linear";
};

// The member an option sets: a flag's bool, a number, or text.
using OptionTarget = std::variant<bool*, int*, long long*, double*, std::string*>;

template <class Command>
struct OptionRow {
    const char* names;  // CLI11's: "-o,--output", "--stats", or "model" for a positional
    std::string help;   // ending with the default in brackets
    OptionTarget (*target)(Command&);
    double min = 0, max = 0;                // a number's range, inclusive
    const char* unit = "";                  // a number's unit, as its range error names it
    std::vector<std::string> choices = {};  // the words a text option takes, when a few
    bool required = false;
};

// Where a slice's settings (the setting table's options) go among its rows.
inline constexpr const char* kSettingsHere = "";

inline const std::vector<OptionRow<SliceCommand>>& slice_rows() {
    using C = SliceCommand;
    static const std::vector<OptionRow<C>> rows{
        {.names = "model",
         .help = "Mesh file: STL (binary or ASCII), OBJ or 3MF; millimetres [required]",
         .target = [](C& c) -> OptionTarget { return &c.run.model_path; },
         .required = true},
        {.names = "-o,--output",
         .help = "G-code file to write [required]",
         .target = [](C& c) -> OptionTarget { return &c.run.gcode_path; },
         .required = true},
        {.names = "--stats",
         .help = "Write the run's figures as JSON to this file [none]",
         .target = [](C& c) -> OptionTarget { return &c.run.stats_path; }},
        {.names = "--stats-check",
         .help = "Also measure the written G-code as carve check --mesh does (hanging inside "
                 "and overhang, material per type, retractions, travel, thin columns, skins "
                 "left open, the --strict verdict) into the stats' \"check\" and the "
                 "summary [off: it doubles the run time]",
         .target = [](C& c) -> OptionTarget { return &c.run.check_output; }},
        {.names = "--strict",
         .help = "Measure the G-code as --stats-check does and write nothing (exit status 5, "
                 "the rules failed on stderr) when it fails a rule of carve check --strict; "
                 "with --cut, every plate [off]",
         .target = [](C& c) -> OptionTarget { return &c.run.strict; }},
        {.names = "--plate-meshes",
         .help = "With --cut: also write each plate's pieces as a binary STL (-o with -plateN.stl "
                 "for its extension), where the plate's G-code prints them, for carve check "
                 "--mesh or another slicer [off]",
         .target = [](C& c) -> OptionTarget { return &c.run.plate_meshes; }},
        {.names = "--stats-strength",
         .help = "Also measure the written G-code's strength as carve check --strength does "
                 "(grams, weakest section and bond with their z, compression and shear "
                 "stiffness; 2 mm voxels, linear law) into the stats' \"strength\", the "
                 "summary and the HTML report, which marks the weakest layers [off: it takes "
                 "several times as long as the slicing]",
         .target = [](C& c) -> OptionTarget { return &c.run.strength_output; }},
        {.names = "--load",
         .help = "PrusaSlicer .ini profile with printer and filament settings (options given "
                 "on the command line win) [none]",
         .target = [](C& c) -> OptionTarget { return &c.given.profile_path; }},
        {.names = "--printer-profile",
         .help = "With a --load bundle: its [printer:NAME] to use [the bundle's presets section]",
         .target = [](C& c) -> OptionTarget { return &c.given.profile.choice.printer; }},
        {.names = "--filament-profile",
         .help = "With a --load bundle: its [filament:NAME] to use [the bundle's presets "
                 "section, else the printer's default_filament_profile]",
         .target = [](C& c) -> OptionTarget { return &c.given.profile.choice.filament; }},
        {.names = "--print-profile",
         .help = "With a --load bundle: its [print:NAME] to use [the bundle's presets section, "
                 "else the printer's default_print_profile]",
         .target = [](C& c) -> OptionTarget { return &c.given.profile.choice.print; }},
        {.names = "--profile-shells",
         .help = "Take covers and shells from the --load profile's top_solid_layers, "
                 "bottom_solid_layers and perimeters [off: carve's own]",
         .target = [](C& c) -> OptionTarget { return &c.given.profile.profile_shells; }},
        {.names = "--printer",
         .help = "Built-in printer preset: " + printer_preset_names() + " [generic]",
         .target = [](C& c) -> OptionTarget { return &c.printer; }},
        {.names = "--preset",
         .help = "The report's presets: 2c0s (2 covers, no shell) or 3c1s (3 covers, 1 "
                 "shell); or strong (--strong 1: the report's carving and 4 shells, the "
                 "stiffest for its weight that carve measured) [none: 2 covers, 0 shells]",
         .target = [](C& c) -> OptionTarget { return &c.given.preset; },
         .choices = {"2c0s", "3c1s", "strong"}},
        {.names = "--report",
         .help = "Write an HTML report (self-contained) to this file [none]",
         .target = [](C& c) -> OptionTarget { return &c.run.report_path; }},
        {.names = "--svg-layers",
         .help = "Write SVG pictures of some layers into DIR [none]",
         .target = [](C& c) -> OptionTarget { return &c.run.svg_dir; }},
        {.names = "--svg-every",
         .help = "With --svg-layers: every N-th layer, layers [0: eight spread over the height]",
         .target = [](C& c) -> OptionTarget { return &c.run.svg_every; },
         .min = 0,
         .max = 100000,
         .unit = "layers"},
        {.names = "--raster",
         .help = "Write a PNG slice stack for resin printers, and its zip, into DIR [none]",
         .target = [](C& c) -> OptionTarget { return &c.run.raster_dir; }},
        {.names = "--raster-pixel",
         .help = "With --raster: pixel size (the printer's XY resolution), mm [0.05]",
         .target = [](C& c) -> OptionTarget { return &c.run.raster_pixel_mm; },
         .min = 0.005,
         .max = 1.0,
         .unit = "mm"},
        {.names = "--raster-min-wall",
         .help = "With --raster: thinnest wall the resin printer cures; cavity outlines are "
                 "thickened to it, mm [0.4]",
         .target = [](C& c) -> OptionTarget { return &c.run.raster_min_wall_mm; },
         .min = 0.01,
         .max = 10.0,
         .unit = "mm"},
        {.names = kSettingsHere, .help = "", .target = nullptr},
        {.names = "--timeout",
         .help = "Give up after this much time, removing every output and temporary; "
                 "0 = no limit, seconds [0]",
         .target = [](C& c) -> OptionTarget { return &c.timeout_s; },
         .min = 0,
         .max = 1e7,
         .unit = "seconds"},
        {.names = "-q,--quiet",
         .help = "Print nothing but errors [off]",
         .target = [](C& c) -> OptionTarget { return &c.quiet; }},
    };
    return rows;
}

inline const std::vector<OptionRow<InfoCommand>>& info_rows() {
    using C = InfoCommand;
    static const std::vector<OptionRow<C>> rows{
        {.names = "model",
         .help = "Mesh file: STL, OBJ or 3MF [required]",
         .target = [](C& c) -> OptionTarget { return &c.model; },
         .required = true},
        {.names = "--json",
         .help = "Machine-readable output (JSON) [off: text]",
         .target = [](C& c) -> OptionTarget { return &c.json; }},
    };
    return rows;
}

inline const std::vector<OptionRow<CheckCommand>>& check_rows() {
    using C = CheckCommand;
    static const std::vector<OptionRow<C>> rows{
        {.names = "gcode",
         .help = "G-code file [required]",
         .target = [](C& c) -> OptionTarget { return &c.gcode; },
         .required = true},
        {.names = "--support-radius",
         .help = "Overhang allowance r, mm [0.2]",
         .target = [](C& c) -> OptionTarget { return &c.analysis.support_radius_mm; },
         .min = 0,
         .max = 100,
         .unit = "mm"},
        {.names = "--far-radius",
         .help = "Distance no filament bridges, mm [2]",
         .target = [](C& c) -> OptionTarget { return &c.analysis.far_radius_mm; },
         .min = 0.01,
         .max = 100,
         .unit = "mm"},
        {.names = "--support-gap",
         .help = "A support's top this far below the layer under an extrusion holds it too "
                 "(the z gap supports leave), mm [0.2]",
         .target = [](C& c) -> OptionTarget { return &c.analysis.support_gap_mm; },
         .min = 0,
         .max = 10,
         .unit = "mm"},
        {.names = "--filament-diameter",
         .help = "Filament diameter, mm; given, it wins over the G-code header's "
                 "[the header's, else 1.75]",
         .target = [](C& c) -> OptionTarget { return &c.analysis.filament_diameter_mm; },
         .min = 0.5,
         .max = 5,
         .unit = "mm"},
        {.names = "--json",
         .help = "Machine-readable output (JSON) [off: text]",
         .target = [](C& c) -> OptionTarget { return &c.json; }},
        {.names = "--timeout",
         .help = "Give up after this much time; 0 = no limit, seconds [0]",
         .target = [](C& c) -> OptionTarget { return &c.timeout_s; },
         .min = 0,
         .max = 1e7,
         .unit = "seconds"},
        {.names = "--layers",
         .help = "The figures of every layer too (z, footprint, far-unsupported, with --mesh "
                 "inside, overhang, travel outside, crossings; retractions, travel, stick "
                 "time), as a table or with --json in it [off]",
         .target = [](C& c) -> OptionTarget { return &c.layers; }},
        {.names = "--mesh",
         .help = "The model the G-code prints (STL, OBJ, 3MF): splits hanging filament "
                 "into inside and overhang, measures travel outside it [none]",
         .target = [](C& c) -> OptionTarget { return &c.mesh; }},
        {.names = "--mesh-offset",
         .help = "With --mesh: X,Y[,Z] from the mesh's coordinates to the G-code's, mm "
                 "[found from the extrusion's bounding box]",
         .target = [](C& c) -> OptionTarget { return &c.mesh_offset; }},
        {.names = "--strict",
         .help = "With --mesh: exit with status 5 when the G-code fails a printability rule "
                 "(a free-standing thin column over 5 mm, top or bottom skin open over "
                 "0.25 %, over 1 mm2 hanging inside, a piece of the model a line wide left "
                 "unprinted), naming each on stderr [off]",
         .target = [](C& c) -> OptionTarget { return &c.strict; }},
        {.names = "--strength",
         .help = "How strong the print is (skirt, brim, supports and custom G-code left "
                 "out): grams, each layer's section (area, second moments) and bond with the "
                 "next, the weakest of each, a voxel finite-element stiffness in compression "
                 "and shear, each per gram [off]",
         .target = [](C& c) -> OptionTarget { return &c.strength; }},
        {.names = "--voxel-size",
         .help = "With --strength: the side of the voxels (finite elements), mm [2]",
         .target = [](C& c) -> OptionTarget { return &c.strength_options.voxel_mm; },
         .min = 0.5,
         .max = 50,
         .unit = "mm"},
        {.names = "--max-voxels",
         .help = "With --strength: voxels the solver takes at most; above, the voxel is "
                 "doubled until the model fits [40000]",
         .target = [](C& c) -> OptionTarget { return &c.strength_options.max_voxels; },
         .min = 100,
         .max = 2000000,
         .unit = "voxels"},
        {.names = "--material-law",
         .help = "With --strength: a voxel's Young's modulus from its filled fraction f: "
                 "linear (E f) or cubic (E f^3) [linear]",
         .target = [](C& c) -> OptionTarget { return &c.law; },
         .choices = {"linear", "cubic"}},
        {.names = "--filament-density",
         .help = "With --strength: for the grams (PLA's by default), g/cm^3 [1.24]",
         .target = [](C& c) -> OptionTarget { return &c.strength_options.density_g_cm3; },
         .min = 0.1,
         .max = 25,
         .unit = "g/cm^3"},
    };
    return rows;
}

}  // namespace carve::cli
