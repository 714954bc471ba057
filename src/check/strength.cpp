// carve check --strength (see strength.hpp): the sections and bonds as the layers come, the
// voxels filled as they come, the finite elements once the file is read.
#include "check/strength.hpp"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "check/footprint.hpp"
#include "check/voxels.hpp"

namespace carve {

namespace {

// Voxels held while the file is read (~50 MB): past it the grid coarsens at once, so that a
// kilometre of print cannot fill the memory before the solver's own cap is applied.
constexpr size_t kMaxStreamVoxels = 1'000'000;

}  // namespace

SectionFigures section_of(const Paths& region) {
    // Green's theorem over each contour, signed by its orientation (holes subtract), from a
    // point of the region so that large coordinates do not cancel the digits away.
    SectionFigures s;
    if (region.empty() || region[0].empty()) return s;
    const double ox = to_mm(region[0][0].X), oy = to_mm(region[0][0].Y);
    double a = 0, sx = 0, sy = 0, ixx = 0, iyy = 0, ixy = 0;
    for (const Path& p : region) {
        for (size_t n = 0; n < p.size(); ++n) {
            const Point& u = p[n];
            const Point& v = p[(n + 1) % p.size()];
            const double x1 = to_mm(u.X) - ox, y1 = to_mm(u.Y) - oy;
            const double x2 = to_mm(v.X) - ox, y2 = to_mm(v.Y) - oy;
            const double c = x1 * y2 - x2 * y1;
            a += c;
            sx += (x1 + x2) * c;
            sy += (y1 + y2) * c;
            ixx += (y1 * y1 + y1 * y2 + y2 * y2) * c;
            iyy += (x1 * x1 + x1 * x2 + x2 * x2) * c;
            ixy += (x1 * y2 + 2 * x1 * y1 + 2 * x2 * y2 + x2 * y1) * c;
        }
    }
    a /= 2;
    if (!(a > 0)) return s;
    const double cx = sx / (6 * a), cy = sy / (6 * a);
    s.area_mm2 = a;
    s.centroid_x_mm = cx + ox, s.centroid_y_mm = cy + oy;
    s.ixx_mm4 = ixx / 12 - a * cy * cy;
    s.iyy_mm4 = iyy / 12 - a * cx * cx;
    s.ixy_mm4 = ixy / 24 - a * cx * cy;
    const double mean = (s.ixx_mm4 + s.iyy_mm4) / 2, half = (s.ixx_mm4 - s.iyy_mm4) / 2;
    s.imin_mm4 = std::max(0.0, mean - std::hypot(half, s.ixy_mm4));
    return s;
}

class StrengthState {
  public:
    explicit StrengthState(double voxel_mm) : grid(voxel_mm, kMaxStreamVoxels) {}
    check::VoxelGrid grid;
    Paths previous;
    std::vector<SectionFigures> layers;
    double volume_mm3 = 0;
    double bottom_z = std::numeric_limits<double>::infinity(), top_z = 0;
};

StrengthMeter::StrengthMeter(const StrengthOptions& options)
    : opt_(options), state_(std::make_unique<StrengthState>(options.voxel_mm)) {}

StrengthMeter::~StrengthMeter() = default;

void StrengthMeter::layer(double z_mm, double height_mm, const Paths& footprint,
                          double volume_mm3) {
    StrengthState& s = *state_;
    SectionFigures f = section_of(footprint);
    f.z_mm = z_mm;
    f.height_mm = height_mm;
    if (!s.layers.empty())
        s.layers.back().bond_mm2 =
            check::region_area_mm2(check::intersection(s.previous, footprint));
    s.previous = footprint;
    s.layers.push_back(f);
    s.grid.add_layer(footprint, z_mm, height_mm);
    s.volume_mm3 += volume_mm3;
    s.bottom_z = std::min(s.bottom_z, z_mm - height_mm);
    s.top_z = std::max(s.top_z, z_mm);
}

namespace {

// The weakest section and bond between the tips (the model's own ends: a cone's tip is as weak
// as it is meant to be).
void find_weakest(StrengthFigures& f, double bottom_z, double top_z, double tips_mm) {
    const bool tall = top_z - bottom_z > 2 * tips_mm;
    auto inside = [&](double z) {
        return !tall || (z >= bottom_z + tips_mm - 1e-9 && z <= top_z - tips_mm + 1e-9);
    };
    bool have_section = false;
    for (const SectionFigures& l : f.layers) {
        if (!inside(l.z_mm)) continue;
        if (!have_section || l.imin_mm4 < f.weakest_section_mm4) {
            f.weakest_section_mm4 = l.imin_mm4, f.weakest_section_z_mm = l.z_mm;
            have_section = true;
        }
        if (l.bond_mm2 < 0) continue;
        if (!f.has_weakest_bond || l.bond_mm2 < f.weakest_bond_mm2) {
            f.weakest_bond_mm2 = l.bond_mm2, f.weakest_bond_z_mm = l.z_mm;
            f.has_weakest_bond = true;
        }
    }
}

}  // namespace

StrengthFigures StrengthMeter::finish() {
    StrengthState& s = *state_;
    StrengthFigures f;
    f.object_volume_mm3 = s.volume_mm3;
    f.grams = s.volume_mm3 * opt_.density_g_cm3 / 1000;
    f.layers = std::move(s.layers);
    find_weakest(f, s.bottom_z, s.top_z, opt_.tips_mm);
    f.law = opt_.solver.law == check::MaterialLaw::kCubic ? "cubic" : "linear";
    f.voxel_mm_asked = opt_.voxel_mm;
    f.young_mpa = opt_.solver.young_mpa, f.poisson = opt_.solver.poisson;
    std::vector<check::Voxel> voxels = s.grid.voxels();
    while (voxels.size() > static_cast<size_t>(opt_.max_voxels)) {
        s.grid.coarsen();
        voxels = s.grid.voxels();
    }
    f.voxel_mm = s.grid.cell_mm();
    f.coarsened = s.grid.coarsenings() > 0;
    if (f.coarsened)
        f.coarsened_note = fmt::format(
            "voxels of {:g} mm instead of {:g}: at {:g} mm more than {} voxels held filament, "
            "the most the solver takes",
            f.voxel_mm, f.voxel_mm_asked, f.voxel_mm / 2, opt_.max_voxels);
    const auto start = std::chrono::steady_clock::now();
    f.stiffness = check::solve_stiffness(voxels, f.voxel_mm, opt_.solver);
    f.solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (f.grams > 0) {
        f.compression_n_per_mm_per_g = f.stiffness.compression_n_per_mm / f.grams;
        f.shear_n_per_mm_per_g = f.stiffness.shear_n_per_mm / f.grams;
    }
    return f;
}

bool has_type_comments(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) return false;
    // Read in blocks, keeping the tail of each so that a comment across two is found.
    std::string carry;
    std::vector<char> block(1 << 16);
    bool found = false;
    for (size_t got; !found && (got = std::fread(block.data(), 1, block.size(), file)) > 0;) {
        carry.append(block.data(), got);
        found = carry.find(";TYPE:") != std::string::npos;
        if (carry.size() > 8) carry.erase(0, carry.size() - 8);
    }
    std::fclose(file);
    return found;
}

nlohmann::json to_json(const StrengthFigures& f) {
    const check::StiffnessFigures& k = f.stiffness;
    nlohmann::json layers = nlohmann::json::array();
    for (const SectionFigures& l : f.layers)
        layers.push_back(
            {{"z_mm", l.z_mm},
             {"height_mm", l.height_mm},
             {"area_mm2", l.area_mm2},
             {"centroid_mm", {l.centroid_x_mm, l.centroid_y_mm}},
             {"ixx_mm4", l.ixx_mm4},
             {"iyy_mm4", l.iyy_mm4},
             {"ixy_mm4", l.ixy_mm4},
             {"imin_mm4", l.imin_mm4},
             {"bond_mm2", l.bond_mm2 < 0 ? nlohmann::json() : nlohmann::json(l.bond_mm2)}});
    nlohmann::json j = {
        {"object_volume_mm3", f.object_volume_mm3},
        {"grams", f.grams},
        {"weakest_section_mm4", f.weakest_section_mm4},
        {"weakest_section_z_mm", f.weakest_section_z_mm},
        {"weakest_bond_mm2", f.has_weakest_bond ? nlohmann::json(f.weakest_bond_mm2) : nullptr},
        {"weakest_bond_z_mm", f.has_weakest_bond ? nlohmann::json(f.weakest_bond_z_mm) : nullptr},
        {"compression_n_per_mm", k.compression_n_per_mm},
        {"shear_n_per_mm", k.shear_n_per_mm},
        {"compression_n_per_mm_per_g", f.compression_n_per_mm_per_g},
        {"shear_n_per_mm_per_g", f.shear_n_per_mm_per_g},
        {"finite_elements",
         {{"law", f.law},
          {"young_mpa", f.young_mpa},
          {"poisson", f.poisson},
          {"voxel_mm_asked", f.voxel_mm_asked},
          {"voxel_mm", f.voxel_mm},
          {"coarsened", f.coarsened},
          {"coarsened_note", f.coarsened_note},
          {"voxels", k.elements},
          {"voxels_not_joined", k.dropped},
          {"nodes", k.nodes},
          {"iterations",
           {{"compression", k.iterations_compression}, {"shear", k.iterations_shear}}},
          {"residual", {{"compression", k.residual_compression}, {"shear", k.residual_shear}}},
          {"converged", k.converged},
          {"solve_s", f.solve_s}}},
        {"layers", std::move(layers)},
    };
    return j;
}

std::string describe_strength(const StrengthFigures& f, bool with_layers) {
    const check::StiffnessFigures& k = f.stiffness;
    std::string out = fmt::format(
        "object           {:.2f} g, {:.0f} mm3 (skirt, brim, supports, custom G-code left out)\n",
        f.grams, f.object_volume_mm3);
    out += fmt::format(
        "weakest section  {:.1f} mm4 at z = {:.2f} mm (smallest principal second "
        "moment of the footprint)\n",
        f.weakest_section_mm4, f.weakest_section_z_mm);
    if (f.has_weakest_bond)
        out += fmt::format(
            "weakest bond     {:.1f} mm2 at z = {:.2f} mm (footprint shared with the "
            "layer above)\n",
            f.weakest_bond_mm2, f.weakest_bond_z_mm);
    out += fmt::format("compression      {:.0f} N/mm, {:.1f} N/mm per g\n", k.compression_n_per_mm,
                       f.compression_n_per_mm_per_g);
    out += fmt::format("shear            {:.0f} N/mm, {:.1f} N/mm per g\n", k.shear_n_per_mm,
                       f.shear_n_per_mm_per_g);
    out += fmt::format(
        "finite elements  {} voxels of {:g} mm, {} law (E {:g} MPa x fraction{}, nu {:g}), {} "
        "not joined to the bed; {} + {} iterations, {:.1f} s\n",
        k.elements, f.voxel_mm, f.law, f.young_mpa, f.law == "cubic" ? "^3" : "", f.poisson,
        k.dropped, k.iterations_compression, k.iterations_shear, f.solve_s);
    if (f.coarsened) out += fmt::format("                 coarsened: {}\n", f.coarsened_note);
    if (!k.converged)
        out += fmt::format(
            "                 not converged: relative residual {:.1e} / {:.1e} after the "
            "iteration cap; the stiffness is approximate\n",
            k.residual_compression, k.residual_shear);
    if (!with_layers) return out;
    out += "\n     z mm   area mm2    Ixx mm4    Iyy mm4    Ixy mm4   Imin mm4   bond mm2\n";
    for (const SectionFigures& l : f.layers)
        out += fmt::format("{:9.2f}  {:9.1f}  {:9.0f}  {:9.0f}  {:9.0f}  {:9.0f}  {:>9}\n", l.z_mm,
                           l.area_mm2, l.ixx_mm4, l.iyy_mm4, l.ixy_mm4, l.imin_mm4,
                           l.bond_mm2 < 0 ? std::string("-") : fmt::format("{:.1f}", l.bond_mm2));
    return out;
}

}  // namespace carve
