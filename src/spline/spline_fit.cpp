#include "ricci/spline/spline_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
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

/// Accumulates triplets in batches summed into one matrix (bounded memory on large meshes).
class Assembler {
 public:
  explicit Assembler(int n) : matrix_(n, n) { triplets_.reserve(kBatch); }
  void add(int i, int j, double value) {
    triplets_.emplace_back(i, j, value);
    if (triplets_.size() >= kBatch) flush();
  }
  Eigen::SparseMatrix<double> finish() {
    flush();
    Eigen::SparseMatrix<double> out;
    out.swap(matrix_);  // (the conversion would copy a moved member)
    return out;
  }

 private:
  static constexpr std::size_t kBatch = 1 << 22;
  void flush() {
    if (triplets_.empty()) return;
    Eigen::SparseMatrix<double> part(matrix_.rows(), matrix_.cols());
    part.setFromTriplets(triplets_.begin(), triplets_.end());
    matrix_ = matrix_.nonZeros() == 0 ? part : Eigen::SparseMatrix<double>(matrix_ + part);
    triplets_.clear();
  }
  Eigen::SparseMatrix<double> matrix_;
  std::vector<Triplet> triplets_;
};

/// Unknowns: per referenced vertex its value, then its gradient unless held at 0.
struct Unknowns {
  std::vector<int> value_dof, gradient_dof;  ///< per vertex; -1 where none
  int count = 0;
  /// The unknowns of a face's 9 nodal parameters (values, then gradients, corner by corner).
  std::array<int, 9> face(const SplineDomain& d, int f) const {
    std::array<int, 9> dofs;
    for (int c = 0; c < 3; ++c) {
      const int v = d.triangles(f, c);
      dofs[c] = value_dof[v];
      dofs[3 + 2 * c] = gradient_dof[v] < 0 ? -1 : gradient_dof[v];
      dofs[4 + 2 * c] = gradient_dof[v] < 0 ? -1 : gradient_dof[v] + 1;
    }
    return dofs;
  }
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

/// Adds a local matrix over `dofs` (-1: no unknown) to the assembler.
template <int N>
void scatter(const Eigen::Matrix<double, N, N>& local, const std::array<int, N>& dofs,
             Assembler& assembler) {
  for (int i = 0; i < N; ++i) {
    if (dofs[i] < 0) continue;
    for (int j = 0; j < N; ++j) {
      if (dofs[j] >= 0) assembler.add(dofs[i], dofs[j], local(i, j));
    }
  }
}

/// The smoothness matrix S: the weighted jumps of the Hessian across the inner edges of each
/// face's split (between its pieces), then across the mesh's edges (between the pieces of the
/// two faces, g's Hessian rotated into f's chart).
Eigen::SparseMatrix<double> smoothness_matrix(const SplineDomain& d, const Unknowns& unknowns) {
  const int nf = static_cast<int>(d.triangles.rows());
  const Eigen::DiagonalMatrix<double, 3> frob(kFrobenius);
  const std::vector<double> local_weight = local_weights(d);
  Assembler s_assembler(unknowns.count);
  for (int f = 0; f < nf; ++f) {
    const std::array<HessianMap, kPowellSabinPieces> g = piece_maps(d, f);
    Eigen::Matrix<double, 9, 9> local = Eigen::Matrix<double, 9, 9>::Zero();
    for (int p = 0; p < kPowellSabinPieces; ++p) {
      const std::array<Eigen::Vector2d, 3> tri = piece_triangle(d, f, p);
      const double len = (tri[1] - tri[2]).norm();  // shared with piece p + 1
      const HessianMap diff = g[p] - g[(p + 1) % kPowellSabinPieces];
      local += local_weight[f] * len * diff.transpose() * frob * diff;
    }
    scatter<9>(local, unknowns.face(d, f), s_assembler);
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
    const std::array<int, 9> dofs_f = unknowns.face(d, f), dofs_g = unknowns.face(d, g);
    std::array<int, 18> dofs;
    for (int i = 0; i < 9; ++i) dofs[i] = dofs_f[i], dofs[9 + i] = dofs_g[i];
    scatter<18>(local, dofs, s_assembler);
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

  // A = (data term on the values) + W S; b = data.
  Eigen::SparseMatrix<double> fit_term(n, n);
  {
    std::vector<Triplet> diag;
    for (int v = 0; v < nv; ++v) {
      const int dof = unknowns.value_dof[v];
      if (dof >= 0) diag.emplace_back(dof, dof, 1.0);
    }
    fit_term.setFromTriplets(diag.begin(), diag.end());
  }
  Eigen::SparseMatrix<double> a = fit_term + fit.weight * smoothness;
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
