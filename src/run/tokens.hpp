// The layers' carriers through the run's oneTBB pipeline (private to src/run): what
// one layer holds between the filters (a carving iteration's prepared half among them, on its
// way to the serial half) and the pool that owns every token.
#pragma once

#include <cstdint>
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

// One layer on its way through the pipeline. Which filter makes, uses and frees each field is
// the filter table's (LayerPipeline::filters), checked there; a new field needs its bit in
// TokenField below and its place in that table.
struct Token {
    int seq = 0;       // place in the stream, 0 for the top slice
    bool end = false;  // after the last slice: flushes the covers' window and the hold-back
    std::optional<PlaneCut> cut;                            // the plane's segments
    std::optional<Slice> slice;                             // as chained
    std::shared_ptr<const CoverSlice> cover;                // ... and eroded
    std::vector<std::shared_ptr<const CoverSlice>> window;  // layer i's 2c+1 slices, top down
    LayerPartition layer;                                   // while it is carved
    LayerRecord record;                           // the carved partition, then each stage's
    std::shared_ptr<const Paths> carvable;        // O'_i, for the layer below
    std::shared_ptr<const Paths> carvable_above;  // O'_{i+1}, while the layer is carved
    std::optional<IterationPrep> prep;            // of the next carving iteration
    std::shared_ptr<const LayerPartition> below;  // slice i - 1 as carved
    LayerOverhang overhang;                       // of O_i beyond O_{i-1}
    double support_new_mm2 = 0;                   // overhang area a support starts under here
    RibSlice rib_slice;                           // what the ribs need of this slice alone
    RibAbove rib_above;                           // ... and of the slice above
    LayerToolpaths paths;
    std::vector<double> volumes;  // of each extrusion of `paths`, mm^3
    double material = 0;          // their sum
};

// Token's fields but seq and end (the stream's own: the first filter sets them, all read
// them), one bit each in Token's order, for the filter table.
struct TokenField {
    enum : uint32_t {
        cut = 1u << 0,
        slice = 1u << 1,
        cover = 1u << 2,
        window = 1u << 3,
        layer = 1u << 4,
        record = 1u << 5,
        carvable = 1u << 6,
        carvable_above = 1u << 7,
        prep = 1u << 8,
        below = 1u << 9,
        overhang = 1u << 10,
        support_new_mm2 = 1u << 11,
        rib_slice = 1u << 12,
        rib_above = 1u << 13,
        paths = 1u << 14,
        volumes = 1u << 15,
        material = 1u << 16,
    };
    static constexpr int count = 17;
    static constexpr const char* names[count] = {
        "cut",       "slice",          "cover", "window",  "layer",    "record",
        "carvable",  "carvable_above", "prep",  "below",   "overhang", "support_new_mm2",
        "rib_slice", "rib_above",      "paths", "volumes", "material"};
};

// How many fields an aggregate has: the most initialisers it takes (C++20 has no reflection),
// so that a field added to Token without a TokenField bit stops the build.
struct AnyField {
    template <class T>
    operator T() const;  // never defined: only asked whether it converts
};
template <class T, class... Fields>
constexpr int aggregate_fields(Fields... fields) {
    if constexpr (requires { T{fields..., AnyField{}}; })
        return aggregate_fields<T>(fields..., AnyField{});
    else
        return int(sizeof...(Fields));
}
static_assert(aggregate_fields<Token>() == 2 + TokenField::count,
              "every Token field but seq and end has a TokenField bit");

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
