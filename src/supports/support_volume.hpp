// Supports for the model's own overhangs (issue #20), decided from above like the cavities.
//
// Shape, chosen by measurement against PrusaSlicer's snug supports and CuraEngine's trees
// (docs/supports.md, bench/results/supports.md): under each overhang a region that narrows going
// down by r per layer (its edge leans at --max-overhang and holds itself, as a cavity's walls do)
// except beside the model, where it keeps its width so that the rings under a dome merge into one
// shadow instead of standing as thin bands side by side. A compact part about 3 mm wide goes
// straight down as a column; what becomes too thin to print is printed as its medial axis, which
// goes on down as a single wall. Each layer is printed as the region's outline, straight walls at
// fixed places (the same lines layer after layer, so they stack) and a few dense interface layers
// on top. A wide overhang thus costs a pyramid of sparse walls ending in a blade, not a column.
//
// Memory stays flat in the model's height: the planner keeps the current support region and
// walls, the new overhangs of the last interface layers and a window of 2g + 2 outlines (g = the
// z gap in layers).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include "config/settings.hpp"
#include "geometry/types.hpp"

namespace carve {

struct SupportOptions {
    SupportMode mode = SupportMode::None;
    int gap_layers = 1;        // empty layers between a support's top and the overhang
    Coord xy_gap = 250;        // from the model's side
    Coord reach = 200;         // overhang beyond the layer below that needs no support
    Coord lean = 200;          // r: how much the support narrows per layer going down
    Coord trunk = 1500;        // half the width below which a part stops narrowing
    Coord line_width = 400;    // w
    int interface_layers = 2;  // dense layers at the top
    double layer_height = 0.2;
    double first_layer = 0.2;  // the first layer's thickness, mm
    double z0 = 0;             // model z of the bottom of layer 0, mm
};
SupportOptions support_options(const Settings& settings, double z0);

// The lowest point of the model over each cell of a grid: where a column from a height down to
// the bed is free of the model (for --support buildplate). Built once from the triangles; its
// size is the model's footprint, not its height.
class ModelShadow {
  public:
    ModelShadow() = default;
    ModelShadow(const std::vector<Vec3>& vertices,
                const std::vector<std::array<uint32_t, 3>>& triangles, double cell_mm);
    bool empty() const { return lowest_.empty(); }
    // Cells with a point of the model below z_mm, grown by `grow`, as a region (um).
    Paths below(double z_mm, Coord grow) const;

  private:
    double x0_ = 0, y0_ = 0, cell_ = 1;
    int nx_ = 0, ny_ = 0;
    std::vector<float> lowest_;
};

struct SupportLayer {
    Paths region;        // everything of the support in the layer
    Paths interface;     // of it, the dense part under an overhang
    Paths walls;         // single walls (open or closed polylines) outside the region
    double new_mm2 = 0;  // overhang area that starts being supported in this layer
};

// Fed the model's outlines top down; hands out each layer's support once it has seen the
// outlines the gap needs below it.
class SupportPlanner {
  public:
    SupportPlanner(SupportOptions options, const ModelShadow* shadow = nullptr);
    // Outline of layer `index`, top down, one after the other.
    void add_outline(int index, const Paths& outline);
    // Layers whose support can be planned now (all the gap's outlines below them are in, or
    // `finished`): the highest such layer not yet handed out, or -1.
    int ready(bool finished) const;
    // The support of layer `ready()`; call in order.
    SupportLayer plan(int index);
    int lookahead() const { return options_.gap_layers; }

  private:
    const Paths& outline(int index) const;
    // plan()'s phases, in order.
    Paths fresh_overhang(int j) const;
    Paths clear_of_model(int j, Paths& region, Paths& walls) const;
    Paths grounded_overhangs() const;
    void add_interface(SupportLayer& out, const Paths& fresh, const Paths& region);
    Paths narrow(const Paths& region, const Paths& hug, SupportLayer& out, Paths& walls) const;
    SupportOptions options_;
    const ModelShadow* shadow_;
    std::deque<std::pair<int, Paths>> outlines_;  // top down, layers next_ + 2g + 1 .. lowest
    int next_ = -1;                               // next layer to plan
    int lowest_ = -1;                             // lowest outline added
    Paths carried_;                               // the support region passed down
    Paths walls_;                                 // single walls passed down
    std::deque<Paths> fresh_;                     // new overhangs of the last interface layers
    Paths empty_;
};

}  // namespace carve
