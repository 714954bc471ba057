// carve check --strength: how strong a print is, from its G-code alone (issue 49). Per layer the
// printed footprint's area, its second moments of area about its centroid and its bond with the
// next layer; the weakest layer by section and by bond; and a voxel finite-element stiffness in
// compression and shear. Only the object counts: skirt, brim, supports, wipe and prime towers
// and custom G-code (a purge line) are left out, by the slicers' ;TYPE: comments.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "check/stiffness.hpp"
#include "geometry/types.hpp"

namespace carve {

struct StrengthOptions {
    double voxel_mm = 2.0;  // the finite elements' side, asked for
    // Voxels the solver takes, at most: above it the voxels are made twice as large until the
    // model fits (said in the figures). 40,000 solve in about 10 s on one core.
    long long max_voxels = 40'000;
    double density_g_cm3 = 1.24;  // PLA
    double tips_mm = 2.0;         // left out of the weakest layers at the bottom and the top
    check::StiffnessOptions solver;
};

// One layer of the object: its footprint's figures, mm; moments about its centroid.
struct SectionFigures {
    double z_mm = 0, height_mm = 0;
    double area_mm2 = 0;
    double centroid_x_mm = 0, centroid_y_mm = 0;
    double ixx_mm4 = 0, iyy_mm4 = 0, ixy_mm4 = 0;  // of y^2, x^2, x y
    double imin_mm4 = 0;                           // the smallest principal moment
    double bond_mm2 = -1;  // the footprint's overlap with the next layer's; -1: the last layer
};

// A section's moments; `region` a union with holes clockwise (what Clipper's union leaves).
SectionFigures section_of(const Paths& region);

struct StrengthFigures {
    double object_volume_mm3 = 0, grams = 0;
    std::vector<SectionFigures> layers;
    // The weakest layers between tips_mm above the bottom and tips_mm below the top (all the
    // layers when the object is lower than twice that). The bond's z is the lower layer's top.
    double weakest_section_mm4 = 0, weakest_section_z_mm = 0;
    double weakest_bond_mm2 = 0, weakest_bond_z_mm = 0;
    bool has_weakest_bond = false;
    // The finite elements.
    std::string law;  // "linear" or "cubic"
    double young_mpa = 0, poisson = 0;
    double voxel_mm_asked = 0;   // StrengthOptions::voxel_mm
    double voxel_mm = 0;         // as used
    bool coarsened = false;      // voxel_mm > voxel_mm_asked: too many voxels
    std::string coarsened_note;  // why, in words
    check::StiffnessFigures stiffness;
    double compression_n_per_mm_per_g = 0, shear_n_per_mm_per_g = 0;
    double solve_s = 0;
};

class StrengthState;

// Collects the object's layers as carve check reads them (GcodeAnalysisOptions::object_layer)
// and works the figures out at the end. Holds the last footprint and the voxels only.
class StrengthMeter {
  public:
    explicit StrengthMeter(const StrengthOptions& options);
    ~StrengthMeter();
    StrengthMeter(const StrengthMeter&) = delete;
    StrengthMeter& operator=(const StrengthMeter&) = delete;

    void layer(double z_mm, double height_mm, const Paths& footprint, double volume_mm3);
    StrengthFigures finish();

  private:
    StrengthOptions opt_;
    std::unique_ptr<StrengthState> state_;
};

// Whether the file has a ;TYPE: comment: if it has, extrusion before the first one is start
// G-code (CuraEngine's purge), not the object; if not, all of it is the object's. False for a
// pipe, which cannot be read twice: nothing is then left out that may be the object.
bool has_type_comments(const std::string& path);

nlohmann::json to_json(const StrengthFigures& figures);
// The figures for people; with_layers: the table of every layer too.
std::string describe_strength(const StrengthFigures& figures, bool with_layers);

}  // namespace carve
