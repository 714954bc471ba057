// The layers' carriers through the run's oneTBB pipeline (private to src/run): what
// one layer holds between the filters (a carving iteration's prepared half among them, on its
// way to the serial half) and the pool that owns every token.
#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <unordered_set>
#include <utility>
#include <vector>

#include "carving/carving.hpp"
#include "carving/layer.hpp"
#include "slice/slicer.hpp"
#include "supports/overhang.hpp"
#include "supports/ribs.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

// One layer on its way through the pipeline.
struct Token {
    int seq = 0;       // place in the stream, 0 for the top slice
    bool end = false;  // after the last slice: flushes the covers' window and the hold-back
    std::optional<PlaneCut> cut;              // the plane's segments, until chained
    std::optional<Slice> slice;               // as cut, until eroded
    std::shared_ptr<const CoverSlice> cover;  // ... and eroded, until the window takes it
    std::vector<std::shared_ptr<const CoverSlice>> window;  // layer i's 2c+1 slices, top down
    LayerPartition layer;  // while it is carved; then moved into `record`
    LayerRecord record;    // from the hold-back on: the carved partition, then each stage's
    std::shared_ptr<const Paths> carvable;        // O'_i, until handed to the layer below
    std::shared_ptr<const Paths> carvable_above;  // O'_{i+1}, while the layer is carved
    std::optional<IterationPrep> prep;            // of the next carving iteration
    std::shared_ptr<const LayerPartition> below;  // slice i - 1 as carved
    LayerOverhang overhang;                       // of O_i beyond O_{i-1}
    double support_new_mm2 = 0;                   // overhang area a support starts under here
    RibSlice rib_slice;                           // what the ribs need of this slice alone
    RibAbove rib_above;                           // ... and of the slice above, until overlapped
    LayerToolpaths paths;
    std::vector<double> volumes;  // of each extrusion of `paths`, mm^3
    double material = 0;          // their sum
};
using TokenPtr = Token*;

// Owns every token. A cancelled parallel_pipeline (an exception in a filter) does not destroy
// the items it holds between filters: LeakSanitizer found the shared_ptr tokens of a failed
// run never freed. So the filters pass plain pointers, a token is freed where the stream drops
// it, and whatever a cancelled run left in flight is freed with the pool.
class TokenPool {
  public:
    TokenPool() = default;
    TokenPool(const TokenPool&) = delete;
    TokenPool& operator=(const TokenPool&) = delete;
    ~TokenPool() {
        for (Token* t : live_) delete t;
    }
    Token* make() {
        auto t = std::make_unique<Token>();
        std::lock_guard lock(mutex_);
        live_.insert(t.get());
        return t.release();
    }
    std::nullptr_t drop(Token* t) {
        if (t) {
            {
                std::lock_guard lock(mutex_);
                live_.erase(t);
            }
            delete t;
        }
        return nullptr;
    }

  private:
    std::mutex mutex_;
    std::unordered_set<Token*> live_;
};

}  // namespace carve
