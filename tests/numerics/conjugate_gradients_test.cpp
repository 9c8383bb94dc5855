#include "numerics/detail/conjugate_gradients.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>

namespace ricci::numerics_detail {
namespace {

/// A 1D Laplacian plus a diagonal shift: symmetric positive definite, ill-conditioned enough that
/// plain CG needs many iterations.
Eigen::MatrixXd laplacian(int n, double shift) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    A(i, i) = 2 + shift;
    if (i > 0) A(i, i - 1) = A(i - 1, i) = -1;
  }
  return A;
}

TEST(ConjugateGradients, ANearbyFactorisationPreconditionsToConvergenceInAFewIterations) {
  const int n = 200;
  const Eigen::MatrixXd A = laplacian(n, 1e-3);
  // The preconditioner: the exact inverse of a nearby matrix (another shift), as the flow's
  // earlier factorisation is of the Hessian at an earlier point.
  const Eigen::LLT<Eigen::MatrixXd> nearby(laplacian(n, 1.2e-3));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1, 2);
  Eigen::VectorXd x;
  const ConjugateGradients cg = conjugate_gradients(
      [&](const Eigen::VectorXd& p) -> Eigen::VectorXd { return A * p; },
      [&](const Eigen::VectorXd& r) -> Eigen::VectorXd { return nearby.solve(r); }, b, 1e-12, 50,
      x);
  EXPECT_TRUE(cg.converged);
  EXPECT_LE(cg.iterations, 10);
  EXPECT_LE((A * x - b).norm(), 1e-11 * b.norm());
  const Eigen::VectorXd exact = A.llt().solve(b);
  EXPECT_LE((x - exact).norm(), 1e-8 * exact.norm());
}

TEST(ConjugateGradients, SaysWhenTheIterationsRunOutOrCurvatureIsNotPositive) {
  const int n = 200;
  const Eigen::MatrixXd A = laplacian(n, 1e-3);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
  const auto identity = [](const Eigen::VectorXd& r) -> Eigen::VectorXd { return r; };
  Eigen::VectorXd x;
  // Unpreconditioned, 5 iterations are far from enough.
  ConjugateGradients cg = conjugate_gradients(
      [&](const Eigen::VectorXd& p) -> Eigen::VectorXd { return A * p; }, identity, b, 1e-12, 5, x);
  EXPECT_FALSE(cg.converged);
  EXPECT_EQ(cg.iterations, 5);
  // A negative definite matrix: the first direction has negative curvature.
  const Eigen::MatrixXd N = -A;
  cg = conjugate_gradients([&](const Eigen::VectorXd& p) -> Eigen::VectorXd { return N * p; },
                           identity, b, 1e-12, 50, x);
  EXPECT_FALSE(cg.converged);
  EXPECT_EQ(cg.iterations, 0);
  // A zero right-hand side is solved by x = 0 at once.
  cg = conjugate_gradients([&](const Eigen::VectorXd& p) -> Eigen::VectorXd { return A * p; },
                           identity, Eigen::VectorXd::Zero(n), 1e-12, 50, x);
  EXPECT_EQ(x.size(), n);
  EXPECT_EQ(x.norm(), 0);
}

}  // namespace
}  // namespace ricci::numerics_detail
