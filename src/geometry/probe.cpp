// The probe lives in a static slot installed once, before any thread starts using geometry; the
// atomic pointer keeps the hand-over well defined anyway.
#include "geometry/probe.hpp"

#include <atomic>

namespace carve {

namespace {

GeometryProbe installed;
std::atomic<const GeometryProbe*> active{nullptr};

}  // namespace

void set_geometry_probe(const GeometryProbe* probe) {
    if (!probe || !probe->now || !probe->add) {
        active.store(nullptr, std::memory_order_release);
        return;
    }
    active.store(nullptr, std::memory_order_release);
    installed = *probe;
    active.store(&installed, std::memory_order_release);
}

GeometryTimer::GeometryTimer(GeometryOp op)
    : op_(op), probe_(active.load(std::memory_order_acquire)) {
    if (probe_) start_ns_ = probe_->now();
}

GeometryTimer::~GeometryTimer() {
    if (probe_) probe_->add(op_, probe_->now() - start_ns_);
}

}  // namespace carve
