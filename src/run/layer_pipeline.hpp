// The layers' oneTBB pipeline (private to src/run): the filters every layer flows through top
// down, one member function each, in the order run() chains them, and the state the serial
// filters carry from one layer to the next. run_slice (pipeline.cpp) builds it, runs it, and
// reads the figures it summed.
#pragma once

#include <tbb/parallel_pipeline.h>

#include <chrono>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
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
    // The filters' names, in the order of their indices below (for the profile's table).
    std::vector<std::string> filter_names() const;

  private:
    // The filters, in pipeline order (each one's index into the span log below).
    TokenPtr cut_slice(tbb::flow_control& fc);    // serial: the slicer's next plane
    TokenPtr chain_cut(TokenPtr t);               // parallel: the plane's segments into contours
    TokenPtr check_limits(TokenPtr t);            // serial: the vertex limits
    TokenPtr erode_slice(TokenPtr t);             // parallel: the cover erosions of a slice
    TokenPtr gather_window(TokenPtr t);           // serial: the covers' window of 2c+1 slices
    TokenPtr find_covers(TokenPtr t);             // parallel: the layer's covers, carvable part
    TokenPtr link_carvable(TokenPtr t);           // serial: O'_{i+1} handed down
    TokenPtr seed_iteration(int j, TokenPtr t);   // parallel: iteration j's half from V^{j-1}
    TokenPtr sweep_iteration(int j, TokenPtr t);  // serial: iteration j's half from C^j_{i+1}
    TokenPtr hold_back(TokenPtr t);               // serial: slice i + 1 waits for slice i
    TokenPtr plan_supports(TokenPtr t);           // serial: supports, the gap's layers held
    TokenPtr bridge_layer_below(TokenPtr t);      // parallel: overhang, bridges, rib regions
    TokenPtr link_ribs(TokenPtr t);               // serial: what the slice above prints
    TokenPtr overlap_ribs(TokenPtr t);            // parallel: ribs' booleans with the above
    TokenPtr grow_ribs(TokenPtr t);               // serial: the ribs carried down
    TokenPtr plan_paths(TokenPtr t);              // parallel: toolpaths, spill, pictures
    void write_layer(TokenPtr t);                 // serial: the writers and sums, in order

    static constexpr int kSlice = 0, kChain = 1, kCheck = 2, kErode = 3, kWindow = 4, kCovers = 5,
                         kLink = 6;
    int k_seed(int j) const { return kLink + 1 + 2 * j; }  // iteration j + 1, parallel half
    int k_sweep(int j) const { return kLink + 2 + 2 * j; }
    int k_hold() const { return kLink + 1 + 2 * k_; }
    int k_support() const { return k_hold() + 1; }
    int k_work() const { return k_support() + 1; }
    int k_rib_link() const { return k_work() + 1; }
    int k_rib_overlap() const { return k_rib_link() + 1; }
    int k_ribs() const { return k_rib_overlap() + 1; }
    int k_paths() const { return k_ribs() + 1; }
    int k_sink() const { return k_paths() + 1; }
    int filter_count() const { return k_sink() + 1; }

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

}  // namespace carve
