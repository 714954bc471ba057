// run_slice: the run as the list of its stages. The mesh, the checks before slicing and the
// outputs are in run_setup.cpp, the pipeline of filters the layers flow through in
// layer_pipeline.cpp (their tokens in tokens.hpp, their profile in span_log.hpp), the figures
// summed as the layers come out in layer_figures.cpp; what follows the last layer is here.
#include "run/pipeline.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "base/error.hpp"
#include "base/stage_timer.hpp"
#include "carving/carving.hpp"
#include "config/setting_table.hpp"
#include "gcode/gcode.hpp"
#include "report/measure_output.hpp"
#include "report/stats.hpp"
#include "run/layer_pipeline.hpp"
#include "run/orient.hpp"
#include "run/run_setup.hpp"
#include "run/span_log.hpp"
#include "slice/slicer.hpp"

namespace carve {

double peak_memory_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes
}

int thread_count(const Settings& settings) {
    // oneTBB's default follows the process's CPU affinity mask: under `taskset -c 0` it is 1,
    // where std::thread::hardware_concurrency() still counts every core of the machine.
    return settings.threads > 0 ? settings.threads : tbb::info::default_concurrency();
}

namespace {

double cpu_s_since(int64_t start_ns) {
    return double(thread_cpu_ns() - start_ns) * 1e-9;
}

// The run's clocks: its wall time, and under CARVE_PROFILE the wall time of each phase.
struct RunClock {
    explicit RunClock(std::chrono::steady_clock::time_point started) : start(started) {
        if (profiling_enabled()) {
            profile_geometry();
            wall.emplace();
        }
    }
    void phase_ends(const char* name) {
        if (wall) wall->mark(name);
    }
    double elapsed_s() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    const std::chrono::steady_clock::time_point start;
    std::optional<WallPhases> wall;
};

// The run's figures that follow from all its layers.
void add_run_figures(RunResult& result, const LayerPipeline& layers,
                     const std::function<void(const std::string&)>& note) {
    for (double v : result.cavity_volume_mm3)
        if (v > 0) ++result.cavities;
    result.external_overhang_mm2 = layers.overhangs().area_mm2();
    result.far_external_overhang_mm2 = layers.overhangs().far_area_mm2();
    if (const std::string w = layers.overhangs().warning(); !w.empty() && !layers.supporting())
        note(w);
    result.unprinted_mm2 = layers.unprinted().area_mm2();
    result.unprinted_layers = layers.unprinted().layers();
    // An open mesh has no inside of its own: its signed volume depends on where the hole is
    // (a cube missing its top gives 2/3 of the cube), while the slicer closes each slice with
    // non-zero fill. What is printed, and what "% of the model" means, is the sliced volume.
    if (!result.mesh.closed()) result.mesh.volume_mm3 = layers.sliced_volume();
}

void refuse_empty_print(const RunResult& result, const Settings& settings,
                        const RunOptions& options) {
    // The skirt, brim and raft print around and under whatever the first layer holds, however
    // thin the model: they are not a print of it.
    double material = result.remainder_fill_mm3;
    for (size_t f = 0; f < kFeatureCount; ++f)
        if (f != size_t(Feature::Skirt) && f != size_t(Feature::Brim))
            material += result.feature_mm3[f];
    if (material <= 1e-9)
        throw InputError(fmt::format(
            "{}: nothing to print: every part of the model is narrower than {:g} mm, the smallest "
            "part printed (--min-feature-size)",
            options.model_path, settings.min_feature_mm()));
}

// The G-code's header and its layers written out, on `threads` threads.
PrintStats finish_gcode(GcodeWriter& writer, const RunOptions& options, const RunResult& result,
                        const Settings& settings, int threads) {
    std::vector<std::string> header{
        // The file's name, not its path: the folders a user slices from are nobody's business
        // of the printer's or of whoever the G-code is shared with.
        fmt::format("model = {}", std::filesystem::path(options.model_path).filename().string()),
        fmt::format("model_volume_mm3 = {:.1f}", result.mesh.volume_mm3),
        fmt::format("carving_scheme = {}", scheme_name(settings.carving)),
        fmt::format("cavities = {}", result.cavities),
    };
    // Only with --orient auto: a run as given keeps the header it had.
    if (result.orientation)
        header.push_back(fmt::format(
            "orientation = {}",
            describe(result.orientation->trials[result.orientation->chosen].candidate)));
    writer.set_threads(threads);
    return writer.finish(header);
}

// The written G-code measured as `carve check --mesh` does (RunOptions::check_output) and as
// `carve check --strength` does (RunOptions::strength_output), in one reading of it.
void measure_written_gcode(const GcodeWriter& writer, const Mesh& mesh, const Settings& settings,
                           const RunOptions& options, const Placement& place, RunResult& result) {
    OutputMeasure measure;
    measure.check = options.check_output || options.strict;
    measure.strength = options.strength_output;
    measure.analysis.filament_diameter_mm = settings.filament_diameter;
    measure.analysis.keep_layers = false;
    measure.strength_options.density_g_cm3 = settings.filament_density;
    // The mesh is where the slicer had it: moved by the bed offset, its lowest point on z = 0,
    // and raised by --z-offset as every Z written is, and by the raft under it.
    measure_output(writer.written_path(), mesh,
                   Vec3{place.offset_x, place.offset_y,
                        settings.z_offset + settings.model_base_mm() - place.z0},
                   std::move(measure), result);
}

// --strict: the rules carve check --strict applies, before anything is renamed into place.
void refuse_failed_rules(const GcodeAnalysis& check, const RunOptions& options) {
    const std::vector<std::string> failed = failed_rules(check);
    if (failed.empty()) return;
    std::string rules;
    for (const std::string& f : failed) rules += (rules.empty() ? "" : "; ") + f;
    throw RuleError(fmt::format("{}: fails carve check --strict ({}); nothing written",
                                std::filesystem::path(options.gcode_path).filename().string(),
                                rules));
}

// CARVE_PROFILE's tables on stderr: the stages, the pipeline's filters, the G-code's chunks
// and the wall time of each phase.
void print_profile(const LayerPipeline& layers, double load_s, double finish_s,
                   const GcodeWriter::ChunkCount& chunks, int threads, const RunClock& clock) {
    std::fputs(profile_table().c_str(), stderr);
    std::fputs(span_table(layers.span(), layers.filter_names(), load_s, finish_s,
                          chunks.parallel_cpu_s, threads)
                   .c_str(),
               stderr);
    std::fprintf(stderr,
                 "G-code: %d chunks of layers, %d of them from their second guess, %d "
                 "written again\n",
                 chunks.chunks, chunks.second_guesses, chunks.written_again);
    std::fputs(clock.wall->table().c_str(), stderr);
}

}  // namespace

RunResult run_slice(const Settings& settings, const RunOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    const int64_t started_cpu_ns = thread_cpu_ns();  // the main thread alone until the pipeline
    auto note = [&](const std::string& s) {
        if (options.note) options.note(s);
    };
    RunResult result;
    RunMesh run_mesh = load_run_mesh(settings, options, result, note);
    return slice_run_mesh(settings, options, std::move(run_mesh), std::move(result), started,
                          started_cpu_ns);
}

RunResult slice_run_mesh(const Settings& settings, const RunOptions& options, RunMesh run_mesh,
                         RunResult result, std::chrono::steady_clock::time_point started,
                         int64_t started_cpu_ns) {
    RunClock clock(started);
    auto note = [&](const std::string& s) {
        if (options.note) options.note(s);
    };
    const int64_t load_start_ns = started_cpu_ns;
    clock.phase_ends("load");
    check_run_size(settings, options, result.mesh.bbox);
    const Placement place = centre_on_bed(settings, result.mesh.bbox);
    TopDownSlicer slicer(run_mesh.mesh, settings.layer_height, settings.model_layer_mm(0));
    const int layer_count = checked_layer_count(slicer, settings, options);
    check_plane_segments(slicer, settings, options);
    std::function<void(const Slice&)> check_slice = vertex_limits(settings, options);
    RunOutputs outputs(settings, options, run_mesh, result, layer_count, place);
    LayerPipeline layers(settings, options, run_mesh.mesh, place.z0, slicer, std::move(check_slice),
                         outputs, result, clock.start, note);
    const double load_s = cpu_s_since(load_start_ns);
    const int threads = thread_count(settings);
    clock.phase_ends("setup");

    layers.run(threads);
    clock.phase_ends("pipeline");

    add_run_figures(result, layers, note);
    refuse_empty_print(result, settings, options);
    // After the refusal: a model of nothing but such parts gets the one message that says so.
    if (const std::string w = layers.unprinted().warning(settings); !w.empty()) note(w);
    const int64_t finish_start_ns = thread_cpu_ns();
    result.print = finish_gcode(outputs.writer, options, result, settings, threads);
    clock.phase_ends("G-code");
    // The G-code's chunks written side by side are parallel work; the rest of finish() serial.
    const GcodeWriter::ChunkCount chunks = outputs.writer.chunk_count();
    double finish_s = std::min(cpu_s_since(finish_start_ns), chunks.serial_cpu_s);
    result.processing_time_s = clock.elapsed_s();
    if (options.check_output || options.strength_output || options.strict) {
        measure_written_gcode(outputs.writer, run_mesh.mesh, settings, options, place, result);
        clock.phase_ends("check");
    }
    if (options.strict) refuse_failed_rules(*result.check, options);
    const int64_t writers_start_ns = thread_cpu_ns();  // the resin zip and the HTML: serial too
    outputs.finish(result, settings, options);
    clock.phase_ends("outputs");
    finish_s += cpu_s_since(writers_start_ns);
    // The candidates of --orient auto are part of the run that chose among them.
    if (profiling_enabled() && !options.discard_outputs)
        print_profile(layers, load_s, finish_s, chunks, threads, clock);
    return result;
}

}  // namespace carve
