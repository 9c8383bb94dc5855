#include "ricci/numerics/predicates.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace ricci {
namespace {

using Triangle = std::array<Eigen::Vector2d, 3>;

TEST(OrientationSign, ExactWhereTheNaiveDeterminantRoundsWrongly) {
  // Points a few ulps off the diagonal through (12, 12) and (24, 24): the determinant is exactly
  // 12 (p_y - p_x), whose sign the plain double evaluation gets wrong or zero for many of them.
  const Eigen::Vector2d b(12, 12), c(24, 24);
  int naive_wrong = 0;
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 64; ++j) {
      const Eigen::Vector2d p(0.5 + i * std::ldexp(1.0, -53), 0.5 + j * std::ldexp(1.0, -53));
      const int expected = (p.y() > p.x()) - (p.y() < p.x());
      EXPECT_EQ(orientation_sign(p, b, c), expected) << i << " " << j;
      const double naive = (b.x() - p.x()) * (c.y() - p.y()) - (b.y() - p.y()) * (c.x() - p.x());
      naive_wrong += ((naive > 0) - (naive < 0)) != expected;
    }
  }
  EXPECT_GT(naive_wrong, 0);  // the test exercises the exact path
}

// A repeated point (two triangles sharing a vertex: the common case the filter cannot decide)
// is collinear whatever the coordinates; distinct points an ulp apart still turn.
TEST(OrientationSign, RepeatedPointsAreCollinear) {
  const Eigen::Vector2d a(0.1, 1e-300), b(3e12, -7.25), c(-1.0 / 3, 5e-17);
  for (const auto& [p, q, r] : {std::array{a, a, b}, std::array{a, b, a}, std::array{b, a, a},
                                std::array{b, c, c}, std::array{c, c, c}}) {
    EXPECT_EQ(orientation_sign(p, q, r), 0);
  }
  const double ulp = std::ldexp(1.0, -52);
  EXPECT_EQ(orientation_sign(Eigen::Vector2d(1, 1), Eigen::Vector2d(1 + ulp, 1),
                             Eigen::Vector2d(1, 1 + ulp)),
            1);
}

TEST(OrientationSign, KnownTurnsAndCollinearPoints) {
  const Eigen::Vector2d a(0, 0), b(1, 0);
  EXPECT_EQ(orientation_sign(a, b, Eigen::Vector2d(0, 1)), 1);
  EXPECT_EQ(orientation_sign(a, Eigen::Vector2d(0, 1), b), -1);
  // On the line (beyond, between, behind, repeated points): exactly zero.
  EXPECT_EQ(orientation_sign(a, b, Eigen::Vector2d(3, 0)), 0);
  EXPECT_EQ(orientation_sign(a, b, Eigen::Vector2d(0.5, 0)), 0);
  EXPECT_EQ(orientation_sign(a, b, Eigen::Vector2d(-7, 0)), 0);
  EXPECT_EQ(orientation_sign(a, a, b), 0);
  // The line y = x / 3 through r: (6, 2) is on it, one ulp of y above or below is not.
  const Eigen::Vector2d r(3.0 * 1024, 1024);
  EXPECT_EQ(orientation_sign(Eigen::Vector2d(0, 0), r, Eigen::Vector2d(6, 2)), 0);
  EXPECT_EQ(orientation_sign(Eigen::Vector2d(0, 0), r, Eigen::Vector2d(6, std::nextafter(2.0, 3))),
            1);
  EXPECT_EQ(orientation_sign(Eigen::Vector2d(0, 0), r, Eigen::Vector2d(6, std::nextafter(2.0, 1))),
            -1);
  // Swapping two points flips the sign; a cyclic shift keeps it, also for points that round off
  // the line (0.1 / 3 is not a third of 0.1 in binary).
  for (const Eigen::Vector2d& s :
       {Eigen::Vector2d(0.1, 0.1 / 3), Eigen::Vector2d(1e10, 1e10 / 3)}) {
    const int sign = orientation_sign(a, r, s);
    EXPECT_EQ(orientation_sign(r, s, a), sign);
    EXPECT_EQ(orientation_sign(r, a, s), -sign);
  }
}

TEST(OrientationSign, NearlyCollinearLargeCoordinates) {
  // A point on the segment between two points with large coordinates, and one ulp above and
  // below it.
  const Eigen::Vector2d a(1e8, 1e8), b(3e8, 3e8);
  const double x = 2e8;
  EXPECT_EQ(orientation_sign(a, b, Eigen::Vector2d(x, x)), 0);
  EXPECT_EQ(orientation_sign(a, b, Eigen::Vector2d(x, std::nextafter(x, 4e8))), 1);
  EXPECT_EQ(orientation_sign(a, b, Eigen::Vector2d(x, std::nextafter(x, 0))), -1);
}

TEST(TrianglesOverlap, TouchingIsNotOverlapping) {
  const Triangle a{Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)};
  // Sharing an edge, on the other side.
  EXPECT_FALSE(
      triangles_overlap(a, {Eigen::Vector2d(1, 0), Eigen::Vector2d(1, 1), Eigen::Vector2d(0, 1)}));
  // Sharing a vertex only; touching the hypotenuse at its midpoint; far apart.
  EXPECT_FALSE(
      triangles_overlap(a, {Eigen::Vector2d(1, 0), Eigen::Vector2d(2, 0), Eigen::Vector2d(2, 1)}));
  EXPECT_FALSE(triangles_overlap(
      a, {Eigen::Vector2d(0.5, 0.5), Eigen::Vector2d(2, 1), Eigen::Vector2d(1, 2)}));
  EXPECT_FALSE(
      triangles_overlap(a, {Eigen::Vector2d(5, 5), Eigen::Vector2d(6, 5), Eigen::Vector2d(5, 6)}));
  // Crossing; one inside the other (given clockwise); the same triangle.
  EXPECT_TRUE(triangles_overlap(
      a, {Eigen::Vector2d(0.2, -0.5), Eigen::Vector2d(0.8, -0.5), Eigen::Vector2d(0.5, 2)}));
  EXPECT_TRUE(triangles_overlap(
      a, {Eigen::Vector2d(0.1, 0.1), Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(0.2, 0.1)}));
  EXPECT_TRUE(triangles_overlap(a, a));
  // The same edge shared, both on the same side (a fold): overlapping.
  EXPECT_TRUE(triangles_overlap(
      a, {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(0.5, 0.2)}));
  // Zero area: no interior.
  EXPECT_FALSE(triangles_overlap(
      a, {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), Eigen::Vector2d(0.5, 0.5)}));
}

TEST(TrianglesOverlap, SymmetricAndAgreesWithTheCounterClockwiseForm) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> where(0, 3);
  int overlapping = 0, apart = 0;
  for (int i = 0; i < 2000; ++i) {
    Triangle a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = Eigen::Vector2d(where(rng), where(rng));
      b[k] = Eigen::Vector2d(where(rng), where(rng));
    }
    const bool overlap = triangles_overlap(a, b);
    EXPECT_EQ(triangles_overlap(b, a), overlap) << i;
    // The same triangles given the other way round.
    EXPECT_EQ(triangles_overlap({a[0], a[2], a[1]}, b), overlap) << i;
    for (Triangle* t : {&a, &b}) {
      if (orientation_sign((*t)[0], (*t)[1], (*t)[2]) < 0) std::swap((*t)[1], (*t)[2]);
    }
    EXPECT_EQ(ccw_triangles_overlap(a, b), overlap) << i;
    (overlap ? overlapping : apart) += 1;
  }
  EXPECT_GT(overlapping, 100);  // both answers exercised
  EXPECT_GT(apart, 100);
}

}  // namespace
}  // namespace ricci
