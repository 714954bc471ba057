// A hook for timing geometry's own operations (booleans, morphology) under CARVE_PROFILE.
// Geometry is the bottom layer and knows nothing of the stage timer that the stages above it
// use: whoever profiles a run installs a probe (src/run does), and without one an operation
// costs a single relaxed atomic load.
#pragma once

#include <cstdint>

namespace carve {

enum class GeometryOp { kMorphology, kBoolean };

// now() is any monotonic clock in nanoseconds; add() receives the time of one operation.
// Both may be called from several threads at once.
struct GeometryProbe {
    int64_t (*now)() = nullptr;
    void (*add)(GeometryOp op, int64_t ns) = nullptr;
};

// Installs `probe` (copied; null functions or a null pointer switch timing off).
void set_geometry_probe(const GeometryProbe* probe);

// Times the enclosing scope as one operation when a probe is installed.
class GeometryTimer {
  public:
    explicit GeometryTimer(GeometryOp op);
    ~GeometryTimer();
    GeometryTimer(const GeometryTimer&) = delete;
    GeometryTimer& operator=(const GeometryTimer&) = delete;

  private:
    GeometryOp op_;
    const GeometryProbe* probe_;
    int64_t start_ns_ = 0;
};

}  // namespace carve
