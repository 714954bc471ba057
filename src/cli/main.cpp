// carve command line: parses options into Settings and calls the library. Nothing else.
//
// Errors the user can act on (bad file, bad option) come out as one line on stderr and exit 1;
// no partial output file is ever left behind (the G-code writer renames only when complete).
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>

#include "base/error.hpp"
#include "run/pipeline.hpp"
#include "gcode/placeholders.hpp"
#include "config/profiles.hpp"
#include "mesh/mesh.hpp"
#include "check/gcode_analysis.hpp"
#include "report/mesh_info.hpp"
#include "report/stats.hpp"

namespace {

int fail(const std::string& message) {
    std::fprintf(stderr, "carve: %s\n", message.c_str());
    return 1;
}

// Writes a small text file atomically: to a temporary name, renamed when complete.
void write_text_atomically(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) throw carve::InputError(fmt::format("cannot write {}", path));
        out << text;
        if (!out.flush()) {
            std::remove(tmp.c_str());
            throw carve::InputError(fmt::format("cannot write {} (disk full?)", path));
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw carve::InputError(fmt::format("cannot write {}", path));
    }
}

// The value of `--name VALUE` or `--name=VALUE` in argv, or empty.
std::string find_option(int argc, char** argv, const std::string& name) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == name && i + 1 < argc) return argv[i + 1];
        if (a.rfind(name + "=", 0) == 0) return a.substr(name.size() + 1);
    }
    return {};
}

// Printer preset, profile and report preset set the defaults that explicit options override,
// so they are applied before the options are parsed.
std::vector<std::string> pre_apply(int argc, char** argv, carve::Settings& settings) {
    std::vector<std::string> notes;
    if (const std::string p = find_option(argc, argv, "--printer"); !p.empty())
        carve::apply_printer_preset(p, settings);
    if (const std::string f = find_option(argc, argv, "--load"); !f.empty())
        notes = carve::load_prusa_profile(f, settings);
    const std::string preset = find_option(argc, argv, "--preset");
    if (preset == "2c0s") settings.covers = 2, settings.shells = 0;
    if (preset == "3c1s") settings.covers = 3, settings.shells = 1;
    return notes;
}

}  // namespace

int main(int argc, char** argv) {
    // Past a file size limit (ulimit -f) the write fails with EFBIG and the writer cleans up and
    // says so; the default action of SIGXFSZ would kill the process and leave its temporary file.
    std::signal(SIGXFSZ, SIG_IGN);
    CLI::App app{
        "carve: slices a mesh into G-code that prints it hollow, with nested "
        "self-supporting cavities instead of infill"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "carve 0.1.0");

    carve::Settings settings;
    carve::RunOptions run;
    std::string stats_path, cavities_text = "6", walls_text = "single", preset, profile_path,
                            printer_name, flavor_text = "marlin", bed_text;
    bool quiet = false, no_bed_check = false;

    CLI::App* slice = app.add_subcommand("slice", "Slice MODEL into hollow G-code (the main job)");
    slice
        ->add_option("model", run.model_path,
                     "Mesh file: STL (binary or ASCII), OBJ or 3MF; millimetres [required]")
        ->required();
    slice->add_option("-o,--output", run.gcode_path, "G-code file to write [required]")->required();
    slice->add_option("--stats", stats_path, "Write the run's figures as JSON to this file [none]");
    slice->add_flag("--stats-check", run.check_output,
                    "Also measure the written G-code as carve check --mesh does (hanging inside "
                    "and overhang, material per type, retractions, travel) into the stats' "
                    "\"check\" [off: it doubles the run time]");
    slice->add_option("--load", profile_path,
                      "PrusaSlicer .ini profile with printer and filament settings (options given "
                      "on the command line win) [none]");
    slice->add_option("--printer", printer_name,
                      "Built-in printer preset: " + carve::printer_preset_names() + " [generic]");
    slice
        ->add_option("--preset", preset,
                     "The report's presets: 2c0s (2 covers, no shell) or "
                     "3c1s (3 covers, 1 shell) [none: 2 covers, 0 shells]")
        ->check(CLI::IsMember({"2c0s", "3c1s"}));
    slice->add_option("--layer-height", settings.layer_height, "Layer height h, mm [0.2]")
        ->check(CLI::Range(0.01, 2.0));
    slice->add_option("--nozzle", settings.nozzle, "Nozzle diameter = line width w, mm [0.4]")
        ->check(CLI::Range(0.05, 3.0));
    slice
        ->add_option("--max-overhang", settings.max_overhang,
                     "Largest overhang from vertical the printer bridges, degrees; the per-layer "
                     "dilation is r = h * tan(angle) [45]")
        ->check(CLI::Range(5.0, 75.0));
    slice->add_option("--cavities", cavities_text,
                      "Carving iterations k, or 'auto' (stop when the remainder erodes away at "
                      "the line width); 0 = a plain hollow shell [6]");
    slice->add_option("--covers", settings.covers, "Solid layers at tops and bottoms, layers [2]")
        ->check(CLI::Range(0, 50));
    slice
        ->add_option("--shells", settings.shells,
                     "Extra perimeters inside the outer wall, lines [0]")
        ->check(CLI::Range(0, 20));
    slice
        ->add_option("--walls", walls_text,
                     "Cavity walls: single (one filament, report 4.3) or double (4.1) [single]")
        ->check(CLI::IsMember({"single", "double"}));
    slice->add_option("--flavor", flavor_text, "G-code flavour: marlin, reprap or klipper [marlin]")
        ->check(CLI::IsMember({"marlin", "reprap", "klipper"}));
    slice->add_flag("--relative-e", settings.relative_e,
                    "Relative extrusion distances (M83) [off: absolute, M82]");
    slice
        ->add_option("--filament-diameter", settings.filament_diameter,
                     "Filament diameter, mm [1.75]")
        ->check(CLI::Range(0.5, 5.0));
    slice->add_option("--bed", bed_text, "Bed size WxH, mm; the model is centred on it [250x210]");
    slice->add_flag("--no-bed-check", no_bed_check, "Allow a model larger than the bed [off]");
    slice
        ->add_option("--temperature", settings.nozzle_temperature,
                     "Nozzle temperature after the first layer, C [210]")
        ->check(CLI::Range(0, 450));
    slice
        ->add_option("--bed-temperature", settings.bed_temperature,
                     "Bed temperature after the first layer, C [60]")
        ->check(CLI::Range(0, 150));
    slice
        ->add_option("--first-layer-temperature", settings.first_layer_nozzle_temperature,
                     "Nozzle temperature on the first layer, C [215]")
        ->check(CLI::Range(0, 450));
    slice
        ->add_option("--first-layer-bed-temperature", settings.first_layer_bed_temperature,
                     "Bed temperature on the first layer, C [60]")
        ->check(CLI::Range(0, 150));
    slice
        ->add_option("--filament-density", settings.filament_density,
                     "Filament density for the weight estimate, g/cm^3 [1.24]")
        ->check(CLI::Range(0.1, 20.0));
    slice->add_option("--travel-speed", settings.travel_speed, "Travel speed, mm/s [150]")
        ->check(CLI::Range(1.0, 1000.0));
    slice->add_option("--perimeter-speed", settings.perimeter_speed, "Outer wall speed, mm/s [40]")
        ->check(CLI::Range(1.0, 1000.0));
    slice->add_option("--cavity-speed", settings.cavity_speed, "Cavity wall speed, mm/s [60]")
        ->check(CLI::Range(1.0, 1000.0));
    slice->add_option("--cover-speed", settings.cover_speed, "Cover (solid) speed, mm/s [50]")
        ->check(CLI::Range(1.0, 1000.0));
    slice->add_option("--bridge-speed", settings.bridge_speed, "Bridge speed, mm/s [25]")
        ->check(CLI::Range(1.0, 1000.0));
    slice
        ->add_option("--first-layer-speed", settings.first_layer_speed,
                     "First layer speed, mm/s [20]")
        ->check(CLI::Range(1.0, 1000.0));
    slice->add_option("--acceleration", settings.acceleration, "Print acceleration, mm/s^2 [1000]")
        ->check(CLI::Range(10.0, 100000.0));
    slice
        ->add_option("--travel-acceleration", settings.travel_acceleration,
                     "Travel acceleration, mm/s^2 [1500]")
        ->check(CLI::Range(10.0, 100000.0));
    slice
        ->add_option("--max-print-speed", settings.max_print_speed,
                     "Cap on every printing speed, mm/s [100]")
        ->check(CLI::Range(1.0, 1000.0));
    slice->add_option("--retract-length", settings.retract_length, "Retraction, mm [0.8]")
        ->check(CLI::Range(0.0, 20.0));
    slice->add_option("--retract-speed", settings.retract_speed, "Retraction speed, mm/s [35]")
        ->check(CLI::Range(1.0, 500.0));
    slice->add_option("--z-hop", settings.z_hop, "Lift on travel with retraction, mm [0]")
        ->check(CLI::Range(0.0, 10.0));
    slice
        ->add_option("--tear-limit", settings.tear_limit,
                     "How far a cavity may tear open along its seed per slice beyond the dilated "
                     "cavity, mm; smaller leaves less unsupported but uses more material "
                     "(the report proposes r/2 = 0.1) [0 = no limit]")
        ->check(CLI::Range(0.0, 1000.0));
    slice->add_flag("!--keep-all-bridges", settings.prune_bridges,
                    "Keep bridges that the layer below already supports [off]");
    slice->add_option("--report", run.report_path,
                      "Write an HTML report (self-contained) to this file [none]");
    slice->add_option("--svg-layers", run.svg_dir,
                      "Write SVG pictures of some layers into DIR [none]");
    slice
        ->add_option("--svg-every", run.svg_every,
                     "With --svg-layers: every N-th layer, layers [0: eight spread over the "
                     "height]")
        ->check(CLI::Range(0, 100000));
    slice->add_option("--raster", run.raster_dir,
                      "Write a PNG slice stack for resin printers, and its zip, into DIR [none]");
    slice
        ->add_option("--raster-pixel", run.raster_pixel_mm,
                     "With --raster: pixel size (the printer's XY resolution), mm [0.05]")
        ->check(CLI::Range(0.005, 1.0));
    slice
        ->add_option("--raster-min-wall", run.raster_min_wall_mm,
                     "With --raster: thinnest wall the resin printer cures; cavity outlines are "
                     "thickened to it, mm [0.4]")
        ->check(CLI::Range(0.01, 10.0));
    slice
        ->add_option("--scale", settings.scale,
                     "Scale the model uniformly by this factor, ratio [1]")
        ->check(CLI::Range(0.01, 100.0));
    slice
        ->add_option("--threads", settings.threads,
                     "Threads the per-layer work runs on, any number from 1 (everything on "
                     "one thread); the G-code is the same for every count, threads [all cores]")
        ->check(CLI::Range(1, 4096));
    slice
        ->add_option("--max-bridge-length", settings.max_bridge_length,
                     "Longest span a bridge may have, mm; longer ones are left out [10]")
        ->check(CLI::Range(1.0, 500.0));
    slice
        ->add_option("--max-vertices-per-layer", settings.max_vertices_per_layer,
                     "Give up when one slice has more contour vertices than this; 0 = no limit, "
                     "vertices [5000000]")
        ->check(CLI::NonNegativeNumber);
    slice->add_flag("-q,--quiet", quiet, "Print nothing but errors [off]");

    std::string info_model;
    bool info_json = false;
    CLI::App* info = app.add_subcommand("info", "Describe a mesh: size, volume, closedness");
    info->add_option("model", info_model, "Mesh file: STL, OBJ or 3MF [required]")->required();
    info->add_flag("--json", info_json, "Machine-readable output (JSON) [off: text]");

    std::string check_gcode;
    bool check_json = false;
    carve::GcodeAnalysisOptions check_options;
    CLI::App* check = app.add_subcommand(
        "check",
        "Measure material and unsupported extrusion of any G-code file (carve's, "
        "PrusaSlicer's, Cura's)");
    check->add_option("gcode", check_gcode, "G-code file [required]")->required();
    check->add_option("--support-radius", check_options.support_radius_mm,
                      "Overhang allowance r, mm [0.2]");
    check->add_option("--far-radius", check_options.far_radius_mm,
                      "Distance no filament bridges, mm [2]");
    check->add_option("--filament-diameter", check_options.filament_diameter_mm,
                      "Filament diameter, mm [1.75]");
    check->add_flag("--json", check_json, "Machine-readable output (JSON) [off: text]");
    bool check_layers = false;
    check->add_flag("--layers", check_layers,
                    "The figures of every layer too (z, footprint, far-unsupported, with --mesh "
                    "inside, overhang, travel outside, crossings; retractions, travel, stick "
                    "time), as a table or with --json in it [off]");
    std::string check_mesh, check_offset;
    check->add_option("--mesh", check_mesh,
                      "The model the G-code prints (STL, OBJ, 3MF): splits hanging filament "
                      "into inside and overhang, measures travel outside it [none]");
    check->add_option("--mesh-offset", check_offset,
                      "With --mesh: X,Y[,Z] from the mesh's coordinates to the G-code's, mm "
                      "[found from the extrusion's bounding box]");

    std::vector<std::string> profile_notes;
    try {
        profile_notes = pre_apply(argc, argv, settings);
    } catch (const carve::InputError& e) {
        return fail(e.what());
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return fail(fmt::format("{} (see carve --help)", e.what()));
    }

    try {
        if (*info) {
            carve::MeshReport report;
            carve::load_mesh(info_model, report);
            if (info_json)
                std::cout << carve::to_json(report).dump(2) << "\n";
            else
                std::cout << carve::describe(report);
            return 0;
        }
        if (*check) {
            std::optional<carve::Vec3> offset;
            if (!check_offset.empty()) {
                carve::Vec3 o{0, 0, std::numeric_limits<double>::quiet_NaN()};  // z: on the bed
                char extra = 0;
                int n =
                    std::sscanf(check_offset.c_str(), "%lf,%lf,%lf%c", &o.x, &o.y, &o.z, &extra);
                if (n != 2 && n != 3)
                    return fail(fmt::format("--mesh-offset: expected X,Y or X,Y,Z in mm, got '{}'",
                                            check_offset));
                offset = o;
            }
            carve::GcodeAnalysis a;
            if (!check_mesh.empty()) {
                carve::MeshReport report;
                const carve::Mesh mesh = carve::load_mesh(check_mesh, report);
                a = carve::analyse_gcode_on_mesh(check_gcode, mesh, check_options, offset);
            } else {
                if (offset) return fail("--mesh-offset needs --mesh");
                a = carve::analyse_gcode(check_gcode, check_options);
            }
            if (check_json) {
                std::cout << carve::to_json(a, check_layers).dump(2) << "\n";
            } else {
                std::cout << carve::describe(a);
                if (check_layers) std::cout << "\n" << carve::describe_layers(a);
            }
            return 0;
        }

        // Precedence: built-in printer, then profile file, then preset, then explicit options.
        // The first three were applied before parsing (see pre_apply); parsing only writes the
        // options the user gave, so those win.
        for (const std::string& n : profile_notes)
            if (!quiet) std::fprintf(stderr, "carve: note: %s\n", n.c_str());
        // Placeholders of the custom G-code that carve cannot evaluate: said once, up front.
        const std::map<std::string, double> at_end{
            {"max_layer_z", 0}, {"layer_z", 0}, {"layer_num", 0}};
        for (const auto& [name, text] : {std::pair{"start_gcode", &settings.start_gcode},
                                         std::pair{"end_gcode", &settings.end_gcode}})
            for (const std::string& u :
                 carve::expand_custom_gcode(*text, settings, at_end).unresolved)
                if (!quiet) std::fprintf(stderr, "carve: note: %s: %s\n", name, u.c_str());

        if (cavities_text == "auto") {
            settings.cavities_auto = true;
        } else {
            try {
                size_t used = 0;
                settings.cavities = std::stoi(cavities_text, &used);
                if (used != cavities_text.size() || settings.cavities < 0 || settings.cavities > 64)
                    throw std::invalid_argument("range");
            } catch (const std::exception&) {
                return fail(
                    fmt::format("--cavities: expected a number from 0 to 64 or 'auto', got '{}'",
                                cavities_text));
            }
        }
        if (slice->count("--walls"))
            settings.walls =
                walls_text == "double" ? carve::WallMode::Double : carve::WallMode::Single;
        if (slice->count("--flavor"))
            settings.flavor = flavor_text == "klipper"  ? carve::GcodeFlavor::Klipper
                              : flavor_text == "reprap" ? carve::GcodeFlavor::RepRap
                                                        : carve::GcodeFlavor::Marlin;
        if (!bed_text.empty()) {
            double bx = 0, by = 0;
            char x = 0, extra = 0;
            if (std::sscanf(bed_text.c_str(), "%lf%c%lf%c", &bx, &x, &by, &extra) != 3 ||
                (x != 'x' && x != 'X') || !(bx > 0) || !(by > 0) || bx > 10000 || by > 10000)
                return fail(fmt::format(
                    "--bed: expected WIDTHxDEPTH in mm such as 250x210, got '{}'", bed_text));
            settings.bed_x = bx, settings.bed_y = by;
        }
        if (no_bed_check) settings.bed_check = false;
        if (settings.layer_height > settings.nozzle)
            return fail(fmt::format("--layer-height {} mm is thicker than the {} mm line width",
                                    settings.layer_height, settings.nozzle));

        run.progress = !quiet;
        run.progress_bar = isatty(STDERR_FILENO);  // plain lines into a log or a pipe
        run.note = [quiet](const std::string& s) {
            if (!quiet) std::fprintf(stderr, "carve: warning: %s\n", s.c_str());
        };
        const carve::RunResult result = carve::run_slice(settings, run);
        if (!stats_path.empty())
            write_text_atomically(stats_path, carve::stats_json(result, settings).dump(2) + "\n");
        if (!quiet) {
            std::cout << carve::summary_text(result, settings);
            std::cout << "G-code     " << run.gcode_path << "\n";
            if (!stats_path.empty()) std::cout << "stats      " << stats_path << "\n";
            if (!run.report_path.empty()) std::cout << "report     " << run.report_path << "\n";
            if (!run.svg_dir.empty()) std::cout << "layers     " << run.svg_dir << "/\n";
            if (!run.raster_dir.empty()) std::cout << "raster     " << run.raster_dir << "/\n";
        }
        return 0;
    } catch (const carve::InputError& e) {
        return fail(e.what());
    } catch (const std::bad_alloc&) {
        return fail("out of memory");
    } catch (const std::exception& e) {
        return fail(fmt::format("internal error: {}", e.what()));
    }
}
