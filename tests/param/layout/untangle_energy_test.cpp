// The untangling energy of one face (param/layout/detail/untangle_energy.hpp): the barrier's
// value and derivatives against its closed form and finite differences, the face energy's
// gradient against finite differences, and its projected Hessian positive semi-definite and
// equal to the true Hessian where that is already definite.

#include "param/layout/detail/untangle_energy.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace ricci::untangle_energy {
namespace {

/// Central differences of smooth functions of order-1 arguments at step 1e-5: their error is
/// about 1e-10 (truncation) plus 1e-11 (rounding).
constexpr double kStep = 1e-5;
constexpr double kDifferenceTolerance = 1e-7;

TEST(UntangleEnergy, ChiMatchesItsClosedFormAndDerivatives) {
  for (const double eps : {1e-3, 0.1, 1.0}) {
    for (const double d : {-2.0, -0.3, -1e-4, 0.0, 1e-4, 0.5, 3.0}) {
      const Chi c = chi(d, eps);
      // The cancellation-free form agrees with the textbook one where the latter is accurate.
      EXPECT_NEAR(c.value, 0.5 * (d + std::sqrt(eps * eps + d * d)), 1e-12 * (1 + std::abs(d)))
          << d << " " << eps;
      EXPECT_GT(c.value, 0);
      const double r = std::sqrt(eps * eps + d * d);
      EXPECT_NEAR(c.first, c.value / r, 1e-15 * (1 + c.first));
      // chi bends on the scale of eps: the difference step follows it (at eps = 1e-3 a step of
      // 1e-5 leaves a truncation error of 2e-6 near D = 0).
      const double h = std::min(kStep, 1e-3 * eps);
      const double first = (chi(d + h, eps).value - chi(d - h, eps).value) / (2 * h);
      const double second = (chi(d + h, eps).first - chi(d - h, eps).first) / (2 * h);
      EXPECT_NEAR(c.first, first, kDifferenceTolerance * (1 + std::abs(first)));
      EXPECT_NEAR(c.second, second, 1e-4 * (1 + std::abs(second)));  // chi'' is steep at small eps
    }
  }
  // A flipped face far past zero keeps a tiny positive barrier, no cancellation to zero.
  EXPECT_GT(chi(-1e8, 1e-3).value, 0);
}

TEST(UntangleEnergy, GradientMatchesFiniteDifferences) {
  const Vec4 points[] = {Vec4(1.0, 0.2, -0.1, 0.9), Vec4(0.3, 1.5, -0.7, 0.2),
                         Vec4(-0.5, 0.1, 0.2, 0.4)};  // the last one flipped (det < 0)
  for (const Vec4& j : points) {
    for (const double theta : {0.0, 1.0 / 128, 0.5}) {
      const double eps = 0.2;
      Vec4 gradient;
      Mat4 hessian;
      const double energy = face_energy(j, eps, theta, &gradient, &hessian);
      EXPECT_DOUBLE_EQ(energy, face_energy(j, eps, theta, nullptr, nullptr));
      for (int i = 0; i < 4; ++i) {
        Vec4 plus = j, minus = j;
        plus[i] += kStep;
        minus[i] -= kStep;
        const double difference = (face_energy(plus, eps, theta, nullptr, nullptr) -
                                   face_energy(minus, eps, theta, nullptr, nullptr)) /
                                  (2 * kStep);
        EXPECT_NEAR(gradient[i], difference, kDifferenceTolerance * (1 + std::abs(difference)))
            << "component " << i << " theta " << theta;
      }
      // The projection is symmetric and positive semi-definite.
      EXPECT_LT((hessian - hessian.transpose()).norm(), 1e-12 * (1 + hessian.norm()));
      Eigen::SelfAdjointEigenSolver<Mat4> eig(hessian);
      EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12 * (1 + hessian.norm()));
    }
  }
}

TEST(UntangleEnergy, ProjectedHessianIsTheHessianWhereDefinite) {
  // Near the identity (a face drawn in its own shape) with an area weight theta = 1/2 the energy
  // is convex: the projection changes nothing, and the Hessian matches differences of the
  // gradient. (With the untangler's theta = 1/128 the energy is nearly scale invariant and not
  // convex there: the projection then rightly differs from the true Hessian.)
  const Vec4 j(1.05, 0.02, -0.03, 0.97);
  const double eps = 1e-3, theta = 0.5;
  Vec4 gradient;
  Mat4 hessian;
  face_energy(j, eps, theta, &gradient, &hessian);
  Mat4 differences;
  for (int i = 0; i < 4; ++i) {
    Vec4 plus = j, minus = j, gp, gm;
    plus[i] += kStep;
    minus[i] -= kStep;
    face_energy(plus, eps, theta, &gp, nullptr);
    face_energy(minus, eps, theta, &gm, nullptr);
    const Vec4 column = (gp - gm) / (2 * kStep);
    differences.col(i) = column;
    EXPECT_LT((hessian.col(i) - column).norm(), kDifferenceTolerance * (1 + column.norm()))
        << "column " << i;
  }
  // The premise: the true Hessian is positive definite there.
  Eigen::SelfAdjointEigenSolver<Mat4> eig(0.5 * (differences + differences.transpose()));
  EXPECT_GT(eig.eigenvalues().minCoeff(), 0);
}

}  // namespace
}  // namespace ricci::untangle_energy
