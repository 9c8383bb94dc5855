#include "ricci/spline/spline_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

#include "ricci/errors.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {
namespace {

using Triplet = Eigen::Triplet<double>;
using HessianMap = Eigen::Matrix<double, 3, 9>;

/// Frobenius weights of (Hxx, Hxy, Hyy): |H|_F^2 = Hxx^2 + 2 Hxy^2 + Hyy^2.
const Eigen::Vector3d kFrobenius(1, 2, 1);

/// H' = R H R^T on (Hxx, Hxy, Hyy) for the rotation by angle arg(a).
Eigen::Matrix3d rotate_hessian(std::complex<double> a) {
  const double c = a.real(), s = a.imag();
  Eigen::Matrix3d t;
  t << c * c, -2 * c * s, s * s,     //
      c * s, c * c - s * s, -c * s,  //
      s * s, 2 * c * s, c * c;
  return t;
}

/// Unknowns: per referenced vertex its value, then its gradient unless held at 0.
struct Unknowns {
  std::vector<int> value_dof, gradient_dof;  ///< per vertex; -1 where none
  int count = 0;
};

Unknowns number_unknowns(const SplineDomain& d) {
  Unknowns u{std::vector<int>(d.num_vertices, -1), std::vector<int>(d.num_vertices, -1), 0};
  for (int v = 0; v < d.num_vertices; ++v) {
    if (!d.referenced[v]) continue;
    u.value_dof[v] = u.count++;
    if (!d.fixed_gradient[v]) {
      u.gradient_dof[v] = u.count;
      u.count += 2;
    }
  }
  return u;
}

/// Sums the local matrices of S into 3 by 3 blocks, one per pair of vertices that share a face
/// or the two faces of an edge, and writes the matrix once at the end. (Summing batches of
/// triplets into the matrix copied all of it at every batch: 101 s of a 107 s fit on a 270k-face
/// scan, with 2 GB at its peak.) A vertex's unknowns are consecutive (its value, then its
/// gradient) and numbered in vertex order, so each block is a dense piece of a column.
class BlockAssembler {
 public:
  BlockAssembler(const SplineDomain& d, const Unknowns& unknowns) : unknowns_(unknowns) {
    const int nv = d.num_vertices;
    std::vector<std::vector<int>> near(nv);
    auto link = [&](std::span<const int> corners) {
      for (const int a : corners) {
        for (const int b : corners) near[b].push_back(a);
      }
    };
    const int nf = static_cast<int>(d.triangles.rows());
    for (int h = 0; h < 3 * nf; ++h) {
      const int h2 = d.halfedge_twin[h];
      if (h2 >= 0 && h2 < h) continue;
      const std::array<int, 6> corners = diamond(d, h);
      link(std::span<const int>(corners.data(), h2 < 0 ? 3 : 6));
    }
    start_.assign(nv + 1, 0);
    for (int v = 0; v < nv; ++v) {
      std::sort(near[v].begin(), near[v].end());
      near[v].erase(std::unique(near[v].begin(), near[v].end()), near[v].end());
      start_[v + 1] = start_[v] + static_cast<int>(near[v].size());
    }
    neighbour_.reserve(start_[nv]);
    for (int v = 0; v < nv; ++v) {
      neighbour_.insert(neighbour_.end(), near[v].begin(), near[v].end());
      std::vector<int>().swap(near[v]);
    }
    blocks_.assign(static_cast<std::size_t>(start_[nv]) * 9, 0.0);
  }

  /// Adds `local` over the nodal parameters of the faces whose corners are `corners` (3 a face),
  /// face after face: the 3 corners' values, then their gradients (x, y) corner by corner.
  template <int N>
  void add(const Eigen::Matrix<double, N, N>& local, const std::array<int, N / 3>& corners) {
    constexpr int kCorners = N / 3;
    std::array<int, N> corner_of{}, component_of{};
    for (int i = 0; i < N; ++i) {
      const int face = i / 9, r = i % 9;
      corner_of[i] = 3 * face + (r < 3 ? r : (r - 3) / 2);
      component_of[i] = r < 3 ? 0 : 1 + (r - 3) % 2;
    }
    std::array<int, kCorners * kCorners> block{};  // (row corner, column corner) -> block
    for (int a = 0; a < kCorners; ++a) {
      for (int b = 0; b < kCorners; ++b) block[a * kCorners + b] = slot(corners[b], corners[a]);
    }
    for (int j = 0; j < N; ++j) {
      const int vj = corners[corner_of[j]];
      if (!has(vj, component_of[j])) continue;
      for (int i = 0; i < N; ++i) {
        const int vi = corners[corner_of[i]];
        if (!has(vi, component_of[i])) continue;
        const int s = block[corner_of[i] * kCorners + corner_of[j]];
        blocks_[static_cast<std::size_t>(s) * 9 + 3 * component_of[j] + component_of[i]] +=
            local(i, j);
      }
    }
  }

  Eigen::SparseMatrix<double> finish() const {
    const int n = unknowns_.count, nv = static_cast<int>(start_.size()) - 1;
    Eigen::SparseMatrix<double> m(n, n);
    std::vector<int> column_size(n, 0);
    for (int v = 0; v < nv; ++v) {
      int rows = 0;
      for (int s = start_[v]; s < start_[v + 1]; ++s) rows += size(neighbour_[s]);
      for (int c = 0; c < size(v); ++c) column_size[unknowns_.value_dof[v] + c] = rows;
    }
    m.reserve(column_size);
    for (int v = 0; v < nv; ++v) {
      for (int c = 0; c < size(v); ++c) {
        const int column = unknowns_.value_dof[v] + c;
        for (int s = start_[v]; s < start_[v + 1]; ++s) {
          const int w = neighbour_[s];
          for (int r = 0; r < size(w); ++r) {
            m.insert(unknowns_.value_dof[w] + r, column) = blocks_[std::size_t(s) * 9 + 3 * c + r];
          }
        }
      }
    }
    m.makeCompressed();
    return m;
  }

  /// The corners of halfedge h's face, then (when h has a twin) those of its twin's face.
  static std::array<int, 6> diamond(const SplineDomain& d, int h) {
    std::array<int, 6> corners{};
    const int f = h / 3, g = d.halfedge_twin[h] / 3;
    for (int c = 0; c < 3; ++c) corners[c] = d.triangles(f, c);
    if (d.halfedge_twin[h] >= 0) {
      for (int c = 0; c < 3; ++c) corners[3 + c] = d.triangles(g, c);
    }
    return corners;
  }

 private:
  /// The number of unknowns of vertex v (0, 1 or 3).
  int size(int v) const {
    if (unknowns_.value_dof[v] < 0) return 0;
    return unknowns_.gradient_dof[v] < 0 ? 1 : 3;
  }
  bool has(int v, int component) const { return component < size(v); }
  /// The block of row vertex `row` in column vertex `column`'s list.
  int slot(int column, int row) const {
    const auto first = neighbour_.begin() + start_[column];
    const auto last = neighbour_.begin() + start_[column + 1];
    return static_cast<int>(std::lower_bound(first, last, row) - neighbour_.begin());
  }

  const Unknowns& unknowns_;
  std::vector<int> start_, neighbour_;  ///< per vertex, its block neighbours (sorted)
  std::vector<double> blocks_;          ///< 9 per block, column-major (column component major)
};

/// The Hessian of each Powell-Sabin piece of face f as a map of its 9 nodal parameters.
std::array<HessianMap, kPowellSabinPieces> piece_maps(const SplineDomain& d, int f) {
  const Eigen::Matrix<double, kPowellSabinOrdinates, 9> o = face_ordinate_map(d, f);
  std::array<HessianMap, kPowellSabinPieces> g;
  for (int p = 0; p < kPowellSabinPieces; ++p) g[p] = piece_hessian_map(d, f, p) * o;
  return g;
}

/// Each face's jump weight, (local chart size / mean)^3: the power that makes |H_a - H_b|^2
/// times a length invariant when the chart is scaled. A conformal map shrinks some regions by
/// orders of magnitude (the Stanford bunny's holes by e^16), and a uniform weight there would
/// smooth the shrunk charts flat (distance errors of 70 % of the bounding box); with local
/// weights every region trades smoothness against data alike.
std::vector<double> local_weights(const SplineDomain& d) {
  const int nf = static_cast<int>(d.triangles.rows());
  std::vector<double> local_weight(nf);
  for (int f = 0; f < nf; ++f) {
    double perimeter = 0;
    for (int c = 0; c < 3; ++c) {
      const int j = (c + 1) % 3;
      perimeter += std::hypot(d.corner_uv(f, 2 * j) - d.corner_uv(f, 2 * c),
                              d.corner_uv(f, 2 * j + 1) - d.corner_uv(f, 2 * c + 1));
    }
    local_weight[f] = std::pow(perimeter / 3 / d.mean_edge_length, 3);
  }
  return local_weight;
}

/// The smoothness matrix S: the weighted jumps of the Hessian across the inner edges of each
/// face's split (between its pieces), then across the mesh's edges (between the pieces of the
/// two faces, g's Hessian rotated into f's chart).
Eigen::SparseMatrix<double> smoothness_matrix(const SplineDomain& d, const Unknowns& unknowns) {
  const int nf = static_cast<int>(d.triangles.rows());
  const Eigen::DiagonalMatrix<double, 3> frob(kFrobenius);
  const std::vector<double> local_weight = local_weights(d);
  BlockAssembler s_assembler(d, unknowns);
  for (int f = 0; f < nf; ++f) {
    const std::array<HessianMap, kPowellSabinPieces> g = piece_maps(d, f);
    Eigen::Matrix<double, 9, 9> local = Eigen::Matrix<double, 9, 9>::Zero();
    for (int p = 0; p < kPowellSabinPieces; ++p) {
      const std::array<Eigen::Vector2d, 3> tri = piece_triangle(d, f, p);
      const double len = (tri[1] - tri[2]).norm();  // shared with piece p + 1
      const HessianMap diff = g[p] - g[(p + 1) % kPowellSabinPieces];
      local += local_weight[f] * len * diff.transpose() * frob * diff;
    }
    s_assembler.add<9>(local, {d.triangles(f, 0), d.triangles(f, 1), d.triangles(f, 2)});
  }
  for (int h = 0; h < 3 * nf; ++h) {
    const int h2 = d.halfedge_twin[h];
    if (h2 < 0 || h2 < h) continue;
    const int f = h / 3, kf = h % 3, g = h2 / 3, kg = h2 % 3;
    const std::array<HessianMap, kPowellSabinPieces> gf = piece_maps(d, f);
    const std::array<HessianMap, kPowellSabinPieces> gg = piece_maps(d, g);
    const Eigen::Matrix3d t = rotate_hessian(d.halfedge_rotation[h]);
    Eigen::Matrix<double, 18, 18> local = Eigen::Matrix<double, 18, 18>::Zero();
    // f's piece 2 kf (P, R) meets g's piece 2 kg + 1 (R, P); f's 2 kf + 1 (R, Q) meets g's 2 kg.
    for (int side = 0; side < 2; ++side) {
      const int pf = 2 * kf + side, pg = 2 * kg + 1 - side;
      const std::array<Eigen::Vector2d, 3> tri = piece_triangle(d, f, pf);
      const double len = (tri[1] - tri[0]).norm();
      Eigen::Matrix<double, 3, 18> diff;
      diff.leftCols<9>() = gf[pf];
      diff.rightCols<9>() = -t * gg[pg];
      local += std::sqrt(local_weight[f] * local_weight[g]) * len * diff.transpose() * frob * diff;
    }
    s_assembler.add<18>(local, BlockAssembler::diamond(d, h));
  }
  return s_assembler.finish();
}

/// The regularisation added to the gradient unknowns when A is not numerically definite (a
/// gradient no term constrains), relative to A's largest diagonal entry: far below every
/// constrained entry, far above the rounding that broke the factorisation.
constexpr double kGradientRegularization = 1e-12;

/// Factorises `a`; when it is not definite, adds kGradientRegularization times its largest
/// diagonal entry to the gradient unknowns and factorises again (sets fit.regularized).
void factorize_regularized(Eigen::SparseMatrix<double>& a, const Unknowns& unknowns,
                           SparseCholesky& solver, SplineFit& fit) {
  const int n = unknowns.count;
  solver.analyze(a);
  try {
    solver.factorize(a);
  } catch (const SolverError&) {
    double largest = 0;
    for (int i = 0; i < n; ++i) largest = std::max(largest, a.coeff(i, i));
    std::vector<Triplet> reg;
    for (const int dof : unknowns.gradient_dof) {
      if (dof < 0) continue;
      reg.emplace_back(dof, dof, kGradientRegularization * largest);
      reg.emplace_back(dof + 1, dof + 1, kGradientRegularization * largest);
    }
    Eigen::SparseMatrix<double> r(n, n);
    r.setFromTriplets(reg.begin(), reg.end());
    a += r;
    solver.factorize(a);
    fit.regularized = true;
  }
}

/// Solves A x = b column by column with `refinement_steps` steps of iterative refinement; sets
/// fit.solve_residual (the largest relative residual).
Eigen::MatrixXd solve_refined(const SparseCholesky& solver, const Eigen::SparseMatrix<double>& a,
                              const Eigen::MatrixXd& b, int refinement_steps, SplineFit& fit) {
  Eigen::MatrixXd x(b.rows(), b.cols());
  for (int col = 0; col < b.cols(); ++col) {
    Eigen::VectorXd xc = solver.solve(b.col(col));
    for (int step = 0; step < refinement_steps; ++step) {
      xc += solver.solve(b.col(col) - a * xc);
    }
    const double bn = b.col(col).norm();
    const double res = (b.col(col) - a * xc).norm();
    fit.solve_residual = std::max(fit.solve_residual, bn > 0 ? res / bn : res);
    x.col(col) = xc;
  }
  return x;
}

/// The solution back to vertex data (values and gradients), with the data energy.
void unpack_solution(const Eigen::MatrixXd& x, const Eigen::MatrixXd& data,
                     const Unknowns& unknowns, SplineFit& fit) {
  const int nv = static_cast<int>(data.rows()), k = static_cast<int>(data.cols());
  fit.data.values = data;
  fit.data.gradients = Eigen::MatrixXd::Zero(nv, 2 * k);
  for (int v = 0; v < nv; ++v) {
    const int value = unknowns.value_dof[v], gradient = unknowns.gradient_dof[v];
    if (value < 0) continue;
    fit.data.values.row(v) = x.row(value);
    fit.data_energy += (x.row(value) - data.row(v)).squaredNorm();
    if (gradient < 0) continue;
    for (int col = 0; col < k; ++col) {
      fit.data.gradients(v, 2 * col) = x(gradient, col);
      fit.data.gradients(v, 2 * col + 1) = x(gradient + 1, col);
    }
  }
}

}  // namespace

SplineFit fit_spline(const SplineDomain& d, const Eigen::MatrixXd& data,
                     const SplineFitOptions& options) {
  const auto start = Clock::now();
  if (data.rows() != d.num_vertices) {
    throw InvalidInput("fit_spline: data has " + std::to_string(data.rows()) + " rows for " +
                       std::to_string(d.num_vertices) + " vertices");
  }
  if (!(options.smoothness > 0) || !std::isfinite(options.smoothness)) {
    throw InvalidInput("fit_spline: smoothness must be finite and > 0, got " +
                       std::to_string(options.smoothness));
  }
  const int nv = d.num_vertices;
  const int k = static_cast<int>(data.cols());
  for (int v = 0; v < nv; ++v) {
    if (d.referenced[v] && !data.row(v).allFinite()) {
      throw InvalidInput("fit_spline: data of vertex " + std::to_string(v) + " is not finite");
    }
  }
  const Unknowns unknowns = number_unknowns(d);
  const int n = unknowns.count;
  SplineFit fit;
  fit.num_unknowns = n;
  fit.weight = options.smoothness * std::pow(d.mean_edge_length, 3);
  const Eigen::SparseMatrix<double> smoothness = smoothness_matrix(d, unknowns);

  // A = (data term on the values) + W S; b = data. S holds every value's diagonal entry (each
  // vertex's block with itself), so the data term is added in place.
  Eigen::SparseMatrix<double> a = fit.weight * smoothness;
  for (int v = 0; v < nv; ++v) {
    const int dof = unknowns.value_dof[v];
    if (dof >= 0) a.coeffRef(dof, dof) += 1.0;
  }
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, k);
  for (int v = 0; v < nv; ++v) {
    if (unknowns.value_dof[v] >= 0) b.row(unknowns.value_dof[v]) = data.row(v);
  }
  SparseCholesky solver;
  factorize_regularized(a, unknowns, solver, fit);
  fit.solver = solver.backend();
  const Eigen::MatrixXd x = solve_refined(solver, a, b, options.refinement_steps, fit);
  unpack_solution(x, data, unknowns, fit);
  for (int col = 0; col < k; ++col) {
    fit.smoothness_energy += x.col(col).dot(smoothness * x.col(col));
  }
  fit.ordinates = face_ordinates(d, fit.data);
  fit.seconds = seconds_since(start);
  return fit;
}

}  // namespace ricci
