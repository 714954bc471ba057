// The layers' oneTBB pipeline (private to src/run): the filters every layer flows through top
// down, one member function each, chained by run() as the filter table lists them, and the state
// the serial filters carry from one layer to the next. run_slice (pipeline.cpp) builds it, runs it,
// and reads the figures it summed.
#pragma once

#include <tbb/parallel_pipeline.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "carving/carving.hpp"
#include "config/settings.hpp"
#include "mesh/mesh.hpp"
#include "report/run_result.hpp"
#include "run/pipeline.hpp"
#include "run/run_setup.hpp"
#include "run/span_log.hpp"
#include "run/tokens.hpp"
#include "slice/slicer.hpp"
#include "supports/bridges.hpp"
#include "supports/overhang.hpp"
#include "supports/ribs.hpp"
#include "supports/support_volume.hpp"
#include "toolpath/thin_walls.hpp"

namespace carve {

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
class LayerPipeline {
  public:
    // Sets result's per-layer figures to zero for the sink to sum into; `check_slice` is the
    // vertex limits (empty: none), `note` tells the user a layer's warnings.
    LayerPipeline(const Settings& settings, const RunOptions& options, const Mesh& mesh, double z0,
                  TopDownSlicer& slicer, std::function<void(const Slice&)> check_slice,
                  RunOutputs& outputs, RunResult& result,
                  std::chrono::steady_clock::time_point start,
                  std::function<void(const std::string&)> note);

    // Every layer through every filter, on `threads` threads. An exception in any filter
    // cancels the pipeline and is rethrown here, with its type and message.
    void run(int threads);

    bool supporting() const { return supporting_; }
    // What the slices hold: the model's volume if the mesh is open.
    double sliced_volume() const { return sliced_volume_; }
    const OverhangTally& overhangs() const { return overhangs_; }
    const UnprintedTally& unprinted() const { return unprinted_; }
    const SpanLog& span() const { return span_; }
    // The filters' names, in chain order (for the profile's table), with `iterations` carving
    // iterations.
    std::vector<std::string> filter_names() const { return filter_names(k_); }
    static std::vector<std::string> filter_names(int iterations);

    // Where a filter stands in the chain: its index (its column in the span log) and, for a
    // carving iteration's filter, which iteration.
    struct At {
        int index = 0, j = 0;
    };
    using FilterFn = TokenPtr (LayerPipeline::*)(At at, TokenPtr t);
    // One row of the filter table (layer_pipeline.cpp), from which run() chains the filters and
    // the span log takes its columns; it states what each filter does with the token's fields
    // (TokenField bits), and lifetime_error below checks that against the token. The first row
    // is the source (given no token, it returns none once the stream is done), the last the
    // sink (it frees the token and all it holds).
    struct Filter {
        const char* name;  // an iteration's filter has the iteration's number after it
        FilterFn fn;
        bool serial;  // serial in order, else parallel
        enum Repeat { Once, EachIteration, IfSupporting } repeat;
        uint32_t makes, uses, frees;  // the fields it sets first, reads or changes, releases
    };
    static std::span<const Filter> filters();

  private:
    // The filters, in pipeline order (their modes and fields are their rows in filters()).
    TokenPtr cut_slice(At at, TokenPtr none);        // the slicer's next plane
    TokenPtr chain_cut(At at, TokenPtr t);           // the plane's segments into contours
    TokenPtr check_limits(At at, TokenPtr t);        // the vertex limits
    TokenPtr erode_slice(At at, TokenPtr t);         // the cover erosions of a slice
    TokenPtr gather_window(At at, TokenPtr t);       // the covers' window of 2c+1 slices
    TokenPtr find_covers(At at, TokenPtr t);         // the layer's covers, carvable part
    TokenPtr link_carvable(At at, TokenPtr t);       // O'_{i+1} handed down
    TokenPtr seed_iteration(At at, TokenPtr t);      // iteration j's half from V^{j-1}
    TokenPtr sweep_iteration(At at, TokenPtr t);     // iteration j's half from C^j_{i+1}
    TokenPtr hold_back(At at, TokenPtr t);           // slice i + 1 waits for slice i
    TokenPtr plan_supports(At at, TokenPtr t);       // supports, the gap's layers held
    TokenPtr bridge_layer_below(At at, TokenPtr t);  // overhang, bridges, rib regions
    TokenPtr link_ribs(At at, TokenPtr t);           // what the slice above prints
    TokenPtr overlap_ribs(At at, TokenPtr t);        // ribs' booleans with the above
    TokenPtr grow_ribs(At at, TokenPtr t);           // the ribs carried down
    TokenPtr plan_paths(At at, TokenPtr t);          // toolpaths, spill, pictures
    TokenPtr write_layer(At at, TokenPtr t);         // the writers and sums, in order

    // The table's rows in chain order, an iteration's rows together once for each iteration
    // (the supports' whether or not they are planned: the span log keeps its column).
    struct Step {
        const Filter* filter;
        At at;
    };
    static std::vector<Step> steps(int iterations);
    int filter_count() const { return int(steps(k_).size()); }

    const Settings& settings_;
    const RunOptions& options_;
    TopDownSlicer& slicer_;
    std::function<void(const Slice&)> check_slice_;
    RunOutputs& outputs_;
    RunResult& result_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_progress_;  // when progress was last shown
    std::function<void(const std::string&)> note_;
    const int layer_count_;
    const int k_;  // carving iterations
    const int c_;  // covers
    // Supports are decided from above too; a layer's support needs the outlines of the z gap's
    // layers below it, so the support filter holds that many layers back (and as many more end
    // tokens flush it). Without supports the filter is not in the chain at all.
    const bool supporting_;
    const int support_lag_;
    SpanLog span_;

    int next_seq_ = 0, ends_left_;
    TokenPool pool_;  // before the filters' state: freed after it
    // Layer i is ready once slice i - c is in (or the slicer is done); the token that brought
    // that slice carries layer i on, with the window's slices shared, not copied.
    std::deque<std::shared_ptr<const CoverSlice>> window_;  // top down
    int next_layer_;
    // The whole-width test of a carving iteration reads O'_{i+1} (what of a part lies under
    // the model's surface in the slice above).
    std::shared_ptr<const Paths> carvable_above_;
    std::vector<std::unique_ptr<CarvingSweep>> sweeps_;
    TokenPtr held_ = nullptr;  // slice i + 1, waiting for slice i
    std::unique_ptr<ModelShadow> shadow_;
    SupportPlanner planner_;
    std::deque<TokenPtr> support_held_;  // top down, waiting for the outlines below them
    const BridgeOptions bridging_;
    const RibOptions ribbing_;
    const Coord overhang_reach_;
    OverhangTally overhangs_;
    UnprintedTally unprinted_;  // what of the slices is too thin to print (thin_walls.hpp)
    // Ribs grow down from what would hang: serial top down, each slice's only after the slices
    // above it (nothing is held back: a rib on slice i depends on slices i and above). Around
    // the serial filter, what reads no rib: the booleans of each slice with the one above (the
    // link hands that down in order) and, in the paths filter, the pieces' clipping.
    RibAbove rib_above_;
    RibPlanner ribs_;
    int done_ = 0;
    double sliced_volume_ = 0;
    double material_out_ = 0;  // of the layers through the sink (RunOptions::give_up_above_mm3)
};

// What the filter table gets wrong about a token field's lifetime: `rule` broken by `filter`
// for the field numbered `field` (TokenField's bit), or no rule. Each field is made by one
// filter, used and freed only after that, and freed at its last use, or else used by the sink
// (which frees it with the token). An iteration's rows count once (each iteration's prep is
// made and freed within it; the last sweep frees carvable_above); the supports' row makes
// support_new_mm2, left 0 where it is not chained.
struct LifetimeError {
    const char* rule = nullptr;
    int field = -1;
    const char* filter = "";
};
constexpr LifetimeError lifetime_error(std::span<const LayerPipeline::Filter> table) {
    const int n = int(table.size());
    for (int f = 0; f < TokenField::count; ++f) {
        const uint32_t bit = 1u << f;
        int made = -1, last_use = -1, freed = -1;
        for (int i = 0; i < n; ++i) {
            const LayerPipeline::Filter& row = table[size_t(i)];
            const bool makes = row.makes & bit, uses = row.uses & bit, frees = row.frees & bit;
            if (!makes && !uses && !frees) continue;
            if (freed >= 0) return {"used after it is freed", f, row.name};
            if (makes && made >= 0) return {"made by a second filter", f, row.name};
            if (makes) made = i;
            if (made < 0) return {"used before it is made", f, row.name};
            if (makes || uses) last_use = i;
            if (frees && last_use != i) return {"freed after its last use", f, row.name};
            if (frees) freed = i;
        }
        if (made < 0) return {"made by no filter", f, ""};
        if (freed < 0 && last_use != n - 1)
            return {"kept after its last use", f, table[size_t(last_use)].name};
    }
    return {};
}

}  // namespace carve
