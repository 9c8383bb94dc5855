#include "ricci/metric/angles.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "ricci/mesh/topology.hpp"

namespace ricci {
namespace {

TEST(AngleFromLengths, EquilateralAndRightTriangles) {
  EXPECT_NEAR(angle_from_lengths(1, 1, 1), std::numbers::pi / 3, 1e-15);
  EXPECT_NEAR(angle_from_lengths(5, 3, 4), std::numbers::pi / 2, 1e-15);
  EXPECT_NEAR(angle_from_lengths(3, 4, 5), std::asin(0.6), 1e-15);
}

TEST(AngleFromLengths, NeedleTriangleKeepsRelativePrecision) {
  // Isosceles needle: legs 1, base b. Exact apex angle 2 asin(b / 2).
  for (double b : {1e-4, 1e-8, 1e-12}) {
    const double exact = 2 * std::asin(b / 2);
    EXPECT_NEAR(angle_from_lengths(b, 1, 1) / exact, 1.0, 1e-13) << "base " << b;
    // The two base angles are (pi - apex) / 2 each.
    EXPECT_NEAR(angle_from_lengths(1, 1, b), (std::numbers::pi - exact) / 2, 1e-15);
  }
  // A flat, obtuse sliver: sides 1, 1, 2 - d has apex angle near pi.
  const double a = 2 - 1e-10;
  const double d = 2 - a;  // exact (Sterbenz): the sliver the double a really describes
  const double apex = angle_from_lengths(a, 1, 1);
  EXPECT_NEAR((std::numbers::pi - apex) / (4 * std::asin(std::sqrt(d) / 2)), 1.0, 1e-10);
}

TEST(AngleFromLengths, TriangleInequalityViolationIsNaN) {
  EXPECT_TRUE(std::isnan(angle_from_lengths(3, 1, 1)));
  EXPECT_TRUE(std::isnan(angle_from_lengths(2, 1, 1)));  // degenerate counts as broken
  EXPECT_TRUE(std::isnan(angle_from_lengths(0, 1, 1)));
  EXPECT_TRUE(std::isnan(angle_from_lengths(-1, 1, 1)));
  EXPECT_TRUE(std::isnan(angle_from_lengths(NAN, 1, 1)));
}

TEST(CornerAngles, ReportsTheFirstBrokenFaceAndSumsToPi) {
  Triangles tris(2, 3);
  tris << 0, 1, 2, 2, 1, 3;
  const Topology t = build_topology(tris, 4);
  Eigen::VectorXd lengths = Eigen::VectorXd::Constant(t.num_edges, 1.0);
  CornerAngles angles;
  EXPECT_EQ(corner_angles(t, lengths, angles).first_bad_face, -1);
  for (int f = 0; f < 2; ++f) EXPECT_NEAR(angles.row(f).sum(), std::numbers::pi, 1e-15);
  // Stretch the edge only face 1 has: (1, 3).
  for (int e = 0; e < t.num_edges; ++e) {
    if (t.edge_vertices(e, 0) == 1 && t.edge_vertices(e, 1) == 3) lengths[e] = 2.5;
  }
  EXPECT_EQ(corner_angles(t, lengths, angles).first_bad_face, 1);
  EXPECT_TRUE(std::isnan(angles(1, 0)));
  EXPECT_NEAR(angles.row(0).sum(), std::numbers::pi, 1e-15);
}

}  // namespace
}  // namespace ricci
