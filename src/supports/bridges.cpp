// Bridge detection: placeholder pass-through until section 4.4 lands.
#include "supports/bridges.hpp"

namespace carve {

BridgeStage::BridgeStage(CarvingSweep& input, const Settings& settings)
    : input_(input), settings_(settings) {}

std::optional<LayerPartition> BridgeStage::next() {
    (void)settings_;
    (void)started_;
    return input_.next();
}

}  // namespace carve
