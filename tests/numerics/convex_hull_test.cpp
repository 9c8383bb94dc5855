#include "ricci/numerics/convex_hull.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "ricci/numerics/predicates.hpp"

namespace ricci {
namespace {

TEST(ConvexHull, ContainsEveryPointAndIsStrictlyConvex) {
  std::mt19937 rng(3);
  std::normal_distribution<double> where(0, 1);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Eigen::Vector2d> points(10 + 50 * trial);
    for (Eigen::Vector2d& p : points) p = Eigen::Vector2d(where(rng), where(rng));
    const std::vector<Eigen::Vector2d> hull = convex_hull(points);
    ASSERT_GE(hull.size(), 3u);
    const std::size_t n = hull.size();
    for (std::size_t i = 0; i < n; ++i) {
      // Counter-clockwise with no collinear points: every turn strictly left.
      EXPECT_EQ(orientation_sign(hull[i], hull[(i + 1) % n], hull[(i + 2) % n]), 1) << trial;
      // Every input point on the closed inner side of every edge.
      for (const Eigen::Vector2d& p : points) {
        EXPECT_GE(orientation_sign(hull[i], hull[(i + 1) % n], p), 0) << trial;
      }
    }
    // Hull vertices are input points.
    for (const Eigen::Vector2d& h : hull) {
      EXPECT_NE(std::find(points.begin(), points.end(), h), points.end());
    }
  }
}

TEST(ConvexHull, SquareWithCollinearInteriorAndRepeatedPoints) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= 4; ++i) {
    for (int j = 0; j <= 4; ++j) points.emplace_back(i, j);
  }
  points.emplace_back(0, 0);  // a repeat
  const std::vector<Eigen::Vector2d> hull = convex_hull(points);
  const std::vector<Eigen::Vector2d> expected{{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  EXPECT_EQ(hull, expected);
  // Fewer than three distinct points: sorted, deduplicated.
  const std::vector<Eigen::Vector2d> two = convex_hull({{1, 1}, {0, 0}, {1, 1}});
  EXPECT_EQ(two, (std::vector<Eigen::Vector2d>{{0, 0}, {1, 1}}));
  // All collinear: the two ends.
  EXPECT_EQ(convex_hull({{0, 0}, {2, 2}, {1, 1}, {3, 3}}).size(), 2u);
}

TEST(MinimalRectangleRotation, TurnsARotatedRectangleBackOntoTheAxes) {
  for (const double angle : {0.0, 0.1, 0.3, std::numbers::pi / 6, -0.7, 1.2, 2.0, -2.5}) {
    const Eigen::Rotation2Dd turn(angle);
    std::vector<Eigen::Vector2d> points;
    for (const auto& [x, y] : {std::pair{0.0, 0.0}, {3.0, 0.0}, {3.0, 1.0}, {0.0, 1.0}}) {
      points.emplace_back(turn * Eigen::Vector2d(x, y) + Eigen::Vector2d(5, -2));
    }
    points.emplace_back(turn * Eigen::Vector2d(1.5, 0.5) + Eigen::Vector2d(5, -2));  // inside
    const double rotation = minimal_rectangle_rotation(convex_hull(points));
    // Back onto the axes up to a quarter turn, and the smallest such turn.
    EXPECT_NEAR(std::remainder(rotation + angle, std::numbers::pi / 2), 0, 1e-12) << angle;
    EXPECT_LE(std::abs(rotation), std::numbers::pi / 4 + 1e-12) << angle;
    // The turned box has the rectangle's area.
    const Eigen::Rotation2Dd back(rotation);
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
    for (const Eigen::Vector2d& p : points) {
      lo = lo.cwiseMin(back * p), hi = hi.cwiseMax(back * p);
    }
    EXPECT_NEAR((hi - lo).prod(), 3.0, 1e-12) << angle;
  }
}

TEST(MinimalRectangleRotation, AxisAlignedStaysAndDegenerateIsZero) {
  EXPECT_EQ(minimal_rectangle_rotation(convex_hull({{0, 0}, {2, 0}, {2, 1}, {0, 1}})), 0);
  EXPECT_EQ(minimal_rectangle_rotation({{0, 0}, {1, 1}}), 0);
  EXPECT_EQ(minimal_rectangle_rotation({}), 0);
}

}  // namespace
}  // namespace ricci
