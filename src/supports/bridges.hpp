// Local minima and bridges (report section 4.4), as a stage between the carving sweep and the
// toolpaths. A minimum at slice i is only known once slice i - 1 is carved, so the stage holds
// one slice back: two slices of state, like the sweep.
#pragma once

#include <optional>

#include "carving/carving.hpp"

namespace carve {

class BridgeStage {
public:
    BridgeStage(CarvingSweep& input, const Settings& settings);
    // The next layer going down, with its bridges filled in.
    std::optional<LayerPartition> next();

private:
    CarvingSweep& input_;
    const Settings& settings_;
    std::optional<LayerPartition> pending_;  // slice i, waiting for slice i - 1
    bool started_ = false;
};

}  // namespace carve
