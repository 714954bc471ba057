// SKEL internals exposed to the tests and benchmarks: retry control and per-call statistics.
//
// The public entry points are in skeleton.hpp; nothing else in the product should need this.
#pragma once

#include <string>
#include <vector>

#include "skeleton/skeleton.hpp"

namespace carve::skel {

struct AxisTrace {
    // Frame of the first attempt (0 = as given, then small exact rotations); tests use it to
    // check that a rotated build gives the same axis.
    int first_frame = 0;
    // Treat the first attempts as failed builds (tests of the retry path; real failures of
    // Boost's builder are rare and input specific).
    int reject_attempts = 0;
};

// What the last medial_axis() / skeleton() call on this thread went through.
struct SkeletonStats {
    int components = 0;  // region components after cleaning
    int retries = 0;     // rebuilds in a rotated frame after a rejected diagram
    int mended = 0;      // components whose contours were split or re-linked (contours.hpp)
    int abandoned = 0;   // components left without an axis after every frame failed
    std::vector<std::string> rejections;  // why each rejected diagram was rejected
    int nodes = 0, edges = 0;             // size of the unpruned axis graphs, summed
};

Paths medial_axis(const Paths& region, const SkeletonOptions& options, const AxisTrace& trace);

// The axes of a region's components as medial_axis() cleaned and built them, kept so that a
// later call on a region made of some of the same components need not build them again: the
// carving sweep works them out for a slice before the slice above is carved (in parallel),
// then asks for the components the cavity above left open.
struct AxisMemo {
    std::vector<Paths> components;  // after prepare_components()
    std::vector<Paths> axes;        // of each
    std::vector<SkeletonStats> stats;
};

// medial_axis(region, options), built in the given frames as usual, but a component equal
// (vertex for vertex) to one of `known` takes its axis from there: the result and
// last_stats() are the same as without `known`. With `record`, the components and their axes
// are kept there.
Paths medial_axis(const Paths& region, const SkeletonOptions& options, const AxisMemo* known,
                  AxisMemo* record = nullptr);

const SkeletonStats& last_stats();

// The number of frames medial_axis() tries before it gives up on a component.
int frame_count();

}  // namespace carve::skel
