#pragma once
/// \file
/// Least-squares fitting of a Powell-Sabin spline to per-vertex data (docs/splines.md): values
/// near the data, plus a small smoothness term that penalises Hessian jumps between adjacent
/// quadratic pieces. The smoothness term vanishes exactly on global quadratics, so linear and
/// quadratic data are reproduced whatever the weight.

#include <string>

#include <Eigen/Core>

#include "ricci/spline/powell_sabin.hpp"

namespace ricci {

/// Options of fit_spline.
struct SplineFitOptions {
  /// Dimensionless weight of the smoothness term: the energy is
  /// sum_v |a_v - p_v|^2 + smoothness * h^3 * S, h the mean edge length in the charts,
  /// S = sum over adjacent pieces of |H_a - H_b|_F^2 times their shared sub-edge's length.
  /// h^3 S is a squared length of the data's units (the deviation from the local quadratic),
  /// so the trade-off does not depend on the mesh's scale or the metric's units. Must be > 0.
  double smoothness = 1e-4;
  int refinement_steps = 2;  ///< iterative refinement of the solve with the same factor
};

/// What fit_spline returns.
struct SplineFit {
  SplineVertexData data;         ///< fitted values (#V by k) and vertex-frame gradients (#V by 2k)
  Eigen::MatrixXd ordinates;     ///< 19 #F by k (face_ordinates of data)
  double weight = 0;             ///< W = smoothness * h^3 actually used
  double data_energy = 0;        ///< sum_v |a_v - p_v|^2 (all columns)
  double smoothness_energy = 0;  ///< S (all columns)
  double solve_residual = 0;     ///< max over columns of |A x - b| / |b| after refinement
  int num_unknowns = 0;
  /// The system was singular (a factorisation failed) and was solved again with a diagonal of
  /// 1e-12 times the largest diagonal entry added on the gradient unknowns.
  bool regularized = false;
  const char* solver = "";
  double seconds = 0;
};

/// Fits a spline to per-vertex data: one sparse SPD system (3 unknowns per vertex, 1 at vertices
/// with a fixed gradient), k right-hand sides, solved by SparseCholesky.
/// \param data #V by k values at the vertices (rows of unreferenced vertices are ignored)
/// \throw InvalidInput when data has not #V rows, has non-finite entries or smoothness <= 0
/// \throw SolverError when even the regularised system cannot be factorised
SplineFit fit_spline(const SplineDomain& domain, const Eigen::MatrixXd& data,
                     const SplineFitOptions& options = {});

}  // namespace ricci
