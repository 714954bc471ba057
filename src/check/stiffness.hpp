// A voxel finite-element model of a print for carve check --strength: each voxel an 8-node
// trilinear hexahedron of isotropic material whose Young's modulus follows its filled fraction,
// the bed clamped, the top pushed. Internal to src/check.
#pragma once

#include <string>
#include <vector>

#include "check/voxels.hpp"

namespace carve::check {

enum class MaterialLaw {
    kLinear,  // E = E_solid * fraction: material adds stiffness where it is
    kCubic,   // E = E_solid * fraction^3: sparse material counts for little (foams, lattices)
};

struct StiffnessOptions {
    double young_mpa = 3500;  // PLA
    double poisson = 0.35;
    MaterialLaw law = MaterialLaw::kLinear;
    int max_iterations = 5000;  // conjugate gradient, per load case
    double tolerance = 1e-6;    // relative residual
};

struct StiffnessFigures {
    double compression_n_per_mm = 0;  // top pushed down, free to spread; reaction / displacement
    double shear_n_per_mm = 0;        // top moved sideways (x), held level; reaction / displacement
    long long elements = 0;           // voxels in the model (joined to the bed)
    long long dropped = 0;            // voxels holding filament left out: not joined to the bed
    long long nodes = 0;
    int iterations_compression = 0, iterations_shear = 0;
    double residual_compression = 0, residual_shear = 0;
    bool converged = true;
};

// The element stiffness matrix of a unit cube (side 1 mm, E = 1 MPa) for Poisson's ratio nu,
// nodes ordered x fastest (node n at (n & 1, n >> 1 & 1, n >> 2)), dofs (x, y, z) per node.
std::vector<double> unit_cube_stiffness(double nu);

// Solves both load cases on the voxels (cell_mm their side).
StiffnessFigures solve_stiffness(const std::vector<Voxel>& voxels, double cell_mm,
                                 const StiffnessOptions& options);

}  // namespace carve::check
