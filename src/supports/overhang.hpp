// The model's own overhangs: what of each slice O_i nothing of O_{i-1} holds.
//
// carve prints no support structures yet. Its cavities hold everything inside the model; what
// sticks out beyond the layer below by more than the printer bridges is the model's external
// overhang, which only supports fix. This stage measures it per layer, so that the run can say
// where the print will hang before the user starts it, and the stats can report it.
#pragma once

#include <string>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

struct LayerOverhang {
    double area_mm2 = 0;      // of O_i beyond dilate(O_{i-1}, support)
    double far_area_mm2 = 0;  // of it beyond dilate(O_{i-1}, far): sags whatever the walls do
};

// O_i \ (O_{i-1} ⊕ D(support)): the part of the slice the layer below does not hold. The bottom
// slice stands on the bed: pass no slice below.
Paths external_overhang(const Paths& outline, const Paths* below, Coord support);

// Both areas; `far` >= `support`. `carve check` calls extrusion more than 2 mm from anything
// below hanging: `far` = 2 mm gives the share of it that is the model's own.
LayerOverhang measure_overhang(const Paths& outline, const Paths* below, Coord support, Coord far);

// The per-layer figures in layer order, and the warning a user needs before printing.
class OverhangTally {
  public:
    explicit OverhangTally(double warn_mm2 = 5.0) : warn_mm2_(warn_mm2) {}
    // z: the layer's height in the G-code (its top), which is what a user looks for.
    void add(int layer, double z, const LayerOverhang& overhang);
    double area_mm2() const { return area_mm2_; }
    double far_area_mm2() const { return far_area_mm2_; }
    // Empty unless the far overhang adds up to more than warn_mm2: then one sentence naming the
    // area and the z ranges (layers with far overhang, gaps of a layer or two bridged) where it
    // is largest.
    std::string warning() const;

  private:
    struct Run {
        int first = 0, last = 0;
        double z_first = 0, z_last = 0, far_mm2 = 0;
    };
    double warn_mm2_;
    double area_mm2_ = 0, far_area_mm2_ = 0;
    std::vector<Run> runs_;
};

}  // namespace carve
