// carve command line: parses options into Settings and calls the library. Nothing else.
//
// Errors come out as one line on stderr with the exit status of their kind (base/errors.hpp):
// 1 bad input or option value, 2 usage, 3 an output not written or refused, 4 internal. No
// partial output is ever left behind (every output goes through base/atomic_file.hpp).
// The options of `slice` that set a setting are made from the settings table
// (config/setting_table.hpp): a new setting is one entry there, not an option here.
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <string_view>
#include <system_error>
#include <vector>

#include "base/atomic_file.hpp"
#include "base/error.hpp"
#include "base/numbers.hpp"
#include "base/output_paths.hpp"
#include "check/gcode_analysis.hpp"
#include "check/strength.hpp"
#include "config/presets.hpp"
#include "config/profiles.hpp"
#include "config/setting_table.hpp"
#include "gcode/placeholders.hpp"
#include "mesh/mesh.hpp"
#include "report/mesh_info.hpp"
#include "report/stats.hpp"
#include "run/pipeline.hpp"

// jemalloc (linked by CMakeLists.txt when installed) reads its options from this symbol. One
// arena: under an address-space limit (ulimit -v) jemalloc crashed creating a new thread's
// arena instead of failing the allocation (the bridges' thread, SIGSEGV in
// pthread_mutex_trylock); with one arena the allocation fails and carve reports "out of
// memory". The run's worker threads are then given arenas of their own, created explicitly
// (run/thread_arenas.hpp): sharing one arena cost 10 % more CPU on 2 cores. Ignored by glibc's
// malloc.
extern "C" {
extern const char* malloc_conf;
const char* malloc_conf = "narenas:1";
}

namespace {

int fail(const std::string& message, int code = carve::kExitBadInput) {
    std::fprintf(stderr, "carve: %s\n", message.c_str());
    return code;
}

// A number option checked as the table's are: decimal only, finite, in [lo, hi] (CLI11's own
// conversion reads "nan", "inf" and "0x10", and NaN passes CLI::Range).
CLI::Validator strict(double lo, double hi, const char* unit, bool integer = false) {
    return CLI::Validator(
        [=](std::string& v) { return carve::range_problem(v, lo, hi, integer, unit); },
        fmt::format("in [{} - {}]", carve::plain_number(lo), carve::plain_number(hi)));
}

// Standard output is an output too: a failed write (a full disk, a closed pipe) is exit 3,
// never a truncated answer with exit 0.
[[maybe_unused]] int checked_stdout(int code) {
    std::cout.flush();
    const bool ok = std::cout.good() && std::fflush(stdout) == 0 && !std::ferror(stdout);
    if (std::fclose(stdout) != 0 || !ok) {
        std::fprintf(stderr, "carve: cannot write standard output: %s\n", std::strerror(errno));
        return code == 0 ? carve::kExitOutput : code;
    }
    return code;
}

int run(int argc, char** argv);

// Set by fuzz/cli_fuzz.cpp only: parse and validate everything, then stop before any job
// reads a model or writes a file.
bool g_parse_only = false;

}  // namespace

#ifndef CARVE_CLI_NO_MAIN
int main(int argc, char** argv) {
    carve::install_cleanup_handlers();
    return checked_stdout(run(argc, argv));
}
#endif

namespace {

int run(int argc, char** argv) {
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
    std::string preset, profile_path, printer_name;
    bool quiet = false;
    double timeout_s = 0;
    // Table options as typed, applied after the printer, the profile and the preset.
    std::vector<std::pair<const carve::SettingSpec*, std::string>> given;
    // Each switch's option and where CLI11 leaves its value: one that was given is added to
    // `given` after parsing (the last of --m73 and --no-m73 wins).
    std::map<const carve::SettingSpec*, std::pair<CLI::Option*, bool>> switches;

    CLI::App* slice = app.add_subcommand("slice", "Slice MODEL into hollow G-code (the main job)");
    slice
        ->add_option("model", run.model_path,
                     "Mesh file: STL (binary or ASCII), OBJ or 3MF; millimetres [required]")
        ->required();
    slice->add_option("-o,--output", run.gcode_path, "G-code file to write [required]")->required();
    slice->add_option("--stats", run.stats_path,
                      "Write the run's figures as JSON to this file [none]");
    slice->add_flag("--stats-check", run.check_output,
                    "Also measure the written G-code as carve check --mesh does (hanging inside "
                    "and overhang, material per type, retractions, travel, thin columns, skins "
                    "left open, the --strict verdict) into the stats' \"check\" and the "
                    "summary [off: it doubles the run time]");
    slice->add_flag("--strict", run.strict,
                    "Measure the G-code as --stats-check does and write nothing (exit status 5, "
                    "the rules failed on stderr) when it fails a rule of carve check --strict; "
                    "with --cut, every plate [off]");
    slice->add_flag(
        "--plate-meshes", run.plate_meshes,
        "With --cut: also write each plate's pieces as a binary STL (-o with -plateN.stl "
        "for its extension), where the plate's G-code prints them, for carve check "
        "--mesh or another slicer [off]");
    slice->add_flag("--stats-strength", run.strength_output,
                    "Also measure the written G-code's strength as carve check --strength does "
                    "(grams, weakest section and bond with their z, compression and shear "
                    "stiffness; 2 mm voxels, linear law) into the stats' \"strength\", the "
                    "summary and the HTML report, which marks the weakest layers [off: it takes "
                    "several times as long as the slicing]");
    slice->add_option("--load", profile_path,
                      "PrusaSlicer .ini profile with printer and filament settings (options given "
                      "on the command line win) [none]");
    carve::ProfileOptions profile_options;
    slice->add_option(
        "--printer-profile", profile_options.choice.printer,
        "With a --load bundle: its [printer:NAME] to use [the bundle's presets section]");
    slice->add_option(
        "--filament-profile", profile_options.choice.filament,
        "With a --load bundle: its [filament:NAME] to use [the bundle's presets section, "
        "else the printer's default_filament_profile]");
    slice->add_option(
        "--print-profile", profile_options.choice.print,
        "With a --load bundle: its [print:NAME] to use [the bundle's presets section, "
        "else the printer's default_print_profile]");
    slice->add_flag("--profile-shells", profile_options.profile_shells,
                    "Take covers and shells from the --load profile's top_solid_layers, "
                    "bottom_solid_layers and perimeters [off: carve's own]");
    CLI::Option* printer_option = slice->add_option(
        "--printer", printer_name,
        "Built-in printer preset: " + carve::printer_preset_names() + " [generic]");
    slice
        ->add_option("--preset", preset,
                     "The report's presets: 2c0s (2 covers, no shell) or 3c1s (3 covers, 1 "
                     "shell); or strong (--strong 1: the report's carving and 4 shells, the "
                     "stiffest for its weight that carve measured) [none: 2 covers, 0 shells]")
        ->check(CLI::IsMember({"2c0s", "3c1s", "strong"}));
    slice->add_option("--report", run.report_path,
                      "Write an HTML report (self-contained) to this file [none]");
    slice->add_option("--svg-layers", run.svg_dir,
                      "Write SVG pictures of some layers into DIR [none]");
    slice
        ->add_option("--svg-every", run.svg_every,
                     "With --svg-layers: every N-th layer, layers [0: eight spread over the "
                     "height]")
        ->check(strict(0, 100000, "layers", true));
    slice->add_option("--raster", run.raster_dir,
                      "Write a PNG slice stack for resin printers, and its zip, into DIR [none]");
    slice
        ->add_option("--raster-pixel", run.raster_pixel_mm,
                     "With --raster: pixel size (the printer's XY resolution), mm [0.05]")
        ->check(strict(0.005, 1.0, "mm"));
    slice
        ->add_option("--raster-min-wall", run.raster_min_wall_mm,
                     "With --raster: thinnest wall the resin printer cures; cavity outlines are "
                     "thickened to it, mm [0.4]")
        ->check(strict(0.01, 10.0, "mm"));
    for (const carve::SettingSpec& spec : carve::setting_table()) {
        if (!*spec.option) continue;  // a profile key without an option of its own
        if (spec.is_switch()) {
            auto& [option, on] = switches[&spec];
            option = slice->add_flag(spec.cli_switch_names(), on, spec.help);
            continue;
        }
        CLI::Option* o = slice->add_option_function<std::string>(
            std::string("--") + spec.option,
            [&given, &spec](const std::string& v) { given.emplace_back(&spec, v); }, spec.help);
        if (!spec.text())
            o->type_name(fmt::format("{} in [{} - {}]", spec.integer() ? "INT" : "FLOAT",
                                     carve::plain_number(spec.min), carve::plain_number(spec.max)));
        else if (!spec.text_field().choices.empty())
            o->check(CLI::IsMember(spec.text_field().choices));
        else
            o->type_name(spec.text_field().type_name);
    }
    slice
        ->add_option("--timeout", timeout_s,
                     "Give up after this much time, removing every output and temporary; "
                     "0 = no limit, seconds [0]")
        ->check(strict(0, 1e7, "seconds"));
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
    check
        ->add_option("--support-radius", check_options.support_radius_mm,
                     "Overhang allowance r, mm [0.2]")
        ->check(strict(0, 100, "mm"));
    check
        ->add_option("--far-radius", check_options.far_radius_mm,
                     "Distance no filament bridges, mm [2]")
        ->check(strict(0.01, 100, "mm"));
    check
        ->add_option("--support-gap", check_options.support_gap_mm,
                     "A support's top this far below the layer under an extrusion holds it too "
                     "(the z gap supports leave), mm [0.2]")
        ->check(strict(0, 10, "mm"));
    check
        ->add_option("--filament-diameter", check_options.filament_diameter_mm,
                     "Filament diameter, mm; given, it wins over the G-code header's "
                     "[the header's, else 1.75]")
        ->check(strict(0.5, 5, "mm"));
    check->add_flag("--json", check_json, "Machine-readable output (JSON) [off: text]");
    double check_timeout_s = 0;
    check
        ->add_option("--timeout", check_timeout_s,
                     "Give up after this much time; 0 = no limit, seconds [0]")
        ->check(strict(0, 1e7, "seconds"));
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
    bool check_strict = false;
    check->add_flag("--strict", check_strict,
                    "With --mesh: exit with status 5 when the G-code fails a printability rule "
                    "(a free-standing thin column over 5 mm, top or bottom skin open over "
                    "0.25 %, over 1 mm2 hanging inside, a piece of the model a line wide left "
                    "unprinted), naming each on stderr [off]");

    bool check_strength = false;
    carve::StrengthOptions strength_options;
    std::string check_law = "linear";
    check->add_flag("--strength", check_strength,
                    "How strong the print is (skirt, brim, supports and custom G-code left "
                    "out): grams, each layer's section (area, second moments) and bond with the "
                    "next, the weakest of each, a voxel finite-element stiffness in compression "
                    "and shear, each per gram [off]");
    check
        ->add_option("--voxel-size", strength_options.voxel_mm,
                     "With --strength: the side of the voxels (finite elements), mm [2]")
        ->check(strict(0.5, 50, "mm"));
    check
        ->add_option("--max-voxels", strength_options.max_voxels,
                     "With --strength: voxels the solver takes at most; above, the voxel is "
                     "doubled until the model fits [40000]")
        ->check(strict(100, 2000000, "voxels", true));
    check
        ->add_option("--material-law", check_law,
                     "With --strength: a voxel's Young's modulus from its filled fraction f: "
                     "linear (E f) or cubic (E f^3) [linear]")
        ->check(CLI::IsMember({"linear", "cubic"}));
    check
        ->add_option("--filament-density", strength_options.density_g_cm3,
                     "With --strength: for the grams (PLA's by default), g/cm^3 [1.24]")
        ->check(strict(0.1, 25, "g/cm^3"));

    std::vector<std::string> profile_notes;
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ValidationError& e) {
        return fail(fmt::format("{} (see carve --help)", e.what()));  // a bad value: 1
    } catch (const CLI::ConversionError& e) {
        return fail(fmt::format("{} (see carve --help)", e.what()));
    } catch (const CLI::ParseError& e) {
        return fail(fmt::format("{} (see carve --help)", e.what()), carve::kExitUsage);
    }

    try {
        if (g_parse_only && (*info || *check)) return 0;
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
            if (check->count("--filament-diameter"))
                check_options.filament_diameter_from_header = false;
            if (check_timeout_s > 0) carve::exit_after(check_timeout_s);
            std::optional<carve::Vec3> offset;
            if (!check_offset.empty()) {
                carve::Vec3 o{0, 0, std::numeric_limits<double>::quiet_NaN()};  // z: on the bed
                // Each part a plain decimal within the bed's reach (sscanf took "nan", "inf"
                // and hexadecimal).
                std::vector<std::optional<double>> parts;
                for (size_t at = 0;;) {
                    const size_t comma = check_offset.find(',', at);
                    const auto v =
                        carve::parse_decimal(std::string_view(check_offset).substr(at, comma - at));
                    parts.push_back(v && std::abs(*v) <= 1e5 ? v : std::nullopt);
                    if (comma == std::string::npos) break;
                    at = comma + 1;
                }
                const bool good = (parts.size() == 2 || parts.size() == 3) &&
                                  std::all_of(parts.begin(), parts.end(),
                                              [](const auto& v) { return v.has_value(); });
                if (!good)
                    return fail(fmt::format(
                        "--mesh-offset: expected X,Y or X,Y,Z in mm (decimal, at most 100000), "
                        "got '{}'",
                        check_offset));
                o.x = *parts[0], o.y = *parts[1];
                if (parts.size() == 3) o.z = *parts[2];
                offset = o;
            }
            for (const char* o :
                 {"--voxel-size", "--max-voxels", "--material-law", "--filament-density"})
                if (!check_strength && check->count(o))
                    return fail(fmt::format("{} needs --strength", o), carve::kExitUsage);
            std::unique_ptr<carve::StrengthMeter> meter;
            if (check_strength) {
                if (check_law == "cubic")
                    strength_options.solver.law = carve::check::MaterialLaw::kCubic;
                meter = std::make_unique<carve::StrengthMeter>(strength_options);
                check_options.untyped_is_object = !carve::has_type_comments(check_gcode);
                check_options.object_layer = [&meter](double z, double h, const carve::Paths& f,
                                                      double v) { meter->layer(z, h, f, v); };
            }
            carve::GcodeAnalysis a;
            if (!check_mesh.empty()) {
                carve::MeshReport report;
                // The same refusals as carve slice: a soup would be sliced at every layer.
                carve::LoadOptions load_options;
                load_options.refuse_soup = true;
                const carve::Mesh mesh = carve::load_mesh(check_mesh, report, load_options);
                a = carve::analyse_gcode_on_mesh(check_gcode, mesh, check_options, offset);
                // The outer wall's centre lies half a line width inside: a few tenths of a mm.
                if (a.mesh_extent_mismatch_mm > 2)
                    std::fprintf(stderr,
                                 "carve: warning: the G-code's extent differs from the mesh's by "
                                 "%.1f mm: is the mesh at the print's scale?\n",
                                 a.mesh_extent_mismatch_mm);
            } else {
                if (offset) return fail("--mesh-offset needs --mesh");
                if (check_strict) return fail("--strict needs --mesh", carve::kExitUsage);
                a = carve::analyse_gcode(check_gcode, check_options);
            }
            std::optional<carve::StrengthFigures> strength;
            if (meter) strength = meter->finish();
            if (check_json) {
                nlohmann::json j = carve::to_json(a, check_layers);
                if (strength) j["strength"] = carve::to_json(*strength);
                std::cout << j.dump(2) << "\n";
            } else {
                std::cout << carve::describe(a);
                if (check_layers) std::cout << "\n" << carve::describe_layers(a);
                if (strength)
                    std::cout << "\n" << carve::describe_strength(*strength, check_layers);
            }
            if (check_strict) {
                const std::vector<std::string> failed = carve::failed_rules(a);
                for (const std::string& f : failed)
                    std::fprintf(stderr, "carve: check: fails: %s\n", f.c_str());
                if (!failed.empty()) return carve::kExitRuleFailed;
            }
            return 0;
        }

        // Precedence: built-in printer, then profile file, then preset, then explicit options;
        // the options were only collected while parsing, so they are applied last and win.
        // Given, even empty: "" once meant generic silently.
        if (printer_option->count() > 0) carve::apply_printer_preset(printer_name, settings);
        if (profile_path.empty() &&
            (!profile_options.choice.printer.empty() || !profile_options.choice.filament.empty() ||
             !profile_options.choice.print.empty() || profile_options.profile_shells))
            return fail(
                "--printer-profile, --filament-profile, --print-profile and "
                "--profile-shells need --load",
                carve::kExitUsage);
        if (!profile_path.empty())
            profile_notes = carve::load_prusa_profile(profile_path, settings, profile_options);
        if (!preset.empty()) carve::apply_print_preset(preset, settings);
        for (const auto& [spec, option_on] : switches)
            if (option_on.first->count() > 0)
                given.emplace_back(spec, option_on.second ? "1" : "0");
        for (const auto& [spec, text] : given)
            spec->set(settings, text, std::string("--") + spec->option);
        {
            // --strong moves shells and ties, but not those typed on the command line.
            const auto typed = [&given](std::string_view option) {
                return std::any_of(given.begin(), given.end(),
                                   [&](const auto& g) { return option == g.first->option; });
            };
            // The split between ties and shells follows the model's slenderness, which no
            // scale changes; it is the model's as loaded (before --orient auto turns it).
            double slender = 0;
            if (settings.strength > 0) {
                carve::MeshReport report;
                carve::LoadOptions load_options;
                load_options.refuse_soup = true;
                carve::load_mesh(run.model_path, report, load_options);
                slender =
                    carve::slenderness(report.bbox.max.z - report.bbox.min.z, report.volume_mm3);
            }
            carve::apply_strength(settings, slender, typed("shells"), typed("ties"));
        }
        // Only once every option is in: --carving may come after an option of its scheme.
        for (const auto& given_option : given) carve::check_scheme(*given_option.first, settings);
        for (const std::string& n : profile_notes)
            if (!quiet) std::fprintf(stderr, "carve: note: %s\n", n.c_str());
        // Placeholders of the custom G-code that carve cannot evaluate: said once, up front.
        const std::map<std::string, double> at_end{
            {"max_layer_z", 0}, {"layer_z", 0}, {"layer_num", 0}};
        for (const auto& [name, text] :
             {std::pair{"start_gcode", &settings.start_gcode},
              std::pair{"end_gcode", &settings.end_gcode},
              std::pair{"start_filament_gcode", &settings.start_filament_gcode},
              std::pair{"end_filament_gcode", &settings.end_filament_gcode},
              std::pair{"before_layer_gcode", &settings.before_layer_gcode},
              std::pair{"layer_gcode", &settings.layer_gcode}})
            try {
                const carve::ExpandedGcode g = carve::expand_custom_gcode(*text, settings, at_end);
                for (const std::string& u : g.unresolved)
                    if (!quiet) std::fprintf(stderr, "carve: note: %s: %s\n", name, u.c_str());
                for (const std::string& u : g.notes)
                    if (!quiet) std::fprintf(stderr, "carve: note: %s: %s\n", name, u.c_str());
            } catch (const carve::InputError& e) {
                throw carve::InputError(fmt::format("{}: {}", name, e.what()));
            }

        carve::validate_settings(settings);
        if (run.plate_meshes && !settings.cutting())
            return fail("--plate-meshes needs --cut or --cut-plane", carve::kExitUsage);
        // Nothing the run writes may be one of its inputs, another of its outputs, or a device.
        carve::check_output_paths({{run.model_path, "the model"}, {profile_path, "the profile"}},
                                  {{run.gcode_path, "-o"},
                                   {run.stats_path, "--stats"},
                                   {run.report_path, "--report"},
                                   {run.svg_dir, "--svg-layers", true},
                                   {run.raster_dir, "--raster", true}});
        if (g_parse_only) return 0;
        if (timeout_s > 0) carve::exit_after(timeout_s);

        run.progress = !quiet;
        run.progress_bar = isatty(STDERR_FILENO);  // plain lines into a log or a pipe
        run.note = [quiet](const std::string& s) {
            if (!quiet) std::fprintf(stderr, "carve: warning: %s\n", s.c_str());
        };
        if (settings.cutting()) {
            const carve::CutRunResult cut = carve::run_cut(settings, run);
            if (!quiet) {
                std::cout << cut.pieces << " pieces on " << cut.plates.size() << " plates\n";
                for (size_t p = 0; p < cut.plates.size(); ++p)
                    std::cout << "plate " << p + 1 << ":\n"
                              << carve::summary_text(cut.plates[p], settings) << "G-code     "
                              << cut.gcode_paths[p] << "\n";
                for (const std::string& m : cut.mesh_paths) std::cout << "mesh       " << m << "\n";
                std::cout << "pieces     " << cut.picture_path << "\n";
                if (!run.stats_path.empty()) std::cout << "stats      " << run.stats_path << "\n";
            }
            return 0;
        }
        const carve::RunResult result = carve::run_slice(settings, run);
        if (!quiet) {
            std::cout << carve::summary_text(result, settings);
            std::cout << "G-code     " << run.gcode_path << "\n";
            if (!run.stats_path.empty()) std::cout << "stats      " << run.stats_path << "\n";
            if (!run.report_path.empty()) std::cout << "report     " << run.report_path << "\n";
            if (!run.svg_dir.empty()) std::cout << "layers     " << run.svg_dir << "/\n";
            if (!run.raster_dir.empty()) std::cout << "raster     " << run.raster_dir << "/\n";
        }
        return 0;
    } catch (const carve::CarveError& e) {
        return fail(e.what(), e.exit_code());
    } catch (const std::bad_alloc&) {
        return fail("out of memory", carve::kExitInternal);
    } catch (const std::system_error& e) {
        // A thread that cannot start (EAGAIN) under a memory or process limit.
        if (e.code() == std::errc::resource_unavailable_try_again)
            return fail("out of memory (cannot start a thread)", carve::kExitInternal);
        return fail(fmt::format("internal error: {}", e.what()), carve::kExitInternal);
    } catch (const std::exception& e) {
        return fail(fmt::format("internal error: {}", e.what()), carve::kExitInternal);
    }
}

}  // namespace
