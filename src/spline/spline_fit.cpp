#include "ricci/spline/spline_fit.hpp"

#include <chrono>
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
  const int nf = static_cast<int>(d.triangles.rows());
  const int k = static_cast<int>(data.cols());
  for (int v = 0; v < nv; ++v) {
    if (d.referenced[v] && !data.row(v).allFinite()) {
      throw InvalidInput("fit_spline: data of vertex " + std::to_string(v) + " is not finite");
    }
  }

  // Unknowns: per referenced vertex its value, then its gradient unless held at 0.
  std::vector<int> value_dof(nv, -1), gradient_dof(nv, -1);
  int n = 0;
  for (int v = 0; v < nv; ++v) {
    if (!d.referenced[v]) continue;
    value_dof[v] = n++;
    if (!d.fixed_gradient[v]) {
      gradient_dof[v] = n;
      n += 2;
    }
  }
  auto face_dofs = [&](int f) {
    std::array<int, 9> dofs;
    for (int c = 0; c < 3; ++c) {
      const int v = d.triangles(f, c);
      dofs[c] = value_dof[v];
      dofs[3 + 2 * c] = gradient_dof[v] < 0 ? -1 : gradient_dof[v];
      dofs[4 + 2 * c] = gradient_dof[v] < 0 ? -1 : gradient_dof[v] + 1;
    }
    return dofs;
  };
  auto piece_maps = [&](int f) {
    const Eigen::Matrix<double, kPowellSabinOrdinates, 9> o = face_ordinate_map(d, f);
    std::array<HessianMap, kPowellSabinPieces> g;
    for (int p = 0; p < kPowellSabinPieces; ++p) g[p] = piece_hessian_map(d, f, p) * o;
    return g;
  };

  SplineFit fit;
  fit.num_unknowns = n;
  fit.weight = options.smoothness * std::pow(d.mean_edge_length, 3);
  const Eigen::DiagonalMatrix<double, 3> frob(kFrobenius);

  // Smoothness matrix S. Each jump term is weighted by (local chart size / mean)^3, the power
  // that makes |H_a - H_b|^2 times a length invariant when the chart is scaled: a conformal
  // map shrinks some regions by orders of magnitude (the Stanford bunny's holes by e^16), and a
  // uniform weight there would smooth the shrunk charts flat (distance errors of 70 % of the
  // bounding box); with local weights every region trades smoothness against data alike.
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
  Assembler s_assembler(n);
  for (int f = 0; f < nf; ++f) {
    const std::array<int, 9> dofs = face_dofs(f);
    const std::array<HessianMap, kPowellSabinPieces> g = piece_maps(f);
    Eigen::Matrix<double, 9, 9> local = Eigen::Matrix<double, 9, 9>::Zero();
    for (int p = 0; p < kPowellSabinPieces; ++p) {
      const std::array<Eigen::Vector2d, 3> tri = piece_triangle(d, f, p);
      const double len = (tri[1] - tri[2]).norm();  // shared with piece p + 1
      const HessianMap diff = g[p] - g[(p + 1) % kPowellSabinPieces];
      local += local_weight[f] * len * diff.transpose() * frob * diff;
    }
    for (int i = 0; i < 9; ++i) {
      if (dofs[i] < 0) continue;
      for (int j = 0; j < 9; ++j) {
        if (dofs[j] >= 0) s_assembler.add(dofs[i], dofs[j], local(i, j));
      }
    }
  }
  for (int h = 0; h < 3 * nf; ++h) {
    const int h2 = d.halfedge_twin[h];
    if (h2 < 0 || h2 < h) continue;
    const int f = h / 3, kf = h % 3, g = h2 / 3, kg = h2 % 3;
    const std::array<HessianMap, kPowellSabinPieces> gf = piece_maps(f);
    const std::array<HessianMap, kPowellSabinPieces> gg = piece_maps(g);
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
    const std::array<int, 9> dofs_f = face_dofs(f), dofs_g = face_dofs(g);
    std::array<int, 18> dofs;
    for (int i = 0; i < 9; ++i) dofs[i] = dofs_f[i], dofs[9 + i] = dofs_g[i];
    for (int i = 0; i < 18; ++i) {
      if (dofs[i] < 0) continue;
      for (int j = 0; j < 18; ++j) {
        if (dofs[j] >= 0) s_assembler.add(dofs[i], dofs[j], local(i, j));
      }
    }
  }
  const Eigen::SparseMatrix<double> smoothness = s_assembler.finish();

  // A = (data term on the values) + W S; b = data.
  Eigen::SparseMatrix<double> fit_term(n, n);
  {
    std::vector<Triplet> diag;
    for (int v = 0; v < nv; ++v) {
      if (value_dof[v] >= 0) diag.emplace_back(value_dof[v], value_dof[v], 1.0);
    }
    fit_term.setFromTriplets(diag.begin(), diag.end());
  }
  Eigen::SparseMatrix<double> a = fit_term + fit.weight * smoothness;
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, k);
  for (int v = 0; v < nv; ++v) {
    if (value_dof[v] >= 0) b.row(value_dof[v]) = data.row(v);
  }

  SparseCholesky solver;
  solver.analyze(a);
  try {
    solver.factorize(a);
  } catch (const SolverError&) {
    double largest = 0;
    for (int i = 0; i < n; ++i) largest = std::max(largest, a.coeff(i, i));
    std::vector<Triplet> reg;
    for (int v = 0; v < nv; ++v) {
      if (gradient_dof[v] < 0) continue;
      reg.emplace_back(gradient_dof[v], gradient_dof[v], 1e-12 * largest);
      reg.emplace_back(gradient_dof[v] + 1, gradient_dof[v] + 1, 1e-12 * largest);
    }
    Eigen::SparseMatrix<double> r(n, n);
    r.setFromTriplets(reg.begin(), reg.end());
    a += r;
    solver.factorize(a);
    fit.regularized = true;
  }
  fit.solver = solver.backend();
  Eigen::MatrixXd x(n, k);
  for (int col = 0; col < k; ++col) {
    Eigen::VectorXd xc = solver.solve(b.col(col));
    for (int step = 0; step < options.refinement_steps; ++step) {
      xc += solver.solve(b.col(col) - a * xc);
    }
    const double bn = b.col(col).norm();
    const double res = (b.col(col) - a * xc).norm();
    fit.solve_residual = std::max(fit.solve_residual, bn > 0 ? res / bn : res);
    x.col(col) = xc;
  }

  // Back to vertex data.
  fit.data.values = data;
  fit.data.gradients = Eigen::MatrixXd::Zero(nv, 2 * k);
  for (int v = 0; v < nv; ++v) {
    if (value_dof[v] < 0) continue;
    fit.data.values.row(v) = x.row(value_dof[v]);
    fit.data_energy += (x.row(value_dof[v]) - data.row(v)).squaredNorm();
    if (gradient_dof[v] < 0) continue;
    for (int col = 0; col < k; ++col) {
      fit.data.gradients(v, 2 * col) = x(gradient_dof[v], col);
      fit.data.gradients(v, 2 * col + 1) = x(gradient_dof[v] + 1, col);
    }
  }
  for (int col = 0; col < k; ++col) {
    fit.smoothness_energy += x.col(col).dot(smoothness * x.col(col));
  }
  fit.ordinates = face_ordinates(d, fit.data);
  fit.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return fit;
}

}  // namespace ricci
