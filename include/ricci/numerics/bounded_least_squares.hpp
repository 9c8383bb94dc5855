#pragma once
/// \file
/// A small dense quadratic programme with box bounds and an optional sum constraint, solved by
/// an active-set method: the cone selection's curvature fits and quasi-Newton steps.

#include <vector>

#include <Eigen/Core>

namespace ricci {

struct BoundedLeastSquaresOptions {
  /// Also require sum x = total (the equality's multiplier is returned).
  bool sum_constraint = false;
  double total = 0;  ///< the sum x must reach with sum_constraint
  /// Programmes of more variables than this first try activating every violated bound among
  /// the free variables at once (one at a time, a genus-150 surface whose 900 cones sit at
  /// their lower bounds took 900 factorisations per programme: 149 s for its selection); when
  /// that fails, the one-at-a-time path runs.
  int batched_above = 64;
  /// Where the active-set iterations start: per variable -1 (at lo), +1 (at hi) or 0 (free), as
  /// BoundedLeastSquaresResult::state of a neighbouring programme returns it; all free when
  /// empty (or not of size m). The optimum does not depend on it, the work does.
  std::vector<int> start_state;
};

struct BoundedLeastSquaresResult {
  /// Whether the bounds (and the sum) could all be met; when they cannot, x is the
  /// minimiser under the sum constraint alone (no bounds).
  bool feasible = false;
  Eigen::VectorXd x;      ///< the minimiser (#variables)
  double multiplier = 0;  ///< the sum constraint's Lagrange multiplier (0 without it)
  /// When feasible: the bounds active at the minimiser (-1 at lo, +1 at hi, 0 free), for
  /// BoundedLeastSquaresOptions::start_state of the next programme.
  std::vector<int> state;
};

/// min 1/2 x^T M x + r^T x subject to lo <= x <= hi and, with options.sum_constraint,
/// sum x = options.total. The active-set iterations solve the KKT system of the free variables
/// (one Cholesky factorisation of M restricted to them, plus a tiny ridge; the sum constraint
/// by its Schur complement), fix violated bounds and release a bound when its multiplier has
/// the wrong sign.
/// \pre M symmetric positive semi-definite (m by m), r, lo, hi of size m, lo <= hi
BoundedLeastSquaresResult bounded_least_squares(const Eigen::MatrixXd& M, const Eigen::VectorXd& r,
                                                const Eigen::VectorXd& lo,
                                                const Eigen::VectorXd& hi,
                                                const BoundedLeastSquaresOptions& options = {});

}  // namespace ricci
