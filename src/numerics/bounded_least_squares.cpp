#include "ricci/numerics/bounded_least_squares.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

namespace ricci {
namespace {

/// The ridge added to M's diagonal, relative to its largest diagonal entry: keeps M restricted
/// to the free variables positive definite when M is only semi-definite, far below any entry
/// that matters.
constexpr double kRelativeRidge = 1e-12;
/// Floor of the scale the ridge is relative to (M = 0 still gets a positive ridge).
constexpr double kSmallestScale = 1e-300;
/// With every variable at a bound, their sum meets `total` within this, relative to 1 + |total|
/// (rounding of a sum of a few dozen curvatures of order pi).
constexpr double kSumSlack = 1e-9;
/// A free variable beyond its bound by more than this (absolute) is a violation: the bounds
/// are curvatures of order 1, and the KKT solve's rounding stays below it.
constexpr double kViolation = 1e-12;
/// A bound's multiplier of the wrong sign beyond this, relative to 1 + the largest gradient
/// entry, releases the bound (smaller ones are rounding at the optimum).
constexpr double kWrongSign = 1e-12;

/// Which variables are free and which sit at a bound, and the programme they belong to.
struct ActiveSet {
  const Eigen::MatrixXd& M;
  const Eigen::VectorXd& r;
  const Eigen::VectorXd& lo;
  const Eigen::VectorXd& hi;
  bool sum_constraint = false;
  double total = 0;
  int m = 0;
  double ridge = 0;
  std::vector<int> state;  ///< 0 free, -1 at lo, +1 at hi
};

/// The minimiser with the active variables at their bounds and the free ones solving the KKT
/// system (lambda: the sum constraint's multiplier). Returns whether it is finite and, when no
/// variable is free, whether the fixed ones meet the sum.
bool solve_free(const ActiveSet& set, Eigen::VectorXd& x, double& lambda) {
  const int m = set.m;
  const std::vector<int>& state = set.state;
  std::vector<int> free;
  for (int i = 0; i < m; ++i) {
    if (state[i] == 0) free.push_back(i);
  }
  x.resize(m);
  for (int i = 0; i < m; ++i) {
    if (state[i] < 0) x[i] = set.lo[i];
    if (state[i] > 0) x[i] = set.hi[i];
  }
  const int nf = static_cast<int>(free.size());
  const int rows = nf + (set.sum_constraint ? 1 : 0);
  lambda = 0;
  if (nf == 0) {
    return !set.sum_constraint ||
           std::abs(x.sum() - set.total) <= kSumSlack * (1 + std::abs(set.total));
  }
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(rows, rows);
  Eigen::VectorXd b(rows);
  for (int a = 0; a < nf; ++a) {
    double fixed_part = 0;
    for (int j = 0; j < m; ++j) {
      if (state[j] != 0) fixed_part += set.M(free[a], j) * x[j];
    }
    b[a] = -set.r[free[a]] - fixed_part;
    for (int c = 0; c < nf; ++c) K(a, c) = set.M(free[a], free[c]);
    K(a, a) += set.ridge;
  }
  if (set.sum_constraint) {
    double fixed_sum = 0;
    for (int j = 0; j < m; ++j) {
      if (state[j] != 0) fixed_sum += x[j];
    }
    for (int a = 0; a < nf; ++a) K(a, nf) = K(nf, a) = 1.0;
    b[nf] = set.total - fixed_sum;
  }
  // M restricted to the free variables is positive definite (M is, plus the ridge): one
  // Cholesky factorisation, and the sum constraint by its Schur complement. (A full-pivoting
  // LU of the whole KKT system took 95 % of a genus-150 selection of 912 cones: 149 s.)
  const Eigen::LLT<Eigen::MatrixXd> llt(K.topLeftCorner(nf, nf));
  Eigen::VectorXd y(rows);
  if (llt.info() == Eigen::Success) {
    const Eigen::VectorXd yb = llt.solve(b.head(nf));
    if (set.sum_constraint) {
      const Eigen::VectorXd y1 = llt.solve(Eigen::VectorXd::Ones(nf));
      const double mu = (yb.sum() - b[nf]) / y1.sum();
      y.head(nf) = yb - mu * y1;
      y[nf] = mu;
    } else {
      y = yb;
    }
  } else {
    y = K.fullPivLu().solve(b);
  }
  for (int a = 0; a < nf; ++a) x[free[a]] = y[a];
  if (set.sum_constraint) lambda = y[nf];
  return y.allFinite();
}

/// The active-set iterations from `start` (all variables free when it is empty); `batched`:
/// violated bounds among the free variables become active all at once. The optimum is unique
/// (M is positive definite), so neither the start nor the path changes it, but a batch can leave
/// the sum constraint a single free variable it cannot meet; then the caller runs the
/// one-at-a-time path. Returns whether it reached the optimum (then in k and multiplier, and its
/// active set in set.state).
bool run_active_set(ActiveSet& set, bool batched, const std::vector<int>& start, Eigen::VectorXd& k,
                    double& multiplier) {
  const int m = set.m;
  std::vector<int>& state = set.state;
  if (start.empty()) {
    std::fill(state.begin(), state.end(), 0);
  } else {
    state = start;
  }
  Eigen::VectorXd x;
  double lambda = 0;
  for (int iteration = 0; iteration < 4 * m + 8; ++iteration) {
    if (!solve_free(set, x, lambda)) break;
    int worst = -1;
    double worst_violation = kViolation;
    std::vector<int> violated;
    for (int i = 0; i < m; ++i) {
      if (state[i] != 0) continue;
      const double v = std::max(set.lo[i] - x[i], x[i] - set.hi[i]);
      if (v > kViolation) violated.push_back(i);
      if (v > worst_violation) {
        worst_violation = v;
        worst = i;
      }
    }
    if (worst >= 0) {
      int free_count = 0;
      for (int st : state) free_count += st == 0;
      if (set.sum_constraint && free_count == 1) break;  // the sum needs one free variable
      if (!batched || (set.sum_constraint && static_cast<int>(violated.size()) >= free_count)) {
        violated = {worst};  // the worst violated bound becomes active
      }
      for (int i : violated) state[i] = x[i] < set.lo[i] ? -1 : 1;
      continue;
    }
    // Feasible: release the active bound whose multiplier has the wrong sign, if any. The
    // gradient of the Lagrangian at a bound at lo must be >= 0 (at hi <= 0).
    const Eigen::VectorXd gradient = set.M * x + set.r + Eigen::VectorXd::Constant(m, lambda);
    int release = -1;
    double most = kWrongSign * (1 + gradient.cwiseAbs().maxCoeff());
    for (int i = 0; i < m; ++i) {
      const double wrong = state[i] < 0 ? -gradient[i] : state[i] > 0 ? gradient[i] : 0.0;
      if (wrong > most) {
        most = wrong;
        release = i;
      }
    }
    if (release < 0) {
      k = x;
      multiplier = lambda;
      return true;
    }
    state[release] = 0;
  }
  return false;
}

}  // namespace

BoundedLeastSquaresResult bounded_least_squares(const Eigen::MatrixXd& M, const Eigen::VectorXd& r,
                                                const Eigen::VectorXd& lo,
                                                const Eigen::VectorXd& hi,
                                                const BoundedLeastSquaresOptions& options) {
  const int m = static_cast<int>(r.size());
  if (m == 0) {  // nothing to solve: feasible when no sum is asked of nothing
    BoundedLeastSquaresResult none;
    none.x.resize(0);
    none.feasible = !options.sum_constraint ||
                    std::abs(options.total) <= kSumSlack * (1 + std::abs(options.total));
    return none;
  }
  ActiveSet set{M,
                r,
                lo,
                hi,
                options.sum_constraint,
                options.total,
                m,
                kRelativeRidge * std::max(kSmallestScale, M.diagonal().cwiseAbs().maxCoeff()),
                std::vector<int>(m, 0)};
  BoundedLeastSquaresResult result;
  const bool sum_unreachable =
      options.sum_constraint && (lo.sum() > options.total || hi.sum() < options.total);
  if (!sum_unreachable) {
    // A neighbouring programme's active set first: the quasi-Newton steps of the cone selection
    // keep most of theirs from one step to the next (eight with 32 cones: 5.4 iterations a
    // programme from all free).
    const std::vector<int>& start = options.start_state;
    const bool warm =
        static_cast<int>(start.size()) == m &&
        std::all_of(start.begin(), start.end(), [](int s) { return s >= -1 && s <= 1; });
    const std::vector<int> cold;
    const auto reached = [&](bool batched, const std::vector<int>& from) {
      result.feasible = run_active_set(set, batched, from, result.x, result.multiplier);
      if (result.feasible) result.state = set.state;
      return result.feasible;
    };
    if ((warm && reached(false, start)) || (m > options.batched_above && reached(true, cold)) ||
        reached(false, cold)) {
      return result;
    }
  }
  // Infeasible: the minimiser under the sum constraint alone.
  std::fill(set.state.begin(), set.state.end(), 0);
  solve_free(set, result.x, result.multiplier);
  return result;
}

}  // namespace ricci
