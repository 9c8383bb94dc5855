#include "ricci/mesh/info.hpp"
#include "support/test_meshes.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>

namespace ricci {
namespace {

using testing::make_mesh;
using testing::tetrahedron;
using testing::torus;

/// The figures of a mesh's shape that the small meshes here have in closed form (the tests give
/// them in this order).
struct ShapeFigures {
  int boundary_loops = 0;
  int euler_characteristic = 0;
  int genus = 0;
  double min_angle_degrees = 0;
  double max_angle_degrees = 0;
  double bounding_box_diagonal = 0;
};

/// Angles to 1e-12 degrees, the diagonal to 1e-15 (a square root of a sum of a few squares).
void expect_shape(const MeshInfo& info, const ShapeFigures& expected) {
  EXPECT_EQ(info.boundary_loops, expected.boundary_loops);
  EXPECT_EQ(info.euler_characteristic, expected.euler_characteristic);
  EXPECT_EQ(info.genus, expected.genus);
  EXPECT_NEAR(info.min_angle_degrees, expected.min_angle_degrees, 1e-12);
  EXPECT_NEAR(info.max_angle_degrees, expected.max_angle_degrees, 1e-12);
  EXPECT_NEAR(info.bounding_box_diagonal, expected.bounding_box_diagonal, 1e-15);
}

TEST(MeshInfo, RegularTetrahedron) {
  const MeshInfo info = mesh_info(tetrahedron());
  EXPECT_EQ(info.vertices, 4);
  EXPECT_EQ(info.unreferenced_vertices, 0);
  EXPECT_EQ(info.edges, 6);
  EXPECT_EQ(info.faces, 4);
  EXPECT_EQ(info.components, 1);
  // Closed, genus 0, equilateral faces, spanning the cube [-1, 1]^3.
  expect_shape(info, {0, 2, 0, 60, 60, 2 * std::sqrt(3.0)});
  EXPECT_TRUE(info.validation.defects.empty());
  ASSERT_EQ(info.component_info.size(), 1u);
  const ComponentInfo& c = info.component_info[0];
  EXPECT_EQ(c.vertices, 4);
  EXPECT_EQ(c.edges, 6);
  EXPECT_EQ(c.faces, 4);
  EXPECT_EQ(c.euler_characteristic, 2);
}

TEST(MeshInfo, SquareDiskAndTorus) {
  const MeshInfo disk =
      mesh_info(make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(disk.edges, 5);
  // One boundary loop, half-squares of the unit square.
  expect_shape(disk, {1, 1, 0, 45, 90, std::sqrt(2.0)});

  const MeshInfo ring = mesh_info(torus(7, 5));
  EXPECT_EQ(ring.vertices, 35);
  EXPECT_EQ(ring.edges, 3 * 35);
  EXPECT_EQ(ring.faces, 70);
  EXPECT_EQ(ring.boundary_loops, 0);
  EXPECT_EQ(ring.euler_characteristic, 0);
  EXPECT_EQ(ring.genus, 1);
}

TEST(MeshInfo, ComponentsAndUnreferencedVertices) {
  // The tetrahedron, an unused vertex 4, and a separate triangle on vertices 5, 6, 7.
  const Mesh mesh = make_mesh({{1, 1, 1},
                               {1, -1, -1},
                               {-1, 1, -1},
                               {-1, -1, 1},
                               {9, 9, 9},
                               {3, 0, 0},
                               {4, 0, 0},
                               {3, 1, 0}},
                              {{0, 1, 2}, {0, 2, 3}, {5, 6, 7}, {0, 3, 1}, {1, 3, 2}});
  const MeshInfo info = mesh_info(mesh);
  EXPECT_EQ(info.vertices, 7);
  EXPECT_EQ(info.unreferenced_vertices, 1);
  EXPECT_EQ(info.edges, 9);
  EXPECT_EQ(info.components, 2);
  EXPECT_EQ(info.boundary_loops, 1);
  EXPECT_EQ(info.euler_characteristic, 7 - 9 + 5);
  EXPECT_EQ(info.genus, 0);
  // The unused vertex at (9, 9, 9) does not widen the box: it spans (-1,-1,-1) to (4, 1, 1).
  EXPECT_NEAR(info.bounding_box_diagonal, std::sqrt(25.0 + 4 + 4), 1e-14);
  ASSERT_EQ(info.component_info.size(), 2u);
  EXPECT_EQ(info.component_info[1].vertices, 3);
  EXPECT_EQ(info.component_info[1].edges, 3);
  EXPECT_EQ(info.component_info[1].faces, 1);
  EXPECT_EQ(info.component_info[1].boundary_loops, 1);
  EXPECT_EQ(info.component_info[1].euler_characteristic, 1);
  EXPECT_TRUE(info.validation.ok());
  ASSERT_EQ(info.validation.counts.size(), 1u);
  EXPECT_EQ(info.validation.counts[0].first, DefectKind::UnreferencedVertex);
}

TEST(MeshInfo, NeedleAnglesAreAccurate) {
  // A right needle: its smallest angle is atan(1e-9). acos of a normalised dot product would
  // return 0 here (the cosine rounds to 1).
  const MeshInfo thin = mesh_info(make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1e-9, 0}}, {{0, 1, 2}}));
  const double degrees = 180 / std::numbers::pi;
  EXPECT_NEAR(thin.min_angle_degrees / (std::atan(1e-9) * degrees), 1.0, 1e-12);
  EXPECT_NEAR(thin.max_angle_degrees, 90, 1e-12);
  // An obtuse needle: its largest angle is 180 degrees less twice atan(1e-8).
  const MeshInfo flat = mesh_info(make_mesh({{0, 0, 0}, {2, 0, 0}, {1, 1e-8, 0}}, {{0, 1, 2}}));
  EXPECT_NEAR(180 - flat.max_angle_degrees, 2 * std::atan(1e-8) * degrees, 1e-12);
  EXPECT_NEAR(flat.min_angle_degrees / (std::atan(1e-8) * degrees), 1.0, 1e-12);
}

TEST(MeshInfo, DefectsLeaveTopologyUndefinedButNeverThrow) {
  // Three faces on the edge (1, 2).
  const Mesh fin = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 1}},
                             {{0, 1, 2}, {1, 3, 2}, {1, 4, 2}});
  MeshInfo info;
  ASSERT_NO_THROW(info = mesh_info(fin));
  EXPECT_EQ(info.vertices, 5);
  EXPECT_EQ(info.faces, 3);
  EXPECT_EQ(info.edges, -1);
  EXPECT_EQ(info.components, -1);
  EXPECT_EQ(info.boundary_loops, -1);
  EXPECT_EQ(info.euler_characteristic, -1);
  EXPECT_EQ(info.genus, -1);
  EXPECT_TRUE(info.component_info.empty());
  EXPECT_FALSE(info.validation.ok());
  EXPECT_EQ(info.validation.defects[0].kind, DefectKind::NonManifoldEdge);
  EXPECT_NEAR(info.max_angle_degrees, 90, 1e-12);

  // An index out of range and a NaN: the angles come from the faces that can be measured.
  Mesh broken = tetrahedron();
  broken.triangles(1, 1) = 40;
  broken.positions(3, 0) = std::numeric_limits<double>::quiet_NaN();
  ASSERT_NO_THROW(info = mesh_info(broken));
  EXPECT_EQ(info.genus, -1);
  EXPECT_NEAR(info.min_angle_degrees, 60, 1e-12);  // face 0, the only face without vertex 3
  // Vertices 0, 1, 2 (vertex 3 is NaN) still span the cube [-1, 1]^3.
  EXPECT_NEAR(info.bounding_box_diagonal, 2 * std::sqrt(3.0), 1e-15);
}

TEST(MeshInfo, ZeroAreaFacesKeepTopologyDefined) {
  Mesh mesh = tetrahedron();
  mesh.positions.row(1) = mesh.positions.row(0);  // faces 0 and 2 collapse to segments
  const MeshInfo info = mesh_info(mesh);
  EXPECT_EQ(info.euler_characteristic, 2);
  EXPECT_EQ(info.genus, 0);
  ASSERT_EQ(info.validation.counts.size(), 1u);
  EXPECT_EQ(info.validation.counts[0], std::make_pair(DefectKind::ZeroAreaFace, 2));
  EXPECT_EQ(info.min_angle_degrees, 0);
}

}  // namespace
}  // namespace ricci
