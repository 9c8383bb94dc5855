#include "ricci/mesh/validate.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <string>
#include <typeinfo>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "support/error_messages.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

using testing::expect_mentions;
using testing::message_of;

using testing::make_mesh;
using testing::tetrahedron;
using testing::torus;

TEST(FindDefects, CleanClosedMeshesHaveNone) {
  EXPECT_TRUE(find_defects(tetrahedron()).defects.empty());
  EXPECT_TRUE(find_defects(torus(6, 5)).counts.empty());
  EXPECT_TRUE(find_defects(tetrahedron()).ok());
  EXPECT_NO_THROW(validate_mesh(torus(6, 5), "torus"));
}

TEST(FindDefects, NonFiniteCoordinate) {
  Mesh mesh = tetrahedron();
  mesh.positions(2, 1) = std::numeric_limits<double>::quiet_NaN();
  mesh.positions(3, 0) = -std::numeric_limits<double>::infinity();
  const ValidationReport report = find_defects(mesh);
  EXPECT_EQ(report.count(DefectKind::NonFiniteCoordinate), 2);
  ASSERT_EQ(report.defects.size(), 2u);  // the faces using them are not checked for area
  EXPECT_EQ(report.defects[0].element, 2);
  expect_mentions(report.defects[0].message, {"vertex 2", "(-1, nan, -1)"});
  expect_mentions(report.defects[1].message, {"vertex 3", "-inf"});
  expect_mentions(message_of<InvalidInput>([&] { validate_mesh(mesh, "m.obj"); }),
                  {"m.obj: vertex 2", "(and 1 more non-finite-coordinate defect)"});
}

TEST(FindDefects, IndexOutOfRange) {
  Mesh mesh = tetrahedron();
  mesh.triangles(1, 2) = 7;
  mesh.triangles(3, 0) = -1;
  const ValidationReport report = find_defects(mesh);
  EXPECT_EQ(report.count(DefectKind::IndexOutOfRange), 2);
  ASSERT_GE(report.defects.size(), 2u);
  EXPECT_EQ(report.defects[0].kind, DefectKind::IndexOutOfRange);
  EXPECT_EQ(report.defects[0].element, 1);
  expect_mentions(report.defects[0].message, {"face 1 uses vertex 7, outside [0, 4)"});
  EXPECT_EQ(report.defects[1].element, 3);
  expect_mentions(message_of<InvalidInput>([&] { validate_mesh(mesh, "ctx"); }), {"ctx: face 1"});
}

TEST(FindDefects, RepeatedVertex) {
  Mesh mesh = tetrahedron();
  mesh.triangles.row(2) << 0, 3, 0;
  const ValidationReport report = find_defects(mesh);
  EXPECT_EQ(report.count(DefectKind::RepeatedVertex), 1);
  EXPECT_EQ(report.defects[0].element, 2);
  expect_mentions(report.defects[0].message, {"face 2 uses vertex 0 more than once (0, 3, 0)"});
}

TEST(FindDefects, DuplicateFaceInEitherOrientation) {
  Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}},
                        {{0, 1, 2}, {1, 3, 2}, {2, 1, 0}, {0, 1, 2}});
  const ValidationReport report = find_defects(mesh);
  EXPECT_EQ(report.count(DefectKind::DuplicateFace), 2);
  ASSERT_GE(report.defects.size(), 2u);
  EXPECT_EQ(report.defects[0].element, 2);
  expect_mentions(report.defects[0].message, {"face 2 (2, 1, 0) has the same vertices as face 0"});
  EXPECT_EQ(report.defects[1].element, 3);
  // Three copies of face 0 put three faces on each of its edges.
  EXPECT_EQ(report.count(DefectKind::NonManifoldEdge), 3);
  expect_mentions(message_of<InvalidInput>([&] { validate_mesh(mesh, "d.off"); }),
                  {"d.off: face 2"});
}

TEST(FindDefects, NonManifoldEdge) {
  const Mesh mesh =
      make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 1}, {0.5, 0.5, -1}},
                {{0, 1, 2}, {1, 3, 2}, {1, 4, 2}, {2, 5, 1}});
  const ValidationReport report = find_defects(mesh);
  EXPECT_EQ(report.count(DefectKind::NonManifoldEdge), 1);
  ASSERT_FALSE(report.defects.empty());
  EXPECT_EQ(report.defects[0].element, 0);
  expect_mentions(report.defects[0].message,
                  {"non-manifold edge (1, 2) is shared by 4 faces (0, 1, 2, 3)"});
  expect_mentions(message_of<TopologyError>([&] { validate_mesh(mesh, "fin"); }),
                  {"fin: non-manifold edge"});
}

TEST(FindDefects, NonManifoldVertex) {
  // Two triangles meeting at vertex 2 only (a bow tie).
  const Mesh mesh =
      make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0, 2, 0}, {1, 2, 0}}, {{0, 1, 2}, {2, 4, 3}});
  const ValidationReport report = find_defects(mesh);
  ASSERT_EQ(report.defects.size(), 1u);
  EXPECT_EQ(report.defects[0].kind, DefectKind::NonManifoldVertex);
  EXPECT_EQ(report.defects[0].element, 2);
  expect_mentions(report.defects[0].message, {"non-manifold vertex 2", "2 fans", "faces 0 and 1"});
  expect_mentions(message_of<TopologyError>([&] { validate_mesh(mesh, "bowtie"); }),
                  {"bowtie: non-manifold vertex 2"});
}

TEST(FindDefects, InconsistentOrientationNamesTheFacesToFlip) {
  Mesh mesh = tetrahedron();
  mesh.triangles.row(3) << 1, 2, 3;  // reversed
  const ValidationReport report = find_defects(mesh);
  // All three edges of face 3 are traversed twice the same way; face 3 is the one to reverse.
  EXPECT_EQ(report.count(DefectKind::InconsistentOrientation), 3);
  ASSERT_EQ(report.defects.size(), 3u);
  for (const Defect& defect : report.defects) EXPECT_EQ(defect.element, 3);
  expect_mentions(report.defects[0].message,
                  {"faces 3 and", "in the same direction", "reversing face 3 makes it consistent"});
  expect_mentions(message_of<TopologyError>([&] { validate_mesh(mesh, "t"); }),
                  {"t: inconsistent orientation", "(and 2 more inconsistent-orientation defects)"});

  // On a torus with a reversed band of faces, the smaller side is the one named.
  Mesh band = torus(8, 6);
  for (int f = 0; f < 12; ++f) band.triangles.row(f) = band.triangles.row(f).reverse().eval();
  const ValidationReport band_report = find_defects(band);
  EXPECT_GT(band_report.count(DefectKind::InconsistentOrientation), 0);
  EXPECT_EQ(band_report.count(DefectKind::NonOrientable), 0);
  for (const Defect& defect : band_report.defects) EXPECT_LT(defect.element, 12);
  expect_mentions(band_report.defects[0].message, {"and the other 11 faces on its side"});
}

TEST(FindDefects, NonOrientable) {
  const ValidationReport report = find_defects(testing::moebius_strip(7));
  ASSERT_EQ(report.defects.size(), 1u);
  EXPECT_EQ(report.defects[0].kind, DefectKind::NonOrientable);
  EXPECT_EQ(report.defects[0].element, 0);
  expect_mentions(report.defects[0].message, {"non-orientable", "14 faces connected to face 0"});
  expect_mentions(
      message_of<TopologyError>([&] { validate_mesh(testing::moebius_strip(7), "strip.ply"); }),
      {"strip.ply: non-orientable"});
}

TEST(FindDefects, ZeroAreaWithScaleFreeTolerance) {
  // Face 1 is collinear, face 2 has two vertices at the same position, face 3 is a sliver 4e6
  // long and 1e-4 high: twice its area over its longest edge squared is 2.5e-11, above the
  // default tolerance although its absolute area (200) is large.
  const Mesh mesh = make_mesh({{0, 0, 0},
                               {1, 0, 0},
                               {0, 1, 0},
                               {2, 0, 0},
                               {0, 1, 0},
                               {0, 5e6, 0},
                               {2e6, 5e6 + 1e-4, 0},
                               {4e6, 5e6, 0}},
                              {{0, 1, 2}, {0, 3, 1}, {0, 2, 4}, {5, 7, 6}});
  const ValidationReport report = find_defects(mesh);
  EXPECT_EQ(report.count(DefectKind::ZeroAreaFace), 2);
  ASSERT_EQ(report.defects.size(), 2u);
  EXPECT_EQ(report.defects[0].element, 1);
  EXPECT_EQ(report.defects[1].element, 2);
  expect_mentions(report.defects[0].message, {"face 1 (0, 3, 1) has zero area"});
  ValidationOptions loose;
  loose.zero_area_tolerance = 1e-9;
  EXPECT_EQ(find_defects(mesh, loose).count(DefectKind::ZeroAreaFace), 3);
  expect_mentions(message_of<InvalidInput>([&] { validate_mesh(mesh, "z"); }),
                  {"z: face 1", "zero area", "(and 1 more zero-area-face defect)"});
}

TEST(FindDefects, UnreferencedVertexIsOnlyAWarning) {
  Mesh mesh = tetrahedron();
  mesh.positions.conservativeResize(6, 3);
  mesh.positions.bottomRows(2).setZero();
  const ValidationReport report = find_defects(mesh);
  EXPECT_TRUE(report.ok());
  EXPECT_EQ(report.count(DefectKind::UnreferencedVertex), 2);
  ASSERT_EQ(report.defects.size(), 2u);
  EXPECT_EQ(report.defects[1].element, 5);
  expect_mentions(report.defects[0].message, {"vertex 4 is not used by any face"});
  EXPECT_NO_THROW(validate_mesh(mesh, "u"));
}

TEST(FindDefects, ReportsInCheckOrderAndThrowsTheFirst) {
  // A zero-area face (checked last) comes before a non-manifold edge (checked earlier) in face
  // order; later a non-finite coordinate (checked first) is added.
  Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}},
                        {{0, 1, 2}, {0, 1, 3}, {1, 0, 4}, {0, 1, 5}});
  ValidationReport report = find_defects(mesh);
  ASSERT_EQ(report.counts.size(), 3u);
  EXPECT_EQ(report.counts[0], std::make_pair(DefectKind::NonManifoldEdge, 1));
  EXPECT_EQ(report.counts[1].first, DefectKind::NonManifoldVertex);
  EXPECT_EQ(report.counts[2], std::make_pair(DefectKind::ZeroAreaFace, 1));
  expect_mentions(message_of<TopologyError>([&] { throw_first_defect(report, "x"); }),
                  {"x: non-manifold edge (0, 1) is shared by 4 faces"});

  mesh.positions(5, 2) = std::numeric_limits<double>::infinity();
  report = find_defects(mesh);
  EXPECT_EQ(report.counts[0].first, DefectKind::NonFiniteCoordinate);
  EXPECT_EQ(report.defects[0].kind, DefectKind::NonFiniteCoordinate);
  expect_mentions(message_of<InvalidInput>([&] { throw_first_defect(report, ""); }),
                  {"validate_mesh: vertex 5 has a non-finite coordinate"});
}

TEST(FindDefects, ListsAtMostMaxDefectsPerKindButCountsAll) {
  Mesh mesh;
  mesh.positions.resize(3 * 50, 3);
  mesh.triangles.resize(50, 3);
  for (int f = 0; f < 50; ++f) {  // 50 separate collinear triangles
    for (int k = 0; k < 3; ++k) mesh.positions.row(3 * f + k) << k, f, 0;
    mesh.triangles.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
  }
  ValidationOptions options;
  options.max_defects_per_kind = 4;
  const ValidationReport report = find_defects(mesh, options);
  EXPECT_EQ(report.defects.size(), 4u);
  EXPECT_EQ(report.count(DefectKind::ZeroAreaFace), 50);
  EXPECT_EQ(report.defects[3].element, 3);
}

TEST(FindDefects, DefectNamesAreStable) {
  EXPECT_STREQ(defect_name(DefectKind::NonFiniteCoordinate), "non-finite-coordinate");
  EXPECT_STREQ(defect_name(DefectKind::IndexOutOfRange), "index-out-of-range");
  EXPECT_STREQ(defect_name(DefectKind::RepeatedVertex), "repeated-vertex");
  EXPECT_STREQ(defect_name(DefectKind::ZeroAreaFace), "zero-area-face");
  EXPECT_STREQ(defect_name(DefectKind::DuplicateFace), "duplicate-face");
  EXPECT_STREQ(defect_name(DefectKind::NonManifoldEdge), "non-manifold-edge");
  EXPECT_STREQ(defect_name(DefectKind::NonManifoldVertex), "non-manifold-vertex");
  EXPECT_STREQ(defect_name(DefectKind::InconsistentOrientation), "inconsistent-orientation");
  EXPECT_STREQ(defect_name(DefectKind::NonOrientable), "non-orientable");
  EXPECT_STREQ(defect_name(DefectKind::UnreferencedVertex), "unreferenced-vertex");
}

// A clean 1M-face mesh has no defect (speed is the benchmark's business, not a test's).
TEST(FindDefects, MillionFaceTorusHasNone) {
  const Mesh mesh = torus(1000, 500);  // 500k vertices, 1M faces
  const ValidationReport report = find_defects(mesh);
  EXPECT_TRUE(report.counts.empty());
  EXPECT_TRUE(report.ok());
}

}  // namespace
}  // namespace ricci
