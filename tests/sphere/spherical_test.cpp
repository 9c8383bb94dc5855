#include "ricci/sphere/spherical.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace ricci {
namespace {

TEST(SphericalCosineLaw, EquilateralTriangleHasTheClosedFormAngle) {
  // Side a: cos A = (cos a - cos^2 a) / sin^2 a = cos a / (1 + cos a); area 3A - pi > 0.
  for (double a : {1e-6, 1e-3, 0.1, 1.0, 2.0, 2.09}) {
    const double angle = spherical_angle_from_lengths(a, a, a);
    const double expected = std::acos(std::cos(a) / (1.0 + std::cos(a)));
    EXPECT_NEAR(angle, expected, 1e-12 * expected) << "a = " << a;
    EXPECT_GT(angle, std::numbers::pi / 3 - 1e-12);  // angle sum above pi: positive curvature
  }
  // The octant: three right angles, area pi / 2.
  EXPECT_NEAR(spherical_angle_from_lengths(std::numbers::pi / 2, std::numbers::pi / 2,
                                           std::numbers::pi / 2),
              std::numbers::pi / 2, 1e-15);
  // Small triangles are nearly Euclidean.
  EXPECT_NEAR(spherical_angle_from_lengths(1e-6, 1e-6, 1e-6), std::numbers::pi / 3, 1e-12);
}

TEST(SphericalCosineLaw, AgreesWithTheCosineFormAndRefusesImpossibleTriangles) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> side(0.2, 2.0);
  int checked = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const double a = side(random), b = side(random), c = side(random);
    const double angle = spherical_angle_from_lengths(a, b, c);
    if (std::abs(b - c) >= a || a >= b + c || a + b + c >= 2 * std::numbers::pi) {
      EXPECT_TRUE(std::isnan(angle));
      continue;
    }
    const double cosine = (std::cos(a) - std::cos(b) * std::cos(c)) / (std::sin(b) * std::sin(c));
    if (std::abs(cosine) > 0.99) continue;  // acos loses digits there
    EXPECT_NEAR(angle, std::acos(cosine), 1e-10);
    ++checked;
  }
  EXPECT_GT(checked, 300);
  EXPECT_TRUE(std::isnan(spherical_angle_from_lengths(0, 1, 1)));
  EXPECT_TRUE(std::isnan(spherical_angle_from_lengths(3, 1, 1)));
  EXPECT_TRUE(std::isnan(spherical_angle_from_lengths(2.2, 2.2, 2.2)));  // perimeter above 2 pi
}

}  // namespace
}  // namespace ricci
