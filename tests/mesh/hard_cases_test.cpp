#include "ricci/mesh/hard_cases.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {
namespace {

TEST(BallWithFingers, CountsTopologyOrientationAndLength) {
  for (int fingers : {0, 1, 5, 6}) {
    const int resolution = 8;
    const double aspect = 2.5;
    const Mesh mesh = make_ball_with_fingers(fingers, aspect, resolution);
    const int rings = 20;  // round(8 aspect)
    EXPECT_EQ(mesh.num_vertices(), 6 * resolution * resolution + 2 + 8 * rings * fingers);
    EXPECT_EQ(mesh.num_faces(), 12 * resolution * resolution + 16 * rings * fingers);
    const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
    ASSERT_EQ(t.components.size(), 1u);
    EXPECT_EQ(t.num_referenced_vertices(), mesh.num_vertices());
    EXPECT_EQ(t.components[0].genus, 0);
    EXPECT_EQ(t.components[0].num_boundary_loops, 0);
    // Outward: positive signed volume (divergence theorem), and every face of positive area.
    double volume = 0, smallest = INFINITY;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, 0));
      const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(f, 1));
      const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(f, 2));
      volume += a.dot(b.cross(c)) / 6;
      smallest = std::min(smallest, (b - a).cross(c - a).norm());
    }
    EXPECT_GT(volume, 4.0);  // the unit ball's 4.19 less the blocks, plus the fingers
    EXPECT_GT(smallest, 1e-4);
    // Each finger: as long as `aspect` circumferences of its octagon (radius r, the mean
    // distance of the block's boundary from its centre, about 2.4 / resolution: (2 + 2 sqrt 2)
    // / 2 cells of width 2 / resolution), plus the cap's dome of r / 2.
    double reach = 0;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      reach = std::max(reach, mesh.positions.row(v).norm());
    }
    if (fingers == 0) {
      EXPECT_NEAR(reach, 1.0, 1e-12);
    } else {
      const double radius = 2.4 / resolution, length = 2 * std::numbers::pi * radius * aspect;
      EXPECT_NEAR(reach, 1 + length + radius / 2, 0.05 * length);
    }
  }
}

TEST(BallWithFingers, RefusesBadArguments) {
  EXPECT_THROW(make_ball_with_fingers(7, 2.0), InvalidInput);
  EXPECT_THROW(make_ball_with_fingers(-1, 2.0), InvalidInput);
  EXPECT_THROW(make_ball_with_fingers(3, 0.0), InvalidInput);
  EXPECT_THROW(make_ball_with_fingers(3, NAN), InvalidInput);
  EXPECT_THROW(make_ball_with_fingers(3, 2.0, 7), InvalidInput);
  try {
    make_ball_with_fingers(3, 2.0, 2);
    FAIL() << "resolution 2 accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("make_ball_with_fingers:"), std::string::npos);
  }
}

}  // namespace
}  // namespace ricci
