// Runs the stages in order and gathers the figures of the run: the writers, the pipeline of
// filters the layers flow through (their tokens in tokens.hpp, their profile in span_log.hpp),
// and what follows the last layer. The mesh and the checks before slicing are in run_setup.cpp,
// the figures summed as the layers come out in layer_figures.cpp.
#include "run/pipeline.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "base/atomic_file.hpp"
#include "base/error.hpp"
#include "base/stage_timer.hpp"
#include "carving/carving.hpp"
#include "gcode/thumbnail.hpp"
#include "geometry/polygon.hpp"
#include "report/html_report.hpp"
#include "report/stats.hpp"
#include "report/svg.hpp"
#include "resin/raster.hpp"
#include "run/layer_figures.hpp"
#include "run/run_setup.hpp"
#include "run/span_log.hpp"
#include "run/thread_arenas.hpp"
#include "run/tokens.hpp"
#include "slice/slicer.hpp"
#include "supports/bridges.hpp"
#include "supports/overhang.hpp"
#include "supports/ribs.hpp"
#include "supports/support_volume.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

double peak_memory_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes
}

namespace {

void progress_bar(int done, int total, double elapsed_s) {
    const int width = 30;
    const double f = total > 0 ? double(done) / total : 1.0;
    const int filled = static_cast<int>(f * width);
    const double left = f > 0 ? elapsed_s * (1 - f) / f : 0;
    std::fprintf(stderr, "\r[%.*s%*s] %d/%d layers, %.0f s left ", filled,
                 "##############################", width - filled, "", done, total, left);
    if (done == total) std::fputc('\n', stderr);
    std::fflush(stderr);
}

// Without a terminal (a log file, a pipe, a CI job) a redrawn bar would be one long line full
// of carriage returns: plain lines instead.
void progress_line(int done, int total, double elapsed_s) {
    const double f = total > 0 ? double(done) / total : 1.0;
    const double left = f > 0 ? elapsed_s * (1 - f) / f : 0;
    std::fprintf(stderr, "carve: %d/%d layers (%.0f %%), %.0f s left\n", done, total, 100 * f,
                 left);
    std::fflush(stderr);
}

}  // namespace

int thread_count(const Settings& settings) {
    // oneTBB's default follows the process's CPU affinity mask: under `taskset -c 0` it is 1,
    // where std::thread::hardware_concurrency() still counts every core of the machine.
    return settings.threads > 0 ? settings.threads : tbb::info::default_concurrency();
}

RunResult run_slice(const Settings& settings, const RunOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    auto note = [&](const std::string& s) {
        if (options.note) options.note(s);
    };
    RunResult result;
    std::optional<WallPhases> wall;
    if (profiling_enabled()) {
        profile_geometry();
        wall.emplace();
    }
    auto phase_ends = [&](const char* name) {
        if (wall) wall->mark(name);
    };
    const int64_t load_start_ns = thread_cpu_ns();  // the main thread alone until the pipeline

    RunMesh run_mesh = load_run_mesh(settings, options, result, note);
    phase_ends("load");
    Mesh& mesh = run_mesh.mesh;
    const BBox3& box = result.mesh.bbox;
    check_run_size(settings, options, box);
    const double offset_x = settings.bed_x / 2 - (box.min.x + box.max.x) / 2;
    const double offset_y = settings.bed_y / 2 - (box.min.y + box.max.y) / 2;
    TopDownSlicer slicer(mesh, settings.layer_height);
    const int layer_count = slicer.layer_count();
    if (layer_count == 0)
        throw InputError(fmt::format("{}: the model is thinner than one layer ({} mm)",
                                     options.model_path, settings.layer_height));
    std::function<void(const Slice&)> check_slice = vertex_limits(settings, options);
    // Every output of the run is complete under a temporary name before any is renamed into
    // place (group.commit_all() at the end); a run failing at any point leaves none of them,
    // and the folders of pictures are written into temporary folders moved in at the end.
    // The group is declared first so that it is destroyed last: the writers it holds back
    // remove their temporaries when an error unwinds this frame.
    OutputGroup group;
    GcodeWriter writer(options.gcode_path, settings, offset_x, offset_y, layer_count);
    writer.commit_with(group);
    label_objects(writer, options, settings, run_mesh, result);
    if (!settings.thumbnails.empty())
        writer.set_thumbnails(thumbnail_blocks(mesh.vertices, mesh.triangles, settings.thumbnails));
    std::unique_ptr<AtomicDir> svg_dir, raster_dir;
    std::unique_ptr<SvgLayerWriter> svg;
    if (!options.svg_dir.empty()) {
        svg_dir = std::make_unique<AtomicDir>(options.svg_dir);
        svg = std::make_unique<SvgLayerWriter>(
            options.svg_every > 0
                ? SvgLayerWriter::every(svg_dir->folder(), options.svg_every)
                : SvgLayerWriter(svg_dir->folder(), SvgLayerWriter::spread(layer_count, 8)));
    }
    std::unique_ptr<HtmlReportWriter> html;
    if (!options.report_path.empty()) {
        html = std::make_unique<HtmlReportWriter>(options.report_path, settings);
        html->commit_with(group);
    }
    if (html) html->set_model_name(options.model_path);
    std::unique_ptr<RasterWriter> raster;
    if (!options.raster_dir.empty()) {
        raster_dir = std::make_unique<AtomicDir>(options.raster_dir);
        const BBox2 footprint{to_units(box.min.x), to_units(box.min.y), to_units(box.max.x),
                              to_units(box.max.y), false};
        raster =
            std::make_unique<RasterWriter>(raster_dir->folder(), settings, footprint,
                                           options.raster_pixel_mm, options.raster_min_wall_mm);
    }

    result.layers = layer_count;
    result.cavity_volume_mm3.assign(sweep_iterations(settings), 0.0);
    result.layer_material_mm3.assign(layer_count, 0.0);
    const double h = settings.layer_height;
    int done = 0;
    double sliced_volume = 0;  // what the slices hold: the model's volume if the mesh is open

    // The layers flow top down through a oneTBB pipeline. Serial in-order filters for what
    // carries state from one slice to the next: the slicer's active set (and the vertex
    // limits, checked in order); the covers' window of 2c+1 slices; handing each layer the
    // carvable region of the one above; one filter per
    // carving iteration, so that the k iterations run as a wavefront (C^j at slice i needs C^j
    // at slice i+1 and V^{j-1} at slice i only: iteration j of one slice overlaps iteration
    // j+1 of the slice above); holding a slice back until the one below is carved (the
    // bridges need it); handing each slice what the slice above prints for the ribs, and the
    // ribs themselves; the writers and sums at the end, in layer order so that every figure
    // and byte is the same whatever the thread count. Between them parallel filters do what
    // depends on its own slice or window only: chaining each plane's segments into its slice,
    // the erosions of each slice, the covers of each
    // layer, before each carving iteration what it can do from V^{j-1} alone (its medial
    // axis, its whole-width test: most of its work), then bridges (against a copy of the slice
    // below as the sweep left it), the ribs' booleans with the slice above, toolpaths (the
    // ribs' pieces clipped first), their G-code spill encoding, material, SVG and resin images.
    const int k = sweep_iterations(settings);
    const int c = std::max(0, settings.covers);
    const int kSlice = 0, kChain = 1, kCheck = 2, kErode = 3, kWindow = 4, kCovers = 5, kLink = 6;
    auto k_seed = [](int j) { return kLink + 1 + 2 * j; };  // iteration j + 1, parallel half
    auto k_sweep = [](int j) { return kLink + 2 + 2 * j; };
    const int kHold = kLink + 1 + 2 * k, kSupport = kHold + 1, kWork = kSupport + 1;
    const int kRibLink = kWork + 1, kRibOverlap = kRibLink + 1, kRibs = kRibOverlap + 1;
    const int kPaths = kRibs + 1, kSink = kPaths + 1;
    const int filter_count = kSink + 1;
    // The slicer's tokens, then c + 1 that flush the window (c layers) and the hold-back.
    SpanLog span(profiling_enabled() ? layer_count + c + 1 : 0, filter_count);
    span.serial.assign(filter_count, true);
    span.serial[kErode] = span.serial[kCovers] = span.serial[kWork] = span.serial[kPaths] = false;
    span.serial[kRibOverlap] = span.serial[kChain] = false;
    for (int j = 0; j < k; ++j) span.serial[k_seed(j)] = false;

    // Supports are decided from above too; a layer's support needs the outlines of the z gap's
    // layers below it, so the support filter holds that many layers back (and as many more end
    // tokens flush it). Without supports the filter is not in the chain at all.
    const bool supporting = settings.support != SupportMode::None;
    const int support_lag = supporting ? std::max(0, settings.support_gap_layers()) : 0;
    int next_seq = 0, ends_left = c + 1 + support_lag;
    TokenPool pool;  // before the filters and their state: freed after them
    auto source = tbb::make_filter<void, TokenPtr>(tbb::filter_mode::serial_in_order,
                                                   [&](tbb::flow_control& fc) -> TokenPtr {
                                                       TokenPtr t = pool.make();
                                                       t->seq = next_seq++;
                                                       SpanTimer timer(span, t->seq, kSlice);
                                                       if (auto cut = slicer.next_cut()) {
                                                           t->cut = std::move(*cut);
                                                       } else if (ends_left-- > 0) {
                                                           t->end = true;
                                                       } else {
                                                           fc.stop();
                                                           return pool.drop(t);
                                                       }
                                                       return t;
                                                   });
    // The plane's segments into contours: the slicer's work but for the active set.
    auto chain_cut = tbb::make_filter<TokenPtr, TokenPtr>(tbb::filter_mode::parallel,
                                                          [&](TokenPtr t) -> TokenPtr {
                                                              if (!t->cut) return t;
                                                              SpanTimer timer(span, t->seq, kChain);
                                                              t->slice = std::move(*t->cut).chain();
                                                              t->cut.reset();
                                                              return t;
                                                          });
    auto check = tbb::make_filter<TokenPtr, TokenPtr>(tbb::filter_mode::serial_in_order,
                                                      [&](TokenPtr t) -> TokenPtr {
                                                          if (!t->slice || !check_slice) return t;
                                                          SpanTimer timer(span, t->seq, kCheck);
                                                          check_slice(*t->slice);
                                                          return t;
                                                      });
    auto erode = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::parallel, [&](TokenPtr t) -> TokenPtr {
            if (!t->slice) return t;
            SpanTimer timer(span, t->seq, kErode);
            t->cover =
                std::make_shared<const CoverSlice>(cover_slice(std::move(*t->slice), settings));
            t->slice.reset();
            return t;
        });
    // Layer i is ready once slice i - c is in (or the slicer is done); the token that brought
    // that slice carries layer i on, with the window's slices shared, not copied.
    std::deque<std::shared_ptr<const CoverSlice>> window;  // top down
    int next_layer = layer_count - 1;
    auto gather = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::serial_in_order, [&](TokenPtr t) -> TokenPtr {
            SpanTimer timer(span, t->seq, kWindow);
            if (t->cover) window.push_back(std::move(t->cover));
            const bool ready =
                next_layer >= 0 && (t->end || window.back()->slice.index <= next_layer - c);
            if (!ready) return t->end ? t : pool.drop(t);
            const int i = next_layer--;
            while (!window.empty() && window.front()->slice.index > i + c) window.pop_front();
            t->end = false;
            t->layer.index = i;
            t->window.assign(window.begin(), window.end());
            return t;
        });
    auto covers = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::parallel, [&](TokenPtr t) -> TokenPtr {
            if (!t || t->end) return t;
            SpanTimer timer(span, t->seq, kCovers);
            std::vector<const CoverSlice*> slices;
            for (const auto& e : t->window) slices.push_back(e.get());
            t->layer = carvable_layer(t->layer.index, slices, settings);
            t->window.clear();
            if (k > 0) t->carvable = std::make_shared<const Paths>(t->layer.carvable);
            return t;
        });
    // The whole-width test of a carving iteration reads O'_{i+1} (what of a part lies under
    // the model's surface in the slice above).
    std::shared_ptr<const Paths> carvable_above;
    auto link = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::serial_in_order, [&](TokenPtr t) -> TokenPtr {
            if (!t || t->end) return t;
            SpanTimer timer(span, t->seq, kLink);
            t->carvable_above = std::exchange(carvable_above, std::move(t->carvable));
            return t;
        });
    tbb::filter<void, TokenPtr> chain = source & chain_cut & check & erode & gather & covers & link;
    // Each iteration in two filters: the half that reads only V^{j-1}_i, on any thread, then
    // the half that needs C^j_{i+1}, in order.
    std::vector<std::unique_ptr<CarvingSweep>> sweeps(k);
    for (int j = 0; j < k; ++j) {
        sweeps[j] = std::make_unique<CarvingSweep>(settings, j, 1);
        chain = chain &
                tbb::make_filter<TokenPtr, TokenPtr>(tbb::filter_mode::parallel,
                                                     [&, j](TokenPtr t) -> TokenPtr {
                                                         if (!t || t->end) return t;
                                                         SpanTimer timer(span, t->seq, k_seed(j));
                                                         t->prep = sweeps[j]->prepare(
                                                             t->layer, t->carvable_above.get());
                                                         return t;
                                                     }) &
                tbb::make_filter<TokenPtr, TokenPtr>(
                    tbb::filter_mode::serial_in_order, [&, j](TokenPtr t) -> TokenPtr {
                        if (!t || t->end) return t;
                        SpanTimer timer(span, t->seq, k_sweep(j));
                        sweeps[j]->carve(t->layer, std::move(*t->prep));
                        t->prep.reset();
                        if (j == k - 1) t->carvable_above.reset();
                        return t;
                    });
    }
    TokenPtr held = nullptr;  // slice i + 1, waiting for slice i
    auto hold = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::serial_in_order, [&](TokenPtr t) -> TokenPtr {
            if (!t) return t;
            TokenPtr out = std::exchange(held, nullptr);
            SpanTimer timer(span, out ? out->seq : t->seq, kHold);
            // Slice i is carved: from here on its partition is only read, by its own later
            // stages and, at once, by the bridges of slice i + 1.
            if (!t->end)
                t->record.carved = std::make_shared<const LayerPartition>(std::move(t->layer));
            if (out && !t->end) out->below = t->record.carved;
            // The end tokens after the first flush the support filter's hold-back (there are
            // none more without supports).
            if (t->end && !out) return t;
            held = t->end ? pool.drop(t) : t;
            return out;  // null for the top slice's token: nothing to release yet
        });
    std::unique_ptr<ModelShadow> shadow;
    if (settings.support == SupportMode::Buildplate)
        shadow = std::make_unique<ModelShadow>(mesh.vertices, mesh.triangles, 0.5);
    SupportPlanner planner(support_options(settings, box.min.z), shadow.get());
    std::deque<TokenPtr> support_held;  // top down, waiting for the outlines below them
    auto support = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::serial_in_order, [&](TokenPtr t) -> TokenPtr {
            if (!t) return t;
            SpanTimer timer(span, t->seq, kSupport);
            const bool finished = t->end;
            if (finished) {
                pool.drop(t);
            } else {
                planner.add_outline(t->record.partition().index, t->record.partition().outline);
                support_held.push_back(t);
            }
            if (support_held.empty() ||
                planner.ready(finished) != support_held.front()->record.partition().index)
                return nullptr;
            TokenPtr out = support_held.front();
            support_held.pop_front();
            SupportLayer s = planner.plan(out->record.partition().index);
            out->record.support = {std::move(s.region), std::move(s.interface), std::move(s.walls)};
            out->support_new_mm2 = s.new_mm2;
            return out;
        });
    const BridgeOptions bridging = bridge_options(settings);
    const RibOptions ribbing = rib_options(settings);
    const Coord overhang_reach = settings.support_reach();
    OverhangTally overhangs;
    auto work = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::parallel, [&](TokenPtr t) -> TokenPtr {
            if (!t) return t;
            SpanTimer timer(span, t->seq, kWork);
            // The bottom slice has no slice below: it stands on the bed.
            t->overhang = measure_overhang(t->record.partition().outline,
                                           t->below ? &t->below->outline : nullptr, overhang_reach,
                                           to_units(2.0));
            {
                StageTimer bridges_timer(Stage::kBridges);
                t->record.bridged = bridge_layer(t->record.partition(), t->below.get(), bridging);
            }
            // The ribs' per-slice regions here, in parallel: the serial rib filter then only
            // carries the ribs down.
            t->rib_slice = rib_slice(t->record, ribbing);
            t->below.reset();
            return t;
        });
    // Ribs grow down from what would hang: serial top down, each slice's only after the slices
    // above it (nothing is held back: a rib on slice i depends on slices i and above). Around
    // the serial filter, what reads no rib: the booleans of each slice with the one above (the
    // link hands that down in order) and, in the paths filter, the pieces' clipping.
    RibAbove rib_above;
    auto rib_link = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::serial_in_order, [&](TokenPtr t) -> TokenPtr {
            if (!t) return t;
            SpanTimer timer(span, t->seq, kRibLink);
            RibAbove next{t->record.partition().index > 0,
                          std::make_shared<const Paths>(std::move(t->rib_slice.printed)),
                          t->record.bridged.unheld};
            t->rib_above = std::exchange(rib_above, std::move(next));
            return t;
        });
    auto rib_overlap_filter = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::parallel, [&](TokenPtr t) -> TokenPtr {
            if (!t) return t;
            SpanTimer timer(span, t->seq, kRibOverlap);
            if (ribbing.enabled) rib_overlap(t->rib_slice, t->rib_above);
            t->rib_above = {};
            return t;
        });
    RibPlanner ribs(ribbing);
    auto rib_filter = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::serial_in_order, [&](TokenPtr t) -> TokenPtr {
            if (!t) return t;
            SpanTimer timer(span, t->seq, kRibs);
            t->record.ribs = ribs.add(t->record, t->rib_slice);
            return t;
        });
    auto paths = tbb::make_filter<TokenPtr, TokenPtr>(
        tbb::filter_mode::parallel, [&](TokenPtr t) -> TokenPtr {
            if (!t) return t;
            SpanTimer timer(span, t->seq, kPaths);
            t->record.ribs = clip_ribs(std::move(t->record.ribs), t->rib_slice, ribbing);
            t->rib_slice = {};
            t->paths = plan_layer(t->record, settings);
            if (options.in_parallel_stage) options.in_parallel_stage(t->record.partition().index);
            writer.add_layer(t->paths);  // thread-safe: the spill is indexed by layer
            // Pictures of one layer each, to files of their own (the HTML report stays in the
            // serial filter: it shares a size budget between the layers in the order they come).
            if (svg) svg->add(t->record, &t->paths);
            if (raster) raster->add_layer(t->record);
            t->volumes = extrusion_volumes_mm3(t->paths, settings);
            for (double v : t->volumes) t->material += v;
            return t;
        });
    auto sink =
        tbb::make_filter<TokenPtr, void>(tbb::filter_mode::serial_in_order, [&](TokenPtr t) {
            if (!t) return;
            struct DropAtEnd {
                TokenPool& pool;
                Token* t;
                ~DropAtEnd() { pool.drop(t); }
            } drop_at_end{pool, t};
            SpanTimer timer(span, t->seq, kSink);
            const LayerPartition& layer = t->record.partition();
            for (const std::string& w : layer.warnings) note(w);
            if (html) html->add_layer(t->record, t->paths);
            add_layer_figures(*t, h, result, sliced_volume, overhangs);
            ++done;
            const int tenth = std::max(1, layer_count / 10);
            if (options.progress && options.progress_bar &&
                (done % 10 == 0 || done == layer_count)) {
                const double t_s =
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                progress_bar(done, layer_count, t_s);
            } else if (options.progress && !options.progress_bar &&
                       (done % tenth == 0 || done == layer_count)) {
                const double t_s =
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                progress_line(done, layer_count, t_s);
            }
        });

    const double load_s = double(thread_cpu_ns() - load_start_ns) * 1e-9;
    const int threads = thread_count(settings);
    // Tokens bound the layers in flight, so memory stays flat in the model's height whatever
    // the thread count: room for one layer in each serial filter plus two per thread for the
    // parallel one, whose layers vary tenfold in cost (fandisk's face tops).
    const size_t tokens = size_t(filter_count) + 2 * size_t(threads) + size_t(support_lag);
    phase_ends("setup");
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        tbb::task_arena arena(threads);
        ThreadArenas arenas(arena);
        // An exception in any filter cancels the pipeline; parallel_pipeline waits for the
        // filters still running and rethrows it here, with its type and message, before
        // this frame's stages and writers are destroyed.
        arena.execute([&] {
            if (supporting)
                tbb::parallel_pipeline(tokens, chain & hold & support & work & rib_link &
                                                   rib_overlap_filter & rib_filter & paths & sink);
            else
                tbb::parallel_pipeline(tokens, chain & hold & work & rib_link & rib_overlap_filter &
                                                   rib_filter & paths & sink);
        });
    }
    phase_ends("pipeline");
    for (double v : result.cavity_volume_mm3)
        if (v > 0) ++result.cavities;
    result.external_overhang_mm2 = overhangs.area_mm2();
    result.far_external_overhang_mm2 = overhangs.far_area_mm2();
    if (const std::string w = overhangs.warning(); !w.empty() && !supporting) note(w);
    // An open mesh has no inside of its own: its signed volume depends on where the hole is
    // (a cube missing its top gives 2/3 of the cube), while the slicer closes each slice with
    // non-zero fill. What is printed, and what "% of the model" means, is the sliced volume.
    if (!result.mesh.closed()) result.mesh.volume_mm3 = sliced_volume;

    double material = 0;
    for (double v : result.layer_material_mm3) material += v;
    if (material <= 0)
        throw InputError(fmt::format(
            "{}: nothing to print: every part of the model is thinner than the {} mm line width",
            options.model_path, settings.nozzle));

    std::vector<std::string> header{
        fmt::format("model = {}", options.model_path),
        fmt::format("model_volume_mm3 = {:.1f}", result.mesh.volume_mm3),
        fmt::format("cavities = {}", result.cavities),
    };
    const int64_t finish_start_ns = thread_cpu_ns();
    writer.set_threads(threads);
    result.print = writer.finish(header);
    phase_ends("G-code");
    // The G-code's chunks written side by side are parallel work; the rest of finish() serial.
    const GcodeWriter::ChunkCount chunks = writer.chunk_count();
    double finish_s = double(thread_cpu_ns() - finish_start_ns) * 1e-9;
    finish_s = std::min(finish_s, chunks.serial_cpu_s);
    result.processing_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.check_output) {
        // The mesh is where the slicer had it: moved by the bed offset, its lowest point on z = 0.
        const auto check_start = std::chrono::steady_clock::now();
        GcodeAnalysisOptions check_options;
        check_options.filament_diameter_mm = settings.filament_diameter;
        check_options.keep_layers = false;
        result.check = analyse_gcode_on_mesh(writer.written_path(), mesh, check_options,
                                             Vec3{offset_x, offset_y, -box.min.z});
        result.check_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - check_start).count();
        phase_ends("check");
    }
    const int64_t writers_start_ns = thread_cpu_ns();  // the resin zip and the HTML: serial too
    if (raster) raster->finish();
    result.peak_memory_mb = peak_memory_mb();
    if (html) html->finish(result, stats_json(result, settings));
    if (!options.stats_path.empty())
        write_file_atomically(options.stats_path, stats_json(result, settings).dump(2) + "\n",
                              &group);
    if (svg_dir) group.hold(std::move(svg_dir));
    if (raster_dir) group.hold(std::move(raster_dir));
    group.commit_all();
    phase_ends("outputs");
    finish_s += double(thread_cpu_ns() - writers_start_ns) * 1e-9;
    if (profiling_enabled()) {
        std::vector<std::string> names{"slice",  "chain",  "check", "erode",
                                       "window", "covers", "link"};
        for (int j = 1; j <= k; ++j) {
            names.push_back(fmt::format("seed C{}", j));
            names.push_back(fmt::format("sweep C{}", j));
        }
        names.insert(names.end(), {"hold back", "supports", "bridges", "rib link", "rib overlap",
                                   "ribs", "paths", "writers"});
        std::fputs(profile_table().c_str(), stderr);
        std::fputs(
            span_table(span, names, load_s, finish_s, chunks.parallel_cpu_s, threads).c_str(),
            stderr);
        std::fprintf(stderr,
                     "G-code: %d chunks of layers, %d of them from their second guess, %d "
                     "written again\n",
                     chunks.chunks, chunks.second_guesses, chunks.written_again);
        std::fputs(wall->table().c_str(), stderr);
    }
    return result;
}

}  // namespace carve
