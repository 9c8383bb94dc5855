#include "ricci/numerics/bounded_least_squares.hpp"

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

namespace ricci {
namespace {

/// The KKT solves are exact up to the relative ridge (1e-12) and rounding of order 1e-15 on
/// entries of order 1.
constexpr double kTolerance = 1e-9;

Eigen::MatrixXd spd3() {
  Eigen::MatrixXd M(3, 3);
  M << 4, 1, 0, 1, 3, 1, 0, 1, 2;
  return M;
}

/// min 1/2 |x|^2 over three variables in the box [lo, hi] with sum x = total.
BoundedLeastSquaresResult least_norm_with_sum(double total, const Eigen::VectorXd& lo,
                                              const Eigen::VectorXd& hi) {
  BoundedLeastSquaresOptions options;
  options.sum_constraint = true;
  options.total = total;
  return bounded_least_squares(Eigen::MatrixXd::Identity(3, 3), Eigen::VectorXd::Zero(3), lo, hi,
                               options);
}

TEST(BoundedLeastSquares, UnconstrainedOptimumInsideTheBox) {
  const Eigen::MatrixXd M = spd3();
  const Eigen::VectorXd r = Eigen::VectorXd{{1, -2, 0.5}};
  const Eigen::VectorXd expected = M.ldlt().solve(-r);
  const BoundedLeastSquaresResult result = bounded_least_squares(
      M, r, Eigen::VectorXd::Constant(3, -10), Eigen::VectorXd::Constant(3, 10));
  ASSERT_TRUE(result.feasible);
  EXPECT_LT((result.x - expected).cwiseAbs().maxCoeff(), kTolerance);
  EXPECT_EQ(result.multiplier, 0.0);
}

TEST(BoundedLeastSquares, ActiveBoundsOfADiagonalProgramme) {
  // Separable: each x_i = clamp(-r_i / M_ii).
  const Eigen::MatrixXd M = Eigen::Vector3d(1, 2, 4).asDiagonal();
  const Eigen::VectorXd r = Eigen::VectorXd{{-3, 4, -2}};  // unbounded optimum (3, -2, 0.5)
  const Eigen::VectorXd lo = Eigen::VectorXd{{-1, -1, -1}}, hi = Eigen::VectorXd{{1, 1, 1}};
  const BoundedLeastSquaresResult result = bounded_least_squares(M, r, lo, hi);
  ASSERT_TRUE(result.feasible);
  EXPECT_NEAR(result.x[0], 1, kTolerance);
  EXPECT_NEAR(result.x[1], -1, kTolerance);
  EXPECT_NEAR(result.x[2], 0.5, kTolerance);
}

TEST(BoundedLeastSquares, SumConstraintAndItsMultiplier) {
  // min 1/2 |x|^2 with sum x = 3: x = (1, 1, 1), the gradient x + lambda = 0: lambda = -1.
  const BoundedLeastSquaresResult result =
      least_norm_with_sum(3, Eigen::VectorXd::Constant(3, -5), Eigen::VectorXd::Constant(3, 5));
  ASSERT_TRUE(result.feasible);
  EXPECT_LT((result.x - Eigen::VectorXd::Ones(3)).cwiseAbs().maxCoeff(), kTolerance);
  EXPECT_NEAR(result.multiplier, -1, kTolerance);
}

TEST(BoundedLeastSquares, SumConstraintWithAnActiveBound) {
  // min 1/2 |x|^2 with sum x = 3 and x_0 <= 0.5: x_0 at its bound, the rest share 2.5.
  const BoundedLeastSquaresResult result =
      least_norm_with_sum(3, Eigen::VectorXd::Constant(3, -5), Eigen::VectorXd{{0.5, 5, 5}});
  ASSERT_TRUE(result.feasible);
  EXPECT_NEAR(result.x[0], 0.5, kTolerance);
  EXPECT_NEAR(result.x[1], 1.25, kTolerance);
  EXPECT_NEAR(result.x[2], 1.25, kTolerance);
  EXPECT_NEAR(result.x.sum(), 3, kTolerance);
}

TEST(BoundedLeastSquares, UnreachableSumReturnsTheUnboundedMinimiser) {
  // The bounds sum to at most 3 < 6: infeasible; x is the minimiser under the sum alone.
  const BoundedLeastSquaresResult result =
      least_norm_with_sum(6, Eigen::VectorXd::Constant(3, -1), Eigen::VectorXd::Constant(3, 1));
  EXPECT_FALSE(result.feasible);
  EXPECT_LT((result.x - Eigen::VectorXd::Constant(3, 2)).cwiseAbs().maxCoeff(), kTolerance);
}

TEST(BoundedLeastSquares, DegenerateCases) {
  // No variables.
  const BoundedLeastSquaresResult none = bounded_least_squares(
      Eigen::MatrixXd(0, 0), Eigen::VectorXd(0), Eigen::VectorXd(0), Eigen::VectorXd(0));
  EXPECT_TRUE(none.feasible);
  EXPECT_EQ(none.x.size(), 0);
  // M only semi-definite (rank 1): the linear term drives the variables along its null space
  // to their bounds. (M = 0 is beyond it: the ridge is then 1e-312 and the solve overflows.)
  Eigen::MatrixXd rank_one(2, 2);
  rank_one << 1, 1, 1, 1;
  const BoundedLeastSquaresResult flat = bounded_least_squares(
      rank_one, Eigen::VectorXd{{1, -1}}, Eigen::VectorXd{{-2, -2}}, Eigen::VectorXd{{3, 3}});
  ASSERT_TRUE(flat.feasible);
  EXPECT_NEAR(flat.x[0], -2.0, kTolerance);
  EXPECT_NEAR(flat.x[1], 3.0, kTolerance);
  // lo = hi pins the variable; the sum constraint then sets the other.
  BoundedLeastSquaresOptions options;
  options.sum_constraint = true;
  options.total = 1;
  const BoundedLeastSquaresResult pinned =
      bounded_least_squares(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2),
                            Eigen::VectorXd{{0.25, -5}}, Eigen::VectorXd{{0.25, 5}}, options);
  ASSERT_TRUE(pinned.feasible);
  EXPECT_NEAR(pinned.x[0], 0.25, kTolerance);
  EXPECT_NEAR(pinned.x[1], 0.75, kTolerance);
}

TEST(BoundedLeastSquares, BatchedPathReachesTheSameOptimum) {
  // 80 variables (above batched_above) pushed below their lower bounds by the linear term,
  // a few left free: the batched and the one-at-a-time paths agree.
  const int m = 80;
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(m, m) * 2;
  for (int i = 0; i + 1 < m; ++i) M(i, i + 1) = M(i + 1, i) = 0.5;
  Eigen::VectorXd r(m);
  for (int i = 0; i < m; ++i) r[i] = i % 10 == 0 ? -1.0 : 3.0 + 0.01 * i;
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(m, -1), hi = Eigen::VectorXd::Constant(m, 1);
  BoundedLeastSquaresOptions batched, single;
  batched.sum_constraint = single.sum_constraint = true;
  batched.total = single.total = -60;
  single.batched_above = m;
  const BoundedLeastSquaresResult a = bounded_least_squares(M, r, lo, hi, batched);
  const BoundedLeastSquaresResult b = bounded_least_squares(M, r, lo, hi, single);
  ASSERT_TRUE(a.feasible);
  ASSERT_TRUE(b.feasible);
  EXPECT_LT((a.x - b.x).cwiseAbs().maxCoeff(), kTolerance);
  EXPECT_NEAR(a.x.sum(), -60, kTolerance);
  EXPECT_GE(a.x.minCoeff(), -1 - kTolerance);
  EXPECT_LE(a.x.maxCoeff(), 1 + kTolerance);
}

// The active set the minimiser ends with is returned, and any start (the right set, a wrong
// one, a malformed one) reaches the same minimiser: the same bits as from all free whenever it
// ends on the same active set.
TEST(BoundedLeastSquares, StartStateChangesTheWorkNotTheMinimiser) {
  const int m = 12;
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(m, m) * 3;
  for (int i = 0; i + 1 < m; ++i) M(i, i + 1) = M(i + 1, i) = 0.7;
  Eigen::VectorXd r(m);
  for (int i = 0; i < m; ++i) r[i] = i % 3 == 0 ? -4.0 : (i % 3 == 1 ? 5.0 : 0.1 * i);
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(m, -1), hi = Eigen::VectorXd::Constant(m, 1);
  BoundedLeastSquaresOptions options;
  options.sum_constraint = true;
  options.total = 0.5;
  const BoundedLeastSquaresResult cold = bounded_least_squares(M, r, lo, hi, options);
  ASSERT_TRUE(cold.feasible);
  ASSERT_EQ(static_cast<int>(cold.state.size()), m);
  for (int i = 0; i < m; ++i) {
    if (cold.state[i] < 0) {
      EXPECT_EQ(cold.x[i], lo[i]) << i;
    } else if (cold.state[i] > 0) {
      EXPECT_EQ(cold.x[i], hi[i]) << i;
    }
  }
  EXPECT_GT(std::count(cold.state.begin(), cold.state.end(), 1), 0);
  EXPECT_GT(std::count(cold.state.begin(), cold.state.end(), -1), 0);
  for (const std::vector<int>& start : {cold.state, std::vector<int>(m, -1), std::vector<int>(m, 1),
                                        std::vector<int>(3, 1), std::vector<int>(m, 7)}) {
    options.start_state = start;
    const BoundedLeastSquaresResult warm = bounded_least_squares(M, r, lo, hi, options);
    ASSERT_TRUE(warm.feasible);
    EXPECT_EQ(warm.state, cold.state);
    EXPECT_TRUE((warm.x.array() == cold.x.array()).all());
    EXPECT_EQ(warm.multiplier, cold.multiplier);
  }
}

}  // namespace
}  // namespace ricci
