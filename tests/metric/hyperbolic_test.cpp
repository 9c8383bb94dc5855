#include "ricci/metric/hyperbolic.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace ricci {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(HyperbolicCosineLaw, EquilateralTriangleHasTheClosedFormAngle) {
  // Side a: cos A = (cosh^2 a - cosh a) / sinh^2 a = cosh a / (1 + cosh a); area pi - 3A.
  for (double a : {1e-6, 1e-3, 0.1, 1.0, 3.0, 10.0}) {
    const double angle = hyperbolic_angle_from_lengths(a, a, a);
    const double expected = std::acos(std::cosh(a) / (1.0 + std::cosh(a)));
    EXPECT_NEAR(angle, expected, 1e-12 * expected) << "a = " << a;
    EXPECT_LT(angle, kPi / 3);  // angle sum below pi: negative curvature
  }
  // Small triangles are nearly Euclidean (60 degrees), huge ones nearly ideal (angle -> 0).
  EXPECT_NEAR(hyperbolic_angle_from_lengths(1e-6, 1e-6, 1e-6), kPi / 3, 1e-12);
  EXPECT_LT(hyperbolic_angle_from_lengths(30, 30, 30), 1e-6);
}

TEST(HyperbolicCosineLaw, AgreesWithTheCosineFormWhereThatIsAccurate) {
  std::mt19937 random(4);
  std::uniform_real_distribution<double> side(0.2, 3.0);
  for (int trial = 0; trial < 1000; ++trial) {
    const double a = side(random), b = side(random), c = side(random);
    const double angle = hyperbolic_angle_from_lengths(a, b, c);
    if (a >= b + c || b >= a + c || c >= a + b) {
      EXPECT_TRUE(std::isnan(angle));
      continue;
    }
    const double cosine =
        (std::cosh(b) * std::cosh(c) - std::cosh(a)) / (std::sinh(b) * std::sinh(c));
    if (std::abs(cosine) < 0.99) {
      EXPECT_NEAR(angle, std::acos(cosine), 1e-12);
    }
  }
  EXPECT_TRUE(std::isnan(hyperbolic_angle_from_lengths(3, 1, 1)));
  EXPECT_TRUE(std::isnan(hyperbolic_angle_from_lengths(0, 1, 1)));
}

TEST(HyperbolicUnifiedForm, TangentCirclesAddTheirRadiiAndLogRadiiRoundTrip) {
  for (double r : {1e-3, 0.5, 2.0, 7.0}) {
    EXPECT_NEAR(hyperbolic_radius(hyperbolic_log_radius(r)), r, 1e-12 * std::max(1.0, r));
    EXPECT_LT(hyperbolic_log_radius(r), 0.0);
    // eta = 1: cosh(r_i + r_j) = cosh r_i cosh r_j + sinh r_i sinh r_j.
    EXPECT_NEAR(hyperbolic_edge_length(r, 0.3, 1.0), r + 0.3, 1e-12 * (r + 0.3));
    // eta = -1: |r_i - r_j|.
    EXPECT_NEAR(hyperbolic_edge_length(r, 0.3, -1.0), std::abs(r - 0.3), 1e-7);
  }
  EXPECT_TRUE(std::isnan(hyperbolic_radius(0.0)));
  EXPECT_TRUE(std::isnan(hyperbolic_edge_length(1.0, 1.0, -2.0)));
}

}  // namespace
}  // namespace ricci
