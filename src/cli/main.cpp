// carve command line: parses options into Settings and calls the library. Nothing else.
//
// Errors come out as one line on stderr with the exit status of their kind (base/errors.hpp):
// 1 bad input or option value, 2 usage, 3 an output not written or refused, 4 internal. No
// partial output is ever left behind (every output goes through base/atomic_file.hpp).
// The options of `slice` that set a setting are made from the settings table
// (config/setting_table.hpp): a new setting is one entry there, not an option here. The other
// options are rows of cli/options.hpp; the settings' precedence is config/resolve.hpp's.
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

#include "base/atomic_file.hpp"
#include "base/error.hpp"
#include "base/numbers.hpp"
#include "base/output_paths.hpp"
#include "check/gcode_analysis.hpp"
#include "check/mesh_offset.hpp"
#include "check/strength.hpp"
#include "cli/options.hpp"
#include "config/presets.hpp"
#include "config/resolve.hpp"
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

using carve::cli::CheckCommand;
using carve::cli::InfoCommand;
using carve::cli::OptionRow;
using carve::cli::SliceCommand;

// One row of cli/options.hpp as a CLI11 option bound to its member of `command`.
template <class Command>
void add_row(CLI::App& app, const OptionRow<Command>& row, Command& command) {
    std::visit(
        [&](auto* member) {
            using T = std::remove_pointer_t<decltype(member)>;
            CLI::Option* o = nullptr;
            if constexpr (std::is_same_v<T, bool>) {
                o = app.add_flag(row.names, *member, row.help);
            } else {
                o = app.add_option(row.names, *member, row.help);
                if constexpr (std::is_arithmetic_v<T>)
                    o->check(strict(row.min, row.max, row.unit, std::is_integral_v<T>));
                else if (!row.choices.empty())
                    o->check(CLI::IsMember(row.choices));
            }
            if (row.required) o->required();
        },
        row.target(command));
}

// The setting table's options: each typed one is kept as typed, to be applied in
// resolve_settings() after the printer, the profile and the preset.
void add_settings(CLI::App& slice, SliceCommand& c) {
    for (const carve::SettingSpec& spec : carve::setting_table()) {
        if (!*spec.option) continue;  // a profile key without an option of its own
        if (spec.is_switch()) {
            auto& [option, on] = c.switches[&spec];
            option = slice.add_flag(spec.cli_switch_names(), on, spec.help);
            continue;
        }
        auto& given = c.given.options;
        CLI::Option* o = slice.add_option_function<std::string>(
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
}

CLI::App* add_slice(CLI::App& app, SliceCommand& c) {
    CLI::App* slice = app.add_subcommand("slice", "Slice MODEL into hollow G-code (the main job)");
    for (const OptionRow<SliceCommand>& row : carve::cli::slice_rows()) {
        if (row.names == carve::cli::kSettingsHere)
            add_settings(*slice, c);
        else
            add_row(*slice, row, c);
    }
    return slice;
}

template <class Command>
CLI::App* add_command(CLI::App& app, const char* name, const char* description,
                      const std::vector<OptionRow<Command>>& rows, Command& c) {
    CLI::App* sub = app.add_subcommand(name, description);
    for (const OptionRow<Command>& row : rows) add_row(*sub, row, c);
    return sub;
}

int info_command(const InfoCommand& c) {
    carve::MeshReport report;
    carve::load_mesh(c.model, report);
    if (c.json)
        std::cout << carve::to_json(report).dump(2) << "\n";
    else
        std::cout << carve::describe(report);
    return 0;
}

int check_command(CheckCommand& c, const CLI::App& check) {
    if (check.count("--filament-diameter")) c.analysis.filament_diameter_from_header = false;
    if (c.timeout_s > 0) carve::exit_after(c.timeout_s);
    std::optional<carve::Vec3> offset;
    if (!c.mesh_offset.empty()) offset = carve::parse_mesh_offset(c.mesh_offset);
    for (const char* o : {"--voxel-size", "--max-voxels", "--material-law", "--filament-density"})
        if (!c.strength && check.count(o))
            return fail(fmt::format("{} needs --strength", o), carve::kExitUsage);
    std::unique_ptr<carve::StrengthMeter> meter;
    if (c.strength) {
        if (c.law == "cubic") c.strength_options.solver.law = carve::check::MaterialLaw::kCubic;
        meter = std::make_unique<carve::StrengthMeter>(c.strength_options);
        c.analysis.untyped_is_object = !carve::has_type_comments(c.gcode);
        c.analysis.object_layer = [&meter](double z, double h, const carve::Paths& f, double v) {
            meter->layer(z, h, f, v);
        };
    }
    carve::GcodeAnalysis a;
    if (!c.mesh.empty()) {
        carve::MeshReport report;
        // The same refusals as carve slice: a soup would be sliced at every layer.
        carve::LoadOptions load_options;
        load_options.refuse_soup = true;
        const carve::Mesh mesh = carve::load_mesh(c.mesh, report, load_options);
        a = carve::analyse_gcode_on_mesh(c.gcode, mesh, c.analysis, offset);
        // The outer wall's centre lies half a line width inside: a few tenths of a mm.
        if (a.mesh_extent_mismatch_mm > 2)
            std::fprintf(stderr,
                         "carve: warning: the G-code's extent differs from the mesh's by "
                         "%.1f mm: is the mesh at the print's scale?\n",
                         a.mesh_extent_mismatch_mm);
    } else {
        if (offset) return fail("--mesh-offset needs --mesh");
        if (c.strict) return fail("--strict needs --mesh", carve::kExitUsage);
        a = carve::analyse_gcode(c.gcode, c.analysis);
    }
    std::optional<carve::StrengthFigures> strength;
    if (meter) strength = meter->finish();
    if (c.json) {
        nlohmann::json j = carve::to_json(a, c.layers);
        if (strength) j["strength"] = carve::to_json(*strength);
        std::cout << j.dump(2) << "\n";
    } else {
        std::cout << carve::describe(a);
        if (c.layers) std::cout << "\n" << carve::describe_layers(a);
        if (strength) std::cout << "\n" << carve::describe_strength(*strength, c.layers);
    }
    if (c.strict) {
        const std::vector<std::string> failed = carve::failed_rules(a);
        for (const std::string& f : failed)
            std::fprintf(stderr, "carve: check: fails: %s\n", f.c_str());
        if (!failed.empty()) return carve::kExitRuleFailed;
    }
    return 0;
}

// Placeholders of the custom G-code that carve cannot evaluate: said once, up front.
void note_custom_gcode(const carve::Settings& settings, bool quiet) {
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
}

// The settings in their precedence (config/resolve.hpp); the model is read for --strong only.
carve::Settings slice_settings(SliceCommand& c, const CLI::App& slice) {
    // Given, even empty: "" once meant generic silently.
    if (slice.count("--printer") > 0) c.given.printer = c.printer;
    for (const auto& [spec, option_on] : c.switches)
        if (option_on.first->count() > 0)
            c.given.options.emplace_back(spec, option_on.second ? "1" : "0");
    // The split between ties and shells is the model's as loaded (before --orient auto).
    const auto slenderness = [&c] {
        carve::MeshReport report;
        carve::LoadOptions load_options;
        load_options.refuse_soup = true;
        carve::load_mesh(c.run.model_path, report, load_options);
        return carve::slenderness(report.bbox.max.z - report.bbox.min.z, report.volume_mm3);
    };
    carve::ResolvedSettings resolved = carve::resolve_settings(c.given, slenderness);
    for (const std::string& n : resolved.notes)
        if (!c.quiet) std::fprintf(stderr, "carve: note: %s\n", n.c_str());
    note_custom_gcode(resolved.settings, c.quiet);
    carve::validate_settings(resolved.settings);
    return std::move(resolved.settings);
}

void print_slice_summary(const carve::RunOptions& run, const carve::Settings& settings,
                         const carve::RunResult& result) {
    std::cout << carve::summary_text(result, settings);
    std::cout << "G-code     " << run.gcode_path << "\n";
    if (!run.stats_path.empty()) std::cout << "stats      " << run.stats_path << "\n";
    if (!run.report_path.empty()) std::cout << "report     " << run.report_path << "\n";
    if (!run.svg_dir.empty()) std::cout << "layers     " << run.svg_dir << "/\n";
    if (!run.raster_dir.empty()) std::cout << "raster     " << run.raster_dir << "/\n";
}

void print_cut_summary(const carve::RunOptions& run, const carve::Settings& settings,
                       const carve::CutRunResult& cut) {
    std::cout << cut.pieces << " pieces on " << cut.plates.size() << " plates\n";
    for (size_t p = 0; p < cut.plates.size(); ++p)
        std::cout << "plate " << p + 1 << ":\n"
                  << carve::summary_text(cut.plates[p], settings) << "G-code     "
                  << cut.gcode_paths[p] << "\n";
    for (const std::string& m : cut.mesh_paths) std::cout << "mesh       " << m << "\n";
    std::cout << "pieces     " << cut.picture_path << "\n";
    if (!run.stats_path.empty()) std::cout << "stats      " << run.stats_path << "\n";
}

int slice_command(SliceCommand& c, const CLI::App& slice) {
    const carve::Settings settings = slice_settings(c, slice);
    carve::RunOptions& run = c.run;
    if (run.plate_meshes && !settings.cutting())
        return fail("--plate-meshes needs --cut or --cut-plane", carve::kExitUsage);
    // Nothing the run writes may be one of its inputs, another of its outputs, or a device.
    carve::check_output_paths(
        {{run.model_path, "the model"}, {c.given.profile_path, "the profile"}},
        {{run.gcode_path, "-o"},
         {run.stats_path, "--stats"},
         {run.report_path, "--report"},
         {run.svg_dir, "--svg-layers", true},
         {run.raster_dir, "--raster", true}});
    if (g_parse_only) return 0;
    if (c.timeout_s > 0) carve::exit_after(c.timeout_s);

    const bool quiet = c.quiet;
    run.progress = !quiet;
    run.progress_bar = isatty(STDERR_FILENO);  // plain lines into a log or a pipe
    run.note = [quiet](const std::string& s) {
        if (!quiet) std::fprintf(stderr, "carve: warning: %s\n", s.c_str());
    };
    if (settings.cutting()) {
        const carve::CutRunResult cut = carve::run_cut(settings, run);
        if (!quiet) print_cut_summary(run, settings, cut);
        return 0;
    }
    const carve::RunResult result = carve::run_slice(settings, run);
    if (!quiet) print_slice_summary(run, settings, result);
    return 0;
}

// CLI11's outcome of the parse as carve's exit status, or nothing when the command may run.
std::optional<int> parse(CLI::App& app, int argc, char** argv) {
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
    return std::nullopt;
}

int run(int argc, char** argv) {
    // Past a file size limit (ulimit -f) the write fails with EFBIG and the writer cleans up and
    // says so; the default action of SIGXFSZ would kill the process and leave its temporary file.
    std::signal(SIGXFSZ, SIG_IGN);
    CLI::App app{
        "carve: slices a mesh into G-code that prints it hollow, with nested "
        "self-supporting cavities instead of infill"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "carve 0.1.0");

    SliceCommand slice_options;
    InfoCommand info_options;
    CheckCommand check_options;
    CLI::App* slice = add_slice(app, slice_options);
    CLI::App* info = add_command(app, "info", "Describe a mesh: size, volume, closedness",
                                 carve::cli::info_rows(), info_options);
    CLI::App* check = add_command(app, "check",
                                  "Measure material and unsupported extrusion of any G-code file "
                                  "(carve's, PrusaSlicer's, Cura's)",
                                  carve::cli::check_rows(), check_options);
    if (const std::optional<int> parsed = parse(app, argc, argv)) return *parsed;

    try {
        if (g_parse_only && (*info || *check)) return 0;
        if (*info) return info_command(info_options);
        if (*check) return check_command(check_options, *check);
        return slice_command(slice_options, *slice);
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
