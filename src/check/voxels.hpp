// The filled fraction of a regular grid of cubic voxels, accumulated layer by layer from the
// printed footprints, for carve check --strength's finite elements. Internal to src/check.
//
// The grid is anchored at the machine's origin (voxel i spans [i a, (i + 1) a)), so that a
// coarser grid of twice the size nests the finer one exactly: coarsening adds up the volumes of
// eight voxels and loses nothing. Only voxels that hold filament are stored.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "geometry/types.hpp"

namespace carve::check {

struct Voxel {
    int i = 0, j = 0, k = 0;
    double fraction = 0;  // filled volume over the voxel's, at most 1
};

class VoxelGrid {
  public:
    // cell_mm: the voxel's side; max_cells: voxels held before the grid coarsens itself.
    VoxelGrid(double cell_mm, size_t max_cells);

    // A layer's footprint (a union, holes clockwise: what widen() returns) extruded over
    // [z_top - height, z_top], mm.
    void add_layer(const Paths& footprint, double z_top_mm, double height_mm);
    // Doubles the voxel's side.
    void coarsen();

    double cell_mm() const { return cell_; }
    size_t size() const { return volume_.size(); }
    int coarsenings() const { return coarsenings_; }
    std::vector<Voxel> voxels() const;

  private:
    struct Key {
        int i, j, k;
        bool operator==(const Key& o) const { return i == o.i && j == o.j && k == o.k; }
    };
    struct KeyHash {
        size_t operator()(const Key& key) const {
            uint64_t h = static_cast<uint32_t>(key.i);
            h = h * 0x9E3779B97F4A7C15ULL ^ static_cast<uint32_t>(key.j);
            h = h * 0x9E3779B97F4A7C15ULL ^ static_cast<uint32_t>(key.k);
            return static_cast<size_t>(h ^ (h >> 29));
        }
    };
    // The footprint's area in each voxel column of its bounding box, mm2.
    struct Columns {
        long i0 = 0, j0 = 0, nx = 0, ny = 0;
        std::vector<double> area;
    };
    Columns rasterise(const Paths& footprint) const;

    double cell_;
    size_t max_cells_;
    int coarsenings_ = 0;
    std::unordered_map<Key, double, KeyHash> volume_;  // mm3 of filament per voxel
};

}  // namespace carve::check
