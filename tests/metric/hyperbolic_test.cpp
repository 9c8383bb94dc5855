#include "ricci/metric/hyperbolic.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "ricci/mesh/generate.hpp"
#include "ricci/metric/lengths.hpp"

namespace ricci {
namespace {

TEST(HyperbolicCosineLaw, EquilateralTriangleHasTheClosedFormAngle) {
  // Side a: cos A = (cosh^2 a - cosh a) / sinh^2 a = cosh a / (1 + cosh a); area pi - 3A.
  for (double a : {1e-6, 1e-3, 0.1, 1.0, 3.0, 10.0}) {
    const double angle = hyperbolic_angle_from_lengths(a, a, a);
    const double expected = std::acos(std::cosh(a) / (1.0 + std::cosh(a)));
    EXPECT_NEAR(angle, expected, 1e-12 * expected) << "a = " << a;
    EXPECT_LT(angle, std::numbers::pi / 3);  // angle sum below pi: negative curvature
  }
  // Small triangles are nearly Euclidean (60 degrees), huge ones nearly ideal (angle -> 0).
  EXPECT_NEAR(hyperbolic_angle_from_lengths(1e-6, 1e-6, 1e-6), std::numbers::pi / 3, 1e-12);
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

TEST(HyperbolicUnifiedForm, MeshLengthsAgreeWithTheCoshFormForCirclePackings) {
  // The mesh-wide lengths (2 asinh sqrt(q) form) against cosh l = cosh r_i cosh r_j +
  // eta sinh r_i sinh r_j, and the mesh-wide angles against the per-triangle law of cosines.
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  std::mt19937 random(7);
  std::uniform_real_distribution<double> radius(0.05, 1.5), eta(0.0, 1.0);
  ConformalStructure s;
  s.scheme = Scheme::Thurston;
  s.geometry = Geometry::Hyperbolic;
  s.epsilon = Eigen::VectorXd::Ones(t.num_vertices);
  s.eta.resize(t.num_edges);
  Eigen::VectorXd r(t.num_vertices), u(t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) s.eta[e] = eta(random);
  for (int v = 0; v < t.num_vertices; ++v) {
    r[v] = radius(random);
    u[v] = hyperbolic_log_radius(r[v]);
  }
  Eigen::VectorXd l;
  ASSERT_EQ(edge_lengths(t, s, u, l).invalid_edges, 0);
  for (int e = 0; e < t.num_edges; ++e) {
    const double expected =
        hyperbolic_edge_length(r[t.edge_vertices(e, 0)], r[t.edge_vertices(e, 1)], s.eta[e]);
    EXPECT_NEAR(l[e], expected, 1e-12 * expected) << "edge " << e;
  }
  CornerAngles angles;
  // Circles meeting at angles up to pi/2 always make triangles (Thurston).
  ASSERT_EQ(corner_angles(t, l, angles, Geometry::Hyperbolic).first_bad_face, -1);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const double expected = hyperbolic_angle_from_lengths(
          l[t.face_edges(f, k)], l[t.face_edges(f, (k + 1) % 3)], l[t.face_edges(f, (k + 2) % 3)]);
      EXPECT_NEAR(angles(f, k), expected, 1e-13) << "face " << f;
    }
  }
  // Hyperbolic triangles have angle sums below pi.
  EXPECT_GT(hyperbolic_total_area(angles), 0);
}

}  // namespace
}  // namespace ricci
