// The filter table, the filters the layers flow through (one member function each, in pipeline
// order), and run(), which chains them as the table lists them (see layer_pipeline.hpp).
#include "run/layer_pipeline.hpp"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdio>
#include <utility>

#include "base/stage_timer.hpp"
#include "report/html_report.hpp"
#include "report/svg.hpp"
#include "resin/raster.hpp"
#include "run/layer_figures.hpp"
#include "run/thread_arenas.hpp"
#include "toolpath/skirt.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

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

// The progress after `done` layers of `layer_count`: every 10 layers on a terminal's bar, every
// tenth of the layers as plain lines; and whenever the last was drawn long enough ago, since a
// tenth of a very tall or very wide model's layers can take many minutes (a 12 m skull within
// the size limits printed nothing for over 300 s). `last` is when the last was drawn.
void report_progress(const RunOptions& options, int done, int layer_count,
                     std::chrono::steady_clock::time_point start,
                     std::chrono::steady_clock::time_point& last) {
    if (!options.progress) return;
    using namespace std::chrono_literals;
    const auto now = std::chrono::steady_clock::now();
    const bool due = options.progress_bar
                         ? (done % 10 == 0 || now - last >= 1s)
                         : (done % std::max(1, layer_count / 10) == 0 || now - last >= 5s);
    if (!due && done != layer_count) return;
    last = now;
    const double t_s = std::chrono::duration<double>(now - start).count();
    if (options.progress_bar)
        progress_bar(done, layer_count, t_s);
    else
        progress_line(done, layer_count, t_s);
}

std::vector<std::unique_ptr<CarvingSweep>> make_sweeps(const Settings& settings, int k) {
    std::vector<std::unique_ptr<CarvingSweep>> sweeps(k);
    for (int j = 0; j < k; ++j) sweeps[j] = std::make_unique<CarvingSweep>(settings, j, 1);
    return sweeps;
}

std::unique_ptr<ModelShadow> make_shadow(const Settings& settings, const Mesh& mesh) {
    if (settings.support != SupportMode::Buildplate) return nullptr;
    return std::make_unique<ModelShadow>(mesh.vertices, mesh.triangles, 0.5);
}

}  // namespace

LayerPipeline::LayerPipeline(const Settings& settings, const RunOptions& options, const Mesh& mesh,
                             double z0, TopDownSlicer& slicer,
                             std::function<void(const Slice&)> check_slice, RunOutputs& outputs,
                             RunResult& result, std::chrono::steady_clock::time_point start,
                             std::function<void(const std::string&)> note)
    : settings_(settings),
      options_(options),
      slicer_(slicer),
      check_slice_(std::move(check_slice)),
      outputs_(outputs),
      result_(result),
      start_(start),
      last_progress_(start),
      note_(std::move(note)),
      layer_count_(slicer.layer_count()),
      k_(sweep_iterations(settings)),
      c_(std::max(0, settings.covers)),
      supporting_(settings.support != SupportMode::None),
      support_lag_(supporting_ ? std::max(0, settings.support_gap_layers()) : 0),
      // The slicer's tokens, then c + 1 that flush the window (c layers) and the hold-back.
      span_(profiling_enabled() ? layer_count_ + c_ + 1 : 0, filter_count()),
      ends_left_(c_ + 1 + support_lag_),
      next_layer_(layer_count_ - 1),
      sweeps_(make_sweeps(settings, k_)),
      shadow_(make_shadow(settings, mesh)),
      planner_(support_options(settings, z0), shadow_.get()),
      bridging_(bridge_options(settings)),
      ribbing_(rib_options(settings)),
      overhang_reach_(settings.support_reach()),
      ribs_(ribbing_) {
    result_.layers = layer_count_;
    result_.cavity_volume_mm3.assign(sweep_iterations(settings), 0.0);
    result_.layer_material_mm3.assign(layer_count_, 0.0);
    for (const Step& s : steps(k_)) span_.serial.push_back(s.filter->serial);
}

// The filters, in pipeline order, and what each does with the token's fields.
std::span<const LayerPipeline::Filter> LayerPipeline::filters() {
    using F = TokenField;
    using P = LayerPipeline;
    constexpr bool serial = true, parallel = false;
    static constexpr Filter kTable[] = {
        {"slice", &P::cut_slice, serial, Filter::Once, F::cut, 0, 0},
        {"chain", &P::chain_cut, parallel, Filter::Once, F::slice, F::cut, F::cut},
        {"check", &P::check_limits, serial, Filter::Once, 0, F::slice, 0},
        {"erode", &P::erode_slice, parallel, Filter::Once, F::cover, F::slice, F::slice},
        // Moves the slice into the window the pipeline keeps, and starts a layer, whose index
        // it sets, on a token of its own.
        {"window", &P::gather_window, serial, Filter::Once, F::window | F::layer, F::cover,
         F::cover},
        {"covers", &P::find_covers, parallel, Filter::Once, F::carvable, F::window | F::layer,
         F::window},
        {"link", &P::link_carvable, serial, Filter::Once, F::carvable_above, F::carvable,
         F::carvable},
        {"seed C", &P::seed_iteration, parallel, Filter::EachIteration, F::prep,
         F::layer | F::carvable_above, 0},
        // The last iteration's frees carvable_above.
        {"sweep C", &P::sweep_iteration, serial, Filter::EachIteration, 0,
         F::layer | F::prep | F::carvable_above, F::prep | F::carvable_above},
        // The carved layer into the record; hands it to the slice above, held back, as `below`.
        {"hold back", &P::hold_back, serial, Filter::Once, F::record | F::below, F::layer,
         F::layer},
        {"supports", &P::plan_supports, serial, Filter::IfSupporting, F::support_new_mm2, F::record,
         0},
        {"bridges", &P::bridge_layer_below, parallel, Filter::Once, F::overhang | F::rib_slice,
         F::record | F::below, F::below},
        {"rib link", &P::link_ribs, serial, Filter::Once, F::rib_above, F::record | F::rib_slice,
         0},
        {"rib overlap", &P::overlap_ribs, parallel, Filter::Once, 0, F::rib_slice | F::rib_above,
         F::rib_above},
        {"ribs", &P::grow_ribs, serial, Filter::Once, 0, F::record | F::rib_slice, 0},
        {"paths", &P::plan_paths, parallel, Filter::Once, F::paths | F::volumes | F::material,
         F::record | F::rib_slice, F::rib_slice},
        {"writers", &P::write_layer, serial, Filter::Once, 0,
         F::record | F::overhang | F::support_new_mm2 | F::paths | F::volumes | F::material, 0},
    };
    static_assert(!lifetime_error(kTable).rule, "the filter table misstates a field's lifetime");
    return kTable;
}

std::vector<LayerPipeline::Step> LayerPipeline::steps(int iterations) {
    const std::span<const Filter> rows = filters();
    std::vector<Step> steps;
    for (size_t i = 0; i < rows.size();) {
        // A run of an iteration's rows, the run once for each iteration.
        size_t end = i + 1;
        const bool each = rows[i].repeat == Filter::EachIteration;
        while (each && end < rows.size() && rows[end].repeat == Filter::EachIteration) ++end;
        for (int j = 0; j < (each ? iterations : 1); ++j)
            for (size_t r = i; r < end; ++r) steps.push_back({&rows[r], {int(steps.size()), j}});
        i = end;
    }
    return steps;
}

std::vector<std::string> LayerPipeline::filter_names(int iterations) {
    std::vector<std::string> names;
    for (const Step& s : steps(iterations))
        names.push_back(s.filter->repeat == Filter::EachIteration
                            ? fmt::format("{}{}", s.filter->name, s.at.j + 1)
                            : std::string(s.filter->name));
    return names;
}

TokenPtr LayerPipeline::cut_slice(At at, TokenPtr) {
    TokenPtr t = pool_.make();
    t->seq = next_seq_++;
    SpanTimer timer(span_, t->seq, at.index);
    if (auto cut = slicer_.next_cut())
        t->cut = std::move(*cut);
    else if (ends_left_-- > 0)
        t->end = true;
    else
        return pool_.drop(t);  // the stream is done
    return t;
}

// The plane's segments into contours: the slicer's work but for the active set.
TokenPtr LayerPipeline::chain_cut(At at, TokenPtr t) {
    if (!t->cut) return t;
    SpanTimer timer(span_, t->seq, at.index);
    t->slice = std::move(*t->cut).chain();
    t->cut.reset();
    return t;
}

TokenPtr LayerPipeline::check_limits(At at, TokenPtr t) {
    if (!t->slice || !check_slice_) return t;
    SpanTimer timer(span_, t->seq, at.index);
    check_slice_(*t->slice);
    return t;
}

TokenPtr LayerPipeline::erode_slice(At at, TokenPtr t) {
    if (!t->slice) return t;
    SpanTimer timer(span_, t->seq, at.index);
    t->cover = std::make_shared<const CoverSlice>(cover_slice(std::move(*t->slice), settings_));
    t->slice.reset();
    return t;
}

TokenPtr LayerPipeline::gather_window(At at, TokenPtr t) {
    SpanTimer timer(span_, t->seq, at.index);
    if (t->cover) window_.push_back(std::move(t->cover));
    const bool ready =
        next_layer_ >= 0 && (t->end || window_.back()->slice.index <= next_layer_ - c_);
    if (!ready) return t->end ? t : pool_.drop(t);
    const int i = next_layer_--;
    while (!window_.empty() && window_.front()->slice.index > i + c_) window_.pop_front();
    t->end = false;
    t->layer.index = i;
    t->window.assign(window_.begin(), window_.end());
    return t;
}

TokenPtr LayerPipeline::find_covers(At at, TokenPtr t) {
    if (!t || t->end) return t;
    SpanTimer timer(span_, t->seq, at.index);
    std::vector<const CoverSlice*> slices;
    for (const auto& e : t->window) slices.push_back(e.get());
    t->layer = carvable_layer(t->layer.index, slices, settings_);
    t->window.clear();
    if (k_ > 0) t->carvable = std::make_shared<const Paths>(t->layer.carvable);
    return t;
}

TokenPtr LayerPipeline::link_carvable(At at, TokenPtr t) {
    if (!t || t->end) return t;
    SpanTimer timer(span_, t->seq, at.index);
    t->carvable_above = std::exchange(carvable_above_, std::move(t->carvable));
    return t;
}

// Each iteration in two filters: the half that reads only V^{j-1}_i, on any thread, then
// the half that needs C^j_{i+1}, in order.
TokenPtr LayerPipeline::seed_iteration(At at, TokenPtr t) {
    if (!t || t->end) return t;
    SpanTimer timer(span_, t->seq, at.index);
    t->prep = sweeps_[at.j]->prepare(t->layer, t->carvable_above.get());
    return t;
}

TokenPtr LayerPipeline::sweep_iteration(At at, TokenPtr t) {
    if (!t || t->end) return t;
    SpanTimer timer(span_, t->seq, at.index);
    sweeps_[at.j]->carve(t->layer, std::move(*t->prep));
    t->prep.reset();
    if (at.j == k_ - 1) t->carvable_above.reset();
    return t;
}

TokenPtr LayerPipeline::hold_back(At at, TokenPtr t) {
    if (!t) return t;
    TokenPtr out = std::exchange(held_, nullptr);
    SpanTimer timer(span_, out ? out->seq : t->seq, at.index);
    // Slice i is carved: from here on its partition is only read, by its own later
    // stages and, at once, by the bridges of slice i + 1.
    if (!t->end) t->record.carved = std::make_shared<const LayerPartition>(std::move(t->layer));
    if (out && !t->end) out->below = t->record.carved;
    // The end tokens after the first flush the support filter's hold-back (there are
    // none more without supports).
    if (t->end && !out) return t;
    held_ = t->end ? pool_.drop(t) : t;
    return out;  // null for the top slice's token: nothing to release yet
}

TokenPtr LayerPipeline::plan_supports(At at, TokenPtr t) {
    if (!t) return t;
    SpanTimer timer(span_, t->seq, at.index);
    const bool finished = t->end;
    if (finished) {
        pool_.drop(t);
    } else {
        planner_.add_outline(t->record.partition().index, t->record.partition().outline);
        support_held_.push_back(t);
    }
    if (support_held_.empty() ||
        planner_.ready(finished) != support_held_.front()->record.partition().index)
        return nullptr;
    TokenPtr out = support_held_.front();
    support_held_.pop_front();
    SupportLayer s = planner_.plan(out->record.partition().index);
    out->record.support = {std::move(s.region), std::move(s.interface), std::move(s.walls)};
    out->support_new_mm2 = s.new_mm2;
    return out;
}

TokenPtr LayerPipeline::bridge_layer_below(At at, TokenPtr t) {
    if (!t) return t;
    SpanTimer timer(span_, t->seq, at.index);
    // The bottom slice has no slice below: it stands on the bed.
    t->overhang =
        measure_overhang(t->record.partition().outline, t->below ? &t->below->outline : nullptr,
                         overhang_reach_, to_units(2.0));
    {
        StageTimer bridges_timer(Stage::kBridges);
        t->record.bridged = bridge_layer(t->record.partition(), t->below.get(), bridging_);
    }
    // The ribs' per-slice regions here, in parallel: the serial rib filter then only
    // carries the ribs down.
    t->rib_slice = rib_slice(t->record, ribbing_);
    t->below.reset();
    return t;
}

TokenPtr LayerPipeline::link_ribs(At at, TokenPtr t) {
    if (!t) return t;
    SpanTimer timer(span_, t->seq, at.index);
    RibAbove next{t->record.partition().index > 0,
                  std::make_shared<const Paths>(std::move(t->rib_slice.printed)),
                  t->record.bridged.unheld, bridges_above(t->record.bridged)};
    t->rib_above = std::exchange(rib_above_, std::move(next));
    return t;
}

TokenPtr LayerPipeline::overlap_ribs(At at, TokenPtr t) {
    if (!t) return t;
    SpanTimer timer(span_, t->seq, at.index);
    if (ribbing_.enabled) rib_overlap(t->rib_slice, t->rib_above);
    t->rib_above = {};
    return t;
}

TokenPtr LayerPipeline::grow_ribs(At at, TokenPtr t) {
    if (!t) return t;
    SpanTimer timer(span_, t->seq, at.index);
    t->record.ribs = ribs_.add(t->record, t->rib_slice);
    return t;
}

TokenPtr LayerPipeline::plan_paths(At at, TokenPtr t) {
    if (!t) return t;
    SpanTimer timer(span_, t->seq, at.index);
    t->record.ribs = clip_ribs(std::move(t->record.ribs), t->rib_slice, ribbing_);
    t->rib_slice = {};
    t->paths = plan_layer(t->record, settings_);
    if (!outputs_.first_loops.empty())
        add_skirt_and_brim(t->paths, outputs_.first_loops, settings_);
    if (options_.in_parallel_stage) options_.in_parallel_stage(t->record.partition().index);
    outputs_.writer.add_layer(t->paths);  // thread-safe: the spill is indexed by layer
    // Pictures of one layer each, to files of their own (the HTML report stays in the
    // serial filter: it shares a size budget between the layers in the order they come).
    if (outputs_.svg) outputs_.svg->add(t->record, &t->paths);
    if (outputs_.raster) outputs_.raster->add_layer(t->record);
    t->volumes = extrusion_volumes_mm3(t->paths, settings_);
    for (double v : t->volumes) t->material += v;
    return t;
}

TokenPtr LayerPipeline::write_layer(At at, TokenPtr t) {
    if (!t) return t;
    struct DropAtEnd {
        TokenPool& pool;
        Token* t;
        ~DropAtEnd() { pool.drop(t); }
    } drop_at_end{pool_, t};
    SpanTimer timer(span_, t->seq, at.index);
    const LayerPartition& layer = t->record.partition();
    for (const std::string& w : layer.warnings)
        if (note_) note_(w);
    if (outputs_.html) outputs_.html->add_layer(t->record, t->paths);
    add_layer_figures(*t, settings_, result_, sliced_volume_, overhangs_);
    material_out_ += t->material;
    if (options_.give_up_above_mm3 > 0) {
        const std::vector<double>& below = options_.below_at_least_mm3;
        const size_t i = size_t(layer.index);
        if (material_out_ + (i < below.size() ? below[i] : 0) > options_.give_up_above_mm3)
            throw RunGivenUp(fmt::format("heavier than a candidate already carved, {} of {} "
                                         "layers still to go",
                                         i, layer_count_),
                             int(i), layer_count_);
    }
    unprinted_.add(layer.index, settings_.layer_top_mm(layer.index), t->paths.unprinted_mm2);
    ++done_;
    report_progress(options_, done_, layer_count_, start_, last_progress_);
    return nullptr;
}

void LayerPipeline::run(int threads) {
    using tbb::filter_mode;
    const std::vector<Step> all_steps = steps(k_);
    auto mode = [](const Step& s) {
        return s.filter->serial ? filter_mode::serial_in_order : filter_mode::parallel;
    };
    const Step source = all_steps.front(), sink = all_steps.back();
    tbb::filter<void, TokenPtr> chain =
        tbb::make_filter<void, TokenPtr>(mode(source), [this, source](tbb::flow_control& fc) {
            TokenPtr t = (this->*source.filter->fn)(source.at, nullptr);
            if (!t) fc.stop();
            return t;
        });
    for (size_t i = 1; i + 1 < all_steps.size(); ++i) {
        const Step s = all_steps[i];
        if (s.filter->repeat == Filter::IfSupporting && !supporting_) continue;
        chain = chain & tbb::make_filter<TokenPtr, TokenPtr>(mode(s), [this, s](TokenPtr t) {
                    return (this->*s.filter->fn)(s.at, t);
                });
    }
    const tbb::filter<void, void> all =
        chain & tbb::make_filter<TokenPtr, void>(
                    mode(sink), [this, sink](TokenPtr t) { (this->*sink.filter->fn)(sink.at, t); });

    // Tokens bound the layers in flight, so memory stays flat in the model's height whatever
    // the thread count: room for one layer in each serial filter plus two per thread for the
    // parallel one, whose layers vary tenfold in cost (fandisk's face tops).
    const size_t tokens = size_t(filter_count()) + 2 * size_t(threads) + size_t(support_lag_);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    tbb::task_arena arena(threads);
    ThreadArenas arenas(arena);
    // parallel_pipeline waits for the filters still running and rethrows an exception of any
    // of them here, before the run's stages and writers are destroyed.
    arena.execute([&] { tbb::parallel_pipeline(tokens, all); });
}

}  // namespace carve
