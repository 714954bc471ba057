// The voxel finite elements of carve check --strength (see stiffness.hpp). The stiffness matrix
// is never assembled: every element is the same cube scaled by its modulus, so the product with
// a displacement is a loop over the elements with one 24 x 24 matrix, and memory is a few
// vectors of the nodes' size (an assembled matrix of 40,000 voxels took ~200 MB). Eigen's
// conjugate gradient runs on it through Eigen's matrix-free interface, preconditioned by the
// diagonal.
#include "check/stiffness.hpp"

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <unordered_map>

namespace carve::check {

namespace {

// A voxel whose modulus is under this share of the solid's adds nothing a figure shows and
// would only slow the solver (the cubic law makes a 4 % filled voxel 1e-4 of the solid).
constexpr double kMinModulusShare = 1e-4;

using Element24 = Eigen::Matrix<double, 24, 24>;
using Vector24 = Eigen::Matrix<double, 24, 1>;

// The elements (node indices, modulus times side) and the unit element's matrix.
struct Model {
    std::vector<std::array<int, 8>> nodes;
    std::vector<double> scale;
    Element24 unit;
    long long node_count = 0;

    // y = K x over every dof.
    void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
        y.setZero(x.size());
        Vector24 ue;
        for (size_t e = 0; e < nodes.size(); ++e) {
            for (int n = 0; n < 8; ++n) ue.segment<3>(3 * n) = x.segment<3>(3 * nodes[e][n]);
            const Vector24 fe = scale[e] * (unit * ue);
            for (int n = 0; n < 8; ++n) y.segment<3>(3 * nodes[e][n]) += fe.segment<3>(3 * n);
        }
    }
};

class FreeDofOperator;

}  // namespace

}  // namespace carve::check

// Eigen's matrix-free interface: the operator is told to be a sparse matrix's kind of thing.
namespace Eigen::internal {
template <>
struct traits<carve::check::FreeDofOperator>
    : public Eigen::internal::traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace carve::check {

namespace {

// The system the solver sees: K on the free dofs, the identity on the prescribed ones (their
// values are moved to the right-hand side), so that it stays symmetric positive definite.
class FreeDofOperator : public Eigen::EigenBase<FreeDofOperator> {
  public:
    using Scalar = double;
    using RealScalar = double;
    using StorageIndex = int;
    enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic };
    enum { IsRowMajor = false };

    FreeDofOperator(const Model& model, const std::vector<char>& fixed)
        : model_(model), fixed_(fixed) {}
    Eigen::Index rows() const { return static_cast<Eigen::Index>(fixed_.size()); }
    Eigen::Index cols() const { return rows(); }

    template <typename Rhs>
    Eigen::Product<FreeDofOperator, Rhs, Eigen::AliasFreeProduct> operator*(
        const Eigen::MatrixBase<Rhs>& x) const {
        return Eigen::Product<FreeDofOperator, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
    }

    void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
        Eigen::VectorXd free = x;
        for (size_t d = 0; d < fixed_.size(); ++d)
            if (fixed_[d]) free[static_cast<Eigen::Index>(d)] = 0;
        model_.multiply(free, y);
        for (size_t d = 0; d < fixed_.size(); ++d)
            if (fixed_[d]) y[static_cast<Eigen::Index>(d)] = x[static_cast<Eigen::Index>(d)];
    }

  private:
    const Model& model_;
    const std::vector<char>& fixed_;
};

// Jacobi: the inverse of the diagonal, given once the model is built.
class InverseDiagonal {
  public:
    InverseDiagonal() = default;
    template <typename M>
    explicit InverseDiagonal(const M&) {}
    template <typename M>
    InverseDiagonal& analyzePattern(const M&) {
        return *this;
    }
    template <typename M>
    InverseDiagonal& factorize(const M&) {
        return *this;
    }
    template <typename M>
    InverseDiagonal& compute(const M&) {
        return *this;
    }
    void set(Eigen::VectorXd inverse) { inverse_ = std::move(inverse); }
    template <typename Rhs>
    Eigen::VectorXd solve(const Rhs& b) const {
        return inverse_.cwiseProduct(b);
    }
    Eigen::ComputationInfo info() const { return Eigen::Success; }

  private:
    Eigen::VectorXd inverse_;
};

}  // namespace

}  // namespace carve::check

namespace Eigen::internal {

template <typename Rhs>
struct generic_product_impl<carve::check::FreeDofOperator, Rhs, SparseShape, DenseShape,
                            GemvProduct>
    : generic_product_impl_base<carve::check::FreeDofOperator, Rhs,
                                generic_product_impl<carve::check::FreeDofOperator, Rhs>> {
    template <typename Dest>
    static void scaleAndAddTo(Dest& dst, const carve::check::FreeDofOperator& lhs, const Rhs& rhs,
                              const double& alpha) {
        const Eigen::VectorXd x = rhs;
        Eigen::VectorXd y;
        lhs.apply(x, y);
        dst += alpha * y;
    }
};

}  // namespace Eigen::internal

namespace carve::check {

std::vector<double> unit_cube_stiffness(double nu) {
    // Exact for the trilinear cube: 2 x 2 x 2 Gauss points integrate B^T D B (quadratic in each
    // coordinate) without error, so this is the closed-form matrix to rounding.
    const double lambda = nu / ((1 + nu) * (1 - 2 * nu)), mu = 1 / (2 * (1 + nu));
    Eigen::Matrix<double, 6, 6> d = Eigen::Matrix<double, 6, 6>::Zero();
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) d(a, b) = lambda;
        d(a, a) = lambda + 2 * mu;
        d(a + 3, a + 3) = mu;
    }
    const double g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
    Element24 k = Element24::Zero();
    for (int p = 0; p < 8; ++p) {
        const double t[3] = {g[p & 1], g[p >> 1 & 1], g[p >> 2]};
        Eigen::Matrix<double, 6, 24> b = Eigen::Matrix<double, 6, 24>::Zero();
        for (int n = 0; n < 8; ++n) {
            const int c[3] = {n & 1, n >> 1 & 1, n >> 2};
            double f[3], df[3];
            for (int a = 0; a < 3; ++a) {
                f[a] = c[a] ? t[a] : 1 - t[a];
                df[a] = c[a] ? 1 : -1;
            }
            const double dx = df[0] * f[1] * f[2], dy = f[0] * df[1] * f[2],
                         dz = f[0] * f[1] * df[2];
            b(0, 3 * n) = dx, b(1, 3 * n + 1) = dy, b(2, 3 * n + 2) = dz;
            b(3, 3 * n + 1) = dz, b(3, 3 * n + 2) = dy;  // gamma yz
            b(4, 3 * n) = dz, b(4, 3 * n + 2) = dx;      // gamma xz
            b(5, 3 * n) = dy, b(5, 3 * n + 1) = dx;      // gamma xy
        }
        k += b.transpose() * d * b / 8.0;
    }
    return std::vector<double>(k.data(), k.data() + 24 * 24);
}

namespace {

struct CellKey {
    int i, j, k;
    bool operator==(const CellKey& o) const { return i == o.i && j == o.j && k == o.k; }
};
struct CellHash {
    size_t operator()(const CellKey& key) const {
        uint64_t h = static_cast<uint32_t>(key.i);
        h = h * 0x9E3779B97F4A7C15ULL ^ static_cast<uint32_t>(key.j);
        h = h * 0x9E3779B97F4A7C15ULL ^ static_cast<uint32_t>(key.k);
        return static_cast<size_t>(h ^ (h >> 29));
    }
};

double modulus_share(double fraction, MaterialLaw law) {
    return law == MaterialLaw::kCubic ? fraction * fraction * fraction : fraction;
}

struct Built {
    Model model;
    std::vector<int> bottom, top;  // nodes on the bed's plane and on the top plane
};

// The voxels stiff enough to count and joined to the bed through faces (a piece joined by an
// edge or a corner alone would turn on it, and one standing on nothing carries no load).
std::vector<const Voxel*> joined_to_bed(const std::vector<Voxel>& voxels, MaterialLaw law) {
    std::unordered_map<CellKey, int, CellHash> index;
    std::vector<const Voxel*> solid;
    int k_min = 0;
    for (const Voxel& v : voxels) {
        if (modulus_share(v.fraction, law) < kMinModulusShare) continue;
        k_min = solid.empty() ? v.k : std::min(k_min, v.k);
        index[{v.i, v.j, v.k}] = static_cast<int>(solid.size());
        solid.push_back(&v);
    }
    std::vector<char> kept(solid.size(), 0);
    std::deque<int> queue;
    for (size_t n = 0; n < solid.size(); ++n)
        if (solid[n]->k == k_min) kept[n] = 1, queue.push_back(static_cast<int>(n));
    static constexpr int kFaces[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                         {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    while (!queue.empty()) {
        const Voxel& v = *solid[static_cast<size_t>(queue.front())];
        queue.pop_front();
        for (const auto& d : kFaces) {
            auto it = index.find({v.i + d[0], v.j + d[1], v.k + d[2]});
            if (it == index.end() || kept[static_cast<size_t>(it->second)]) continue;
            kept[static_cast<size_t>(it->second)] = 1;
            queue.push_back(it->second);
        }
    }
    std::vector<const Voxel*> out;
    for (size_t n = 0; n < solid.size(); ++n)
        if (kept[n]) out.push_back(solid[n]);
    return out;
}

Built build(const std::vector<Voxel>& voxels, double cell_mm, const StiffnessOptions& o,
            StiffnessFigures& f) {
    Built b;
    const std::vector<const Voxel*> kept = joined_to_bed(voxels, o.law);
    for (const Voxel& v : voxels)
        if (v.fraction > 0) ++f.dropped;
    f.dropped -= static_cast<long long>(kept.size());
    if (kept.empty()) return b;
    const std::vector<double> unit = unit_cube_stiffness(o.poisson);
    b.model.unit = Eigen::Map<const Element24>(unit.data());
    std::unordered_map<CellKey, int, CellHash> node_index;
    int k_min = kept.front()->k, k_max = k_min;
    for (const Voxel* v : kept) k_min = std::min(k_min, v->k), k_max = std::max(k_max, v->k);
    for (const Voxel* v : kept) {
        std::array<int, 8> nodes;
        for (int n = 0; n < 8; ++n) {
            const CellKey key{v->i + (n & 1), v->j + (n >> 1 & 1), v->k + (n >> 2)};
            auto [it, added] = node_index.try_emplace(key, static_cast<int>(node_index.size()));
            nodes[static_cast<size_t>(n)] = it->second;
            if (added && key.k == k_min) b.bottom.push_back(it->second);
            if (added && key.k == k_max + 1) b.top.push_back(it->second);
        }
        b.model.nodes.push_back(nodes);
        // An element's stiffness grows with its side: K = E * a * K(unit cube).
        b.model.scale.push_back(o.young_mpa * modulus_share(v->fraction, o.law) * cell_mm);
    }
    b.model.node_count = static_cast<long long>(node_index.size());
    f.elements = static_cast<long long>(kept.size());
    f.nodes = b.model.node_count;
    return b;
}

// The bed holds every bottom node; the top nodes move by 1 mm along `axis` (the others free, or
// held at 0 with hold_others). Returns the top's reaction along the axis, N per mm.
double solve_case(const Built& b, int axis, double direction, bool hold_others,
                  const StiffnessOptions& o, int& iterations, double& residual, bool& converged) {
    const Eigen::Index dofs = 3 * static_cast<Eigen::Index>(b.model.node_count);
    std::vector<char> fixed(static_cast<size_t>(dofs), 0);
    Eigen::VectorXd prescribed = Eigen::VectorXd::Zero(dofs);
    for (int n : b.bottom)
        for (int a = 0; a < 3; ++a) fixed[static_cast<size_t>(3 * n + a)] = 1;
    for (int n : b.top) {
        fixed[static_cast<size_t>(3 * n + axis)] = 1;
        prescribed[3 * n + axis] = direction;
        if (hold_others)
            for (int a = 0; a < 3; ++a) fixed[static_cast<size_t>(3 * n + a)] = 1;
    }
    Eigen::VectorXd rhs;
    b.model.multiply(prescribed, rhs);
    rhs = -rhs;
    Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(dofs);
    for (size_t e = 0; e < b.model.nodes.size(); ++e)
        for (int l = 0; l < 24; ++l)
            diagonal[3 * b.model.nodes[e][static_cast<size_t>(l / 3)] + l % 3] +=
                b.model.scale[e] * b.model.unit(l, l);
    for (Eigen::Index d = 0; d < dofs; ++d)
        if (fixed[static_cast<size_t>(d)] || diagonal[d] <= 0) rhs[d] = 0, diagonal[d] = 1;
    FreeDofOperator op(b.model, fixed);
    Eigen::ConjugateGradient<FreeDofOperator, Eigen::Lower | Eigen::Upper, InverseDiagonal> cg;
    cg.setMaxIterations(o.max_iterations);
    cg.setTolerance(o.tolerance);
    cg.compute(op);
    cg.preconditioner().set(diagonal.cwiseInverse());
    Eigen::VectorXd u = cg.solve(rhs);
    iterations = static_cast<int>(cg.iterations());
    residual = cg.error();
    converged = converged && cg.info() == Eigen::Success;
    u += prescribed;
    Eigen::VectorXd force;
    b.model.multiply(u, force);
    double reaction = 0;
    for (int n : b.top) reaction += force[3 * n + axis];
    return std::fabs(reaction);
}

}  // namespace

StiffnessFigures solve_stiffness(const std::vector<Voxel>& voxels, double cell_mm,
                                 const StiffnessOptions& options) {
    StiffnessFigures f;
    const Built b = build(voxels, cell_mm, options, f);
    if (b.model.nodes.empty() || b.top.empty()) return f;
    // Compression: a frictionless plate pushes the top down, which may spread (a solid block
    // then gives E A / L but for the bed's hold). Shear: a plate glued to the top moves it
    // sideways, held level.
    f.compression_n_per_mm = solve_case(b, 2, -1.0, false, options, f.iterations_compression,
                                        f.residual_compression, f.converged);
    f.shear_n_per_mm =
        solve_case(b, 0, 1.0, true, options, f.iterations_shear, f.residual_shear, f.converged);
    return f;
}

}  // namespace carve::check
