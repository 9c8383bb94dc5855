#include "ricci/mesh/repair.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/info.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

using testing::make_mesh;
using testing::tetrahedron;
using testing::torus;

bool mentions(const std::vector<std::string>& lines, const std::string& piece) {
  return std::any_of(lines.begin(), lines.end(), [&](const std::string& line) {
    return line.find(piece) != std::string::npos;
  });
}

Eigen::Vector3d corner_of(const Mesh& mesh, int f, int k) {
  return mesh.positions.row(mesh.triangles(f, k)).transpose();
}

/// The area vector of face f (its normal times twice its area).
Eigen::Vector3d twice_area_vector(const Mesh& mesh, int f) {
  return (corner_of(mesh, f, 1) - corner_of(mesh, f, 0))
      .cross(corner_of(mesh, f, 2) - corner_of(mesh, f, 0));
}

double total_face_area(const Mesh& mesh) {
  double area = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) area += 0.5 * twice_area_vector(mesh, f).norm();
  return area;
}

/// The pieces of each split input face cover it: their area vectors add up to its own (up to the
/// orientation face_flipped gives), and every corner of a piece lies in the input face.
void expect_pieces_cover_their_faces(const Mesh& input, const RepairResult& r) {
  std::vector<Eigen::Vector3d> sum(input.num_faces(), Eigen::Vector3d::Zero());
  std::vector<char> split(input.num_faces(), 0);
  for (int f = 0; f < r.mesh.num_faces(); ++f) {
    if (!r.face_split[f]) continue;
    const int g = r.face_map[f];
    split[g] = 1;
    sum[g] += (r.face_flipped[f] ? -1.0 : 1.0) * twice_area_vector(r.mesh, f);
    const Eigen::Vector3d normal = twice_area_vector(input, g);
    double longest = 0;
    for (int k = 0; k < 3; ++k) {
      longest =
          std::max(longest, (corner_of(input, g, k) - corner_of(input, g, (k + 1) % 3)).norm());
    }
    if (normal.norm() <= 1e-9 * longest * longest) continue;  // a sliver split across another
    for (int k = 0; k < 3; ++k) {
      // Barycentric coordinates of the corner in g: each in [0, 1] up to rounding.
      const Eigen::Vector3d p = corner_of(r.mesh, f, k);
      for (int i = 0; i < 3; ++i) {
        const double weight = (corner_of(input, g, (i + 1) % 3) - p)
                                  .cross(corner_of(input, g, (i + 2) % 3) - p)
                                  .dot(normal) /
                              normal.squaredNorm();
        EXPECT_GE(weight, -1e-9) << "piece " << f << " corner " << k << " outside face " << g;
      }
    }
  }
  for (int g = 0; g < input.num_faces(); ++g) {
    if (!split[g]) continue;
    const Eigen::Vector3d whole = twice_area_vector(input, g);
    double scale = 0;  // of the rounding: the longest edge squared
    for (int k = 0; k < 3; ++k) {
      scale = std::max(scale,
                       (corner_of(input, g, k) - corner_of(input, g, (k + 1) % 3)).squaredNorm());
    }
    // The pieces miss the sliver: twice its area is at most 1e-12 times its longest edge squared.
    EXPECT_LE((sum[g] - whole).norm(), 2e-12 * scale) << "the pieces of face " << g;
  }
}

/// nv random vertices in [-1, 1]^3 (with on_a_line: all but every third on the x axis, so that
/// slivers and chains of them arise) and nf random faces among them, drawn in that order.
Mesh random_soup(std::mt19937& random, int nv, int nf, bool on_a_line) {
  std::uniform_real_distribution<double> coordinate(-1, 1);
  std::uniform_int_distribution<int> vertex(0, nv - 1);
  Mesh mesh;
  mesh.positions.resize(nv, 3);
  for (int v = 0; v < nv; ++v) {
    if (on_a_line && v % 3 != 2) {
      mesh.positions.row(v) << coordinate(random), 0, 0;
    } else {
      mesh.positions.row(v) << coordinate(random), coordinate(random), coordinate(random);
    }
  }
  mesh.triangles.resize(nf, 3);
  for (int f = 0; f < nf; ++f) {
    mesh.triangles.row(f) << vertex(random), vertex(random), vertex(random);
  }
  return mesh;
}

/// The maps are what the header promises: every output vertex sits where its input vertex does,
/// and every output face is its input face (corners 1 and 2 exchanged when flipped) up to the
/// vertices that were welded, or a piece of it.
void expect_maps_consistent(const Mesh& input, const RepairResult& r) {
  ASSERT_EQ(static_cast<int>(r.vertex_map.size()), r.mesh.num_vertices());
  ASSERT_EQ(static_cast<int>(r.face_map.size()), r.mesh.num_faces());
  ASSERT_EQ(static_cast<int>(r.face_flipped.size()), r.mesh.num_faces());
  ASSERT_EQ(static_cast<int>(r.face_split.size()), r.mesh.num_faces());
  for (int v = 0; v < r.mesh.num_vertices(); ++v) {
    EXPECT_EQ(r.mesh.positions.row(v), input.positions.row(r.vertex_map[v])) << "vertex " << v;
  }
  expect_pieces_cover_their_faces(input, r);
  for (int f = 0; f < r.mesh.num_faces(); ++f) {
    if (r.face_split[f]) continue;
    const int g = r.face_map[f];
    const int order[3] = {0, r.face_flipped[f] ? 2 : 1, r.face_flipped[f] ? 1 : 2};
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(r.mesh.positions.row(r.mesh.triangles(f, k)),
                input.positions.row(input.triangles(g, order[k])))
          << "face " << f << " corner " << k;
    }
  }
  EXPECT_EQ(r.report.output_vertices, r.mesh.num_vertices());
  EXPECT_EQ(r.report.output_faces, r.mesh.num_faces());
}

TEST(RepairMesh, CleanMeshComesBackUnchanged) {
  const Mesh mesh = torus(8, 5);
  const RepairResult r = repair_mesh(mesh);
  EXPECT_FALSE(r.report.changed());
  EXPECT_TRUE(r.report.messages.empty());
  EXPECT_EQ(r.mesh.positions, mesh.positions);
  EXPECT_EQ(r.mesh.triangles, mesh.triangles);
  std::vector<int> identity(40);
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(r.vertex_map, identity);
  identity.resize(80);
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(r.face_map, identity);
}

TEST(RepairMesh, WeldsATriangleSoupIntoAClosedSurface) {
  // Every face of an icosphere with its own three vertices: 80 faces, 240 vertices.
  const Mesh sphere = make_icosphere(1);
  Mesh soup;
  soup.positions.resize(3 * sphere.num_faces(), 3);
  soup.triangles.resize(sphere.num_faces(), 3);
  for (int f = 0; f < sphere.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      soup.positions.row(3 * f + k) = sphere.positions.row(sphere.triangles(f, k));
      soup.triangles(f, k) = 3 * f + k;
    }
  }
  ASSERT_GT(find_defects(soup).count(DefectKind::InconsistentOrientation) +
                mesh_info(soup).boundary_loops,
            0);
  const RepairResult r = repair_mesh(soup);
  expect_maps_consistent(soup, r);
  EXPECT_EQ(r.report.welded_vertices.count, 240 - 42);
  EXPECT_EQ(r.report.welded_vertices.examples.size(), 5u);
  EXPECT_EQ(r.mesh.num_vertices(), 42);
  EXPECT_EQ(r.mesh.num_faces(), 80);
  EXPECT_EQ(r.report.unreferenced_vertices_dropped.count, 0);  // welded, not dropped
  EXPECT_TRUE(mentions(r.report.messages, "welded 198 vertices"));
  const MeshInfo info = mesh_info(r.mesh);
  EXPECT_TRUE(info.validation.ok());
  EXPECT_EQ(info.euler_characteristic, 2);
  EXPECT_EQ(info.boundary_loops, 0);
}

TEST(RepairMesh, WeldToleranceIsRelativeToTheBoundingBox) {
  // Two unit squares side by side whose shared side is 1e-9 apart.
  const Mesh mesh = make_mesh({{0, 0, 0},
                               {1, 0, 0},
                               {1, 1, 0},
                               {0, 1, 0},
                               {1 + 1e-9, 0, 0},
                               {2, 0, 0},
                               {2, 1, 0},
                               {1 + 1e-9, 1, 0}},
                              {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}});
  EXPECT_FALSE(repair_mesh(mesh).report.changed());  // exact by default
  RepairOptions loose;
  loose.weld_tolerance = 1e-6;  // of the diagonal sqrt(5)
  const RepairResult r = repair_mesh(mesh, loose);
  EXPECT_EQ(r.report.welded_vertices.count, 2);
  EXPECT_EQ(r.report.welded_vertices.examples, (std::vector<int>{4, 7}));
  EXPECT_EQ(r.mesh.num_vertices(), 6);
  EXPECT_TRUE(mentions(r.report.messages, "within the weld tolerance"));
  const MeshInfo info = mesh_info(r.mesh);
  EXPECT_EQ(info.edges, 9);
  EXPECT_EQ(info.boundary_loops, 1);
  EXPECT_EQ(info.euler_characteristic, 1);
  loose.weld_tolerance = 1e-12;  // 2.2e-12 absolute: too small to reach 1e-9
  EXPECT_EQ(repair_mesh(mesh, loose).report.welded_vertices.count, 0);
}

TEST(RepairMesh, RemovesDuplicateAndCollapsedFacesAndDropsUnusedVertices) {
  // A tetrahedron, a copy of face 0 reversed, a face that collapses when vertex 4 (a copy of
  // vertex 1) is welded, a face that repeats a vertex outright, and vertex 5 used by none.
  Mesh mesh =
      make_mesh({{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, -1}, {7, 7, 7}},
                {{0, 1, 2}, {0, 2, 3}, {2, 1, 0}, {0, 3, 1}, {1, 4, 3}, {1, 3, 2}, {3, 3, 0}});
  const RepairResult r = repair_mesh(mesh);
  expect_maps_consistent(mesh, r);
  const RepairReport& report = r.report;
  EXPECT_EQ(report.welded_vertices.examples, (std::vector<int>{4}));
  EXPECT_EQ(report.repeated_vertex_faces_removed.examples, (std::vector<int>{4, 6}));
  EXPECT_EQ(report.duplicate_faces_removed.examples, (std::vector<int>{2}));
  EXPECT_EQ(report.unreferenced_vertices_dropped.examples, (std::vector<int>{5}));
  EXPECT_EQ(report.faces_flipped.count, 0);
  EXPECT_EQ(r.face_map, (std::vector<int>{0, 1, 3, 5}));
  EXPECT_EQ(r.vertex_map, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(r.mesh.triangles, tetrahedron().triangles);
  EXPECT_TRUE(mentions(report.messages, "face 2, the same vertices as face 0"));
  EXPECT_TRUE(mentions(report.messages, "removed 2 faces that use a vertex twice after welding"));
  EXPECT_TRUE(mentions(report.messages, "dropped 1 unreferenced vertices (e.g. vertex 5)"));
  EXPECT_TRUE(find_defects(r.mesh).counts.empty());
}

TEST(RepairMesh, SplitsTwoTetrahedraSharingAnEdge) {
  // Outward-oriented tetrahedra on (0, 1, 2, 3) and (0, 1, 4, 5) share the edge (0, 1): four
  // faces on it.
  Mesh mesh = make_mesh(
      {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0.2}, {0.5, 0.5, 1}, {0.5, -1, 0.2}, {0.5, -0.5, -1}},
      {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 4, 1}, {0, 1, 5}, {0, 5, 4}, {1, 4, 5}});
  ASSERT_TRUE(find_defects(tetrahedron()).counts.empty());
  ASSERT_EQ(find_defects(mesh).count(DefectKind::NonManifoldEdge), 1);
  ASSERT_EQ(find_defects(mesh).count(DefectKind::InconsistentOrientation), 0);
  const RepairResult r = repair_mesh(mesh);
  expect_maps_consistent(mesh, r);
  EXPECT_EQ(r.report.non_manifold_edges_split, 1);
  ASSERT_EQ(r.report.non_manifold_edge_examples.size(), 1u);
  EXPECT_EQ(r.report.non_manifold_edge_examples[0], (std::array<int, 2>{0, 1}));
  EXPECT_EQ(r.report.non_manifold_vertices_split.examples, (std::vector<int>{0, 1}));
  EXPECT_EQ(r.report.vertex_copies_added, 2);
  EXPECT_EQ(r.report.faces_flipped.count, 0);
  EXPECT_EQ(r.vertex_map, (std::vector<int>{0, 1, 2, 3, 4, 5, 0, 1}));
  // The pairing follows the solids: two closed tetrahedra, not faces of both glued across.
  const MeshInfo info = mesh_info(r.mesh);
  ASSERT_TRUE(info.validation.ok()) << info.validation.defects[0].message;
  EXPECT_EQ(info.components, 2);
  for (const ComponentInfo& c : info.component_info) {
    EXPECT_EQ(c.faces, 4);
    EXPECT_EQ(c.euler_characteristic, 2);
  }
}

TEST(RepairMesh, ThreeSheetsOnAnEdgeKeepOnePairAndDetachTheThird) {
  // Three triangles on the edge (0, 1): two form a flat square, one stands up.
  Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}},
                        {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  const RepairResult r = repair_mesh(mesh);
  expect_maps_consistent(mesh, r);
  EXPECT_EQ(r.report.non_manifold_edges_split, 1);
  EXPECT_EQ(r.mesh.num_vertices(), 7);
  const MeshInfo info = mesh_info(r.mesh);
  ASSERT_TRUE(info.validation.ok()) << info.validation.defects[0].message;
  EXPECT_EQ(info.components, 2);
  EXPECT_EQ(info.edges, 5 + 3);
}

TEST(RepairMesh, SplitsABowTieVertex) {
  const Mesh mesh =
      make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0, 2, 0}, {1, 2, 0}}, {{0, 1, 2}, {2, 4, 3}});
  const RepairResult r = repair_mesh(mesh);
  expect_maps_consistent(mesh, r);
  EXPECT_EQ(r.report.non_manifold_edges_split, 0);
  EXPECT_EQ(r.report.non_manifold_vertices_split.examples, (std::vector<int>{2}));
  EXPECT_EQ(r.report.vertex_copies_added, 1);
  EXPECT_EQ(r.vertex_map, (std::vector<int>{0, 1, 2, 3, 4, 2}));
  EXPECT_EQ(r.mesh.triangles.row(1), Eigen::RowVector3i(5, 4, 3));
  EXPECT_TRUE(mentions(r.report.messages,
                       "split 1 non-manifold vertices into one copy per fan of faces (1 copies "
                       "added) (e.g. vertex 2)"));
  EXPECT_TRUE(find_defects(r.mesh).counts.empty());
}

TEST(RepairMesh, SplitsTwoClosedSurfacesTouchingAtAVertex) {
  // Two tetrahedra sharing vertex 0 only.
  Mesh mesh = make_mesh(
      {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}},
      {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}});
  ASSERT_EQ(find_defects(mesh).count(DefectKind::NonManifoldVertex), 1);
  const RepairResult r = repair_mesh(mesh);
  EXPECT_EQ(r.report.non_manifold_vertices_split.count, 1);
  const MeshInfo info = mesh_info(r.mesh);
  ASSERT_TRUE(info.validation.ok());
  EXPECT_EQ(info.components, 2);
  EXPECT_EQ(info.euler_characteristic, 4);
}

TEST(RepairMesh, KeepsOnlyTheLargestComponentWhenAsked) {
  // A lone triangle (vertices 0-2) listed before a tetrahedron (vertices 3-6), one of whose
  // vertices (7) repeats vertex 3's position.
  Mesh mesh = make_mesh({{5, 5, 5},
                         {6, 5, 5},
                         {5, 6, 5},
                         {1, 1, 1},
                         {1, -1, -1},
                         {-1, 1, -1},
                         {-1, -1, 1},
                         {1, 1, 1}},
                        {{0, 1, 2}, {3, 4, 5}, {7, 5, 6}, {3, 6, 4}, {4, 6, 5}});
  RepairOptions options;
  EXPECT_EQ(repair_mesh(mesh, options).mesh.num_faces(), 5);
  options.largest_component_only = true;
  const RepairResult r = repair_mesh(mesh, options);
  expect_maps_consistent(mesh, r);
  EXPECT_EQ(r.report.smaller_components_removed.count, 1);
  EXPECT_EQ(r.report.smaller_components_removed.examples, (std::vector<int>{0}));
  EXPECT_EQ(r.report.smaller_component_faces_removed, 1);
  EXPECT_EQ(r.face_map, (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(r.vertex_map, (std::vector<int>{3, 4, 5, 6}));
  EXPECT_EQ(r.mesh.triangles, tetrahedron().triangles);
  EXPECT_EQ(r.weld_map, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 3}));
  EXPECT_EQ(r.report.unreferenced_vertices_dropped.count, 0);  // removed with their component
  EXPECT_TRUE(mentions(r.report.messages,
                       "removed 1 components smaller than the largest (1 "
                       "faces; 4 faces kept) (e.g. the one with face 0)"));
}

TEST(RepairMesh, OrientsEachComponentByItsMajority) {
  Mesh mesh = torus(8, 6);
  for (int f = 0; f < 12; ++f) mesh.triangles.row(f) = mesh.triangles.row(f).reverse().eval();
  const RepairResult r = repair_mesh(mesh);
  expect_maps_consistent(mesh, r);
  EXPECT_EQ(r.report.faces_flipped.count, 12);
  EXPECT_EQ(r.report.faces_flipped.examples, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_TRUE(find_defects(r.mesh).counts.empty());
  // Reversing (a, b, c) gives (c, b, a); exchanging corners 1 and 2 gives (c, a, b): the same
  // triangle.
  const Mesh original = torus(8, 6);
  for (int f = 0; f < 12; ++f) {
    EXPECT_EQ(r.mesh.triangles.row(f),
              Eigen::RowVector3i(original.triangles(f, 2), original.triangles(f, 0),
                                 original.triangles(f, 1)));
  }
}

TEST(RepairMesh, LeavesANonOrientableComponentAndSaysSo) {
  // A Moebius strip beside a tetrahedron with one face reversed: the tetrahedron is fixed.
  const Mesh strip = testing::moebius_strip(7);
  Mesh mesh;
  mesh.positions.resize(18, 3);
  mesh.positions << strip.positions, tetrahedron().positions.array() + 5.0;
  mesh.triangles.resize(18, 3);
  Triangles tetra = tetrahedron().triangles.array() + 14;
  tetra.row(3) = tetra.row(3).reverse().eval();
  mesh.triangles << strip.triangles, tetra;
  const RepairResult r = repair_mesh(mesh);
  EXPECT_EQ(r.report.non_orientable_components.count, 1);
  EXPECT_EQ(r.report.non_orientable_components.examples, (std::vector<int>{0}));
  EXPECT_EQ(r.report.faces_flipped.examples, (std::vector<int>{17}));
  EXPECT_EQ(r.mesh.triangles.topRows(14), strip.triangles);
  EXPECT_TRUE(mentions(r.report.messages, "not repaired: 1 non-orientable components"));
  const ValidationReport after = find_defects(r.mesh);
  EXPECT_EQ(after.counts.size(), 1u);
  EXPECT_EQ(after.count(DefectKind::NonOrientable), 1);
}

TEST(RepairMesh, NonFiniteCoordinatesAreLeft) {
  Mesh mesh = tetrahedron();
  mesh.positions(2, 1) = std::nan("");
  const RepairResult r = repair_mesh(mesh);
  EXPECT_FALSE(r.report.changed());
  EXPECT_EQ(find_defects(r.mesh).count(DefectKind::NonFiniteCoordinate), 1);
}

/// The checks every sliver repair must pass: valid, the maps, no face turned over (all these
/// meshes are flat, facing +z), and the area of the input.
void expect_sliver_repair(const Mesh& input, const RepairResult& r, double area) {
  expect_maps_consistent(input, r);
  const MeshInfo info = mesh_info(r.mesh);
  ASSERT_TRUE(info.validation.ok()) << info.validation.defects[0].message;
  for (int f = 0; f < r.mesh.num_faces(); ++f) {
    EXPECT_GT(twice_area_vector(r.mesh, f).z(), 0) << "face " << f << " turned over";
  }
  EXPECT_NEAR(total_face_area(r.mesh), area, 1e-12 * area);
  EXPECT_EQ(r.report.zero_area_faces_left.count, 0);
}

/// A flat n by n grid of unit squares (make_grid), vertex (x, y) at index x + (n + 1) y.
Mesh unit_grid(int n) {
  return make_grid(n, n, n, n);
}
int grid_vertex(int n, int x, int y) {
  return x + (n + 1) * y;
}

TEST(RepairMesh, SliverInsideIsAbsorbedByItsNeighbour) {
  // Vertex (2, 2) moved onto the opposite edge (3, 2) - (3, 3) of its face in square (2, 2):
  // that face becomes a sliver; the face across the edge, in square (3, 2), is split at it.
  Mesh mesh = unit_grid(4);
  const int p = grid_vertex(4, 2, 2);
  mesh.positions.row(p) << 3, 2.5, 0;
  ASSERT_EQ(find_defects(mesh).count(DefectKind::ZeroAreaFace), 1);
  const RepairResult r = repair_mesh(mesh);
  expect_sliver_repair(mesh, r, 16);
  const RepairReport& report = r.report;
  EXPECT_EQ(report.slivers_removed.count, 1);
  EXPECT_EQ(report.slivers_removed.examples, std::vector<int>{2 * (2 + 4 * 2)});
  EXPECT_EQ(report.boundary_slivers_removed, 0);
  EXPECT_EQ(report.faces_split.examples, std::vector<int>{2 * (3 + 4 * 2) + 1});
  EXPECT_EQ(r.mesh.num_faces(), 32);
  EXPECT_EQ(std::count(r.face_split.begin(), r.face_split.end(), 1), 2);
  EXPECT_TRUE(report.changed());
  EXPECT_TRUE(mentions(report.messages,
                       "removed 1 zero-area faces with a vertex on their longest edge (slivers) "
                       "(e.g. face 20): 1 by splitting the face across that edge at the vertex "
                       "(1 faces split (e.g. face 23); the surface is unchanged)"));
  const MeshInfo info = mesh_info(r.mesh);
  EXPECT_EQ(info.euler_characteristic, 1);
  EXPECT_EQ(info.boundary_loops, 1);
}

TEST(RepairMesh, SliverOnTheBoundaryIsRemoved) {
  // Vertex (1, 1) moved onto the boundary edge (0, 0) - (1, 0) of its face in square (0, 0).
  Mesh mesh = unit_grid(4);
  mesh.positions.row(grid_vertex(4, 1, 1)) << 0.5, 0, 0;
  const RepairResult r = repair_mesh(mesh);
  expect_sliver_repair(mesh, r, 16);
  EXPECT_EQ(r.report.slivers_removed.examples, std::vector<int>{0});
  EXPECT_EQ(r.report.boundary_slivers_removed, 1);
  EXPECT_EQ(r.report.faces_split.count, 0);
  EXPECT_EQ(r.mesh.num_faces(), 31);
  EXPECT_TRUE(mentions(r.report.messages, "1 on the boundary (they cover nothing)"));
  const MeshInfo info = mesh_info(r.mesh);
  EXPECT_EQ(info.euler_characteristic, 1);
  EXPECT_EQ(info.boundary_loops, 1);

  // The catalogue's collinear face, alone on its boundary edge: removed, its far vertex dropped.
  const Mesh collinear =
      make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}}, {{0, 1, 2}, {0, 3, 1}});
  const RepairResult c = repair_mesh(collinear);
  expect_sliver_repair(collinear, c, 0.5);
  EXPECT_EQ(c.mesh.num_faces(), 1);
  EXPECT_EQ(c.report.unreferenced_vertices_dropped.examples, std::vector<int>{3});
}

TEST(RepairMesh, TwoAdjacentSliversResolveTogether) {
  // Vertices (2, 2) and (4, 3) both moved onto the edge (3, 2) - (3, 3): two slivers on either
  // side of it, each the other's neighbour across its longest edge.
  Mesh mesh = unit_grid(6);
  mesh.positions.row(grid_vertex(6, 2, 2)) << 3, 2.5, 0;
  mesh.positions.row(grid_vertex(6, 4, 3)) << 3, 2.75, 0;
  ASSERT_EQ(find_defects(mesh).count(DefectKind::ZeroAreaFace), 2);
  const RepairResult r = repair_mesh(mesh);
  expect_sliver_repair(mesh, r, 36);
  EXPECT_EQ(r.report.slivers_removed.count, 2);
  EXPECT_EQ(r.mesh.num_faces(), 72);
}

TEST(RepairMesh, ChainOfSliversAlongALineResolves) {
  // Two fans that meet along y = 0 with interleaved vertices, glued by four slivers (the
  // shared meshes' degtri_sliding.off): lower apex 0, upper apex 7.
  const Mesh mesh = make_mesh(
      {{4, -2, 0}, {6, 0, 0}, {4, 0, 0}, {2, 0, 0}, {1, 0, 0}, {3, 0, 0}, {5, 0, 0}, {3, 2, 0}},
      {{0, 1, 2}, {0, 2, 3}, {3, 2, 4}, {2, 1, 6}, {2, 6, 4}, {4, 6, 5}, {5, 6, 7}, {4, 5, 7}});
  ASSERT_EQ(find_defects(mesh).count(DefectKind::ZeroAreaFace), 4);
  const RepairResult r = repair_mesh(mesh);
  expect_sliver_repair(mesh, r, 8);
  EXPECT_EQ(r.report.slivers_removed.count, 4);
  EXPECT_EQ(r.mesh.num_faces(), 8);
  const MeshInfo info = mesh_info(r.mesh);
  EXPECT_EQ(info.euler_characteristic, 1);
  EXPECT_EQ(info.boundary_loops, 1);
}

TEST(RepairMesh, NeedlesAreLeftAndSaidSo) {
  // Vertex (2, 2) moved to within 1e-14 of vertex (3, 2): two needles, which no split answers
  // (a piece would have zero area again); welding with a tolerance would.
  Mesh mesh = unit_grid(4);
  mesh.positions.row(grid_vertex(4, 2, 2)) << 3 - 1e-14, 2, 0;
  const int before = find_defects(mesh).count(DefectKind::ZeroAreaFace);
  ASSERT_GT(before, 0);
  const RepairResult r = repair_mesh(mesh);
  EXPECT_EQ(r.report.zero_area_faces_left.count, before);
  EXPECT_EQ(find_defects(r.mesh).count(DefectKind::ZeroAreaFace), before);
  EXPECT_TRUE(mentions(r.report.messages, "not repaired: " + std::to_string(before) +
                                              " zero-area faces cannot be removed without "
                                              "changing the surface"));
  EXPECT_TRUE(mentions(r.report.messages, "a needle, not a sliver"));
  RepairOptions weld;
  weld.weld_tolerance = 1e-12;
  const RepairResult welded = repair_mesh(mesh, weld);
  EXPECT_TRUE(find_defects(welded.mesh).counts.empty());
  RepairOptions off;
  off.remove_slivers = false;
  EXPECT_FALSE(repair_mesh(unit_grid(4), off).report.changed());
}

// Vertices on one line and random faces among them and a few others: whatever slivers and
// chains arise, repair ends, the maps hold, and what it says it left is what validation finds.
TEST(RepairMesh, RandomSliverSoupsEnd) {
  std::mt19937 random(11);
  for (int trial = 0; trial < 300; ++trial) {
    const Mesh mesh = random_soup(random, 5 + trial % 8, 2 + trial % 30, true);
    SCOPED_TRACE("trial " + std::to_string(trial));
    const RepairResult r = repair_mesh(mesh);
    expect_maps_consistent(mesh, r);
    EXPECT_EQ(find_defects(r.mesh).count(DefectKind::ZeroAreaFace),
              r.report.zero_area_faces_left.count);
  }
}

TEST(RepairMesh, OptionsSwitchStepsOff) {
  const Mesh bowtie =
      make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0, 2, 0}, {1, 2, 0}}, {{0, 1, 2}, {2, 4, 3}});
  RepairOptions options;
  options.split_non_manifold = false;
  EXPECT_EQ(repair_mesh(bowtie, options).mesh.triangles, bowtie.triangles);
  Mesh flipped = tetrahedron();
  flipped.triangles.row(0) = flipped.triangles.row(0).reverse().eval();
  options.orient = false;
  EXPECT_EQ(repair_mesh(flipped, options).report.faces_flipped.count, 0);
  Mesh twice = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}}, {{0, 1, 2}, {3, 2, 1}});
  options.weld_vertices = false;
  EXPECT_EQ(repair_mesh(twice, options).mesh.num_vertices(), 4);
}

// Random triangle soups on few vertices are as non-manifold as meshes get: after repair no
// defect but non-orientability may be left (zero area does not occur at random positions), the
// maps must hold, and a second repair (without welding) must leave the mesh as it is.
TEST(RepairMesh, RandomSoupsComeOutManifoldAndOriented) {
  std::mt19937 random(5);
  int non_orientable = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Mesh mesh = random_soup(random, 4 + trial % 9, 1 + trial % 40, false);
    SCOPED_TRACE("trial " + std::to_string(trial));
    const RepairResult r = repair_mesh(mesh);
    expect_maps_consistent(mesh, r);
    const ValidationReport after = find_defects(r.mesh);
    for (const auto& [kind, count] : after.counts) {
      EXPECT_EQ(kind, DefectKind::NonOrientable) << defect_name(kind) << ": " << count;
    }
    EXPECT_EQ(after.count(DefectKind::NonOrientable), r.report.non_orientable_components.count);
    non_orientable += r.report.non_orientable_components.count;
    // A repaired mesh is left alone (welding would join the copies of split vertices again).
    RepairOptions no_weld;
    no_weld.weld_vertices = false;
    const RepairResult again = repair_mesh(r.mesh, no_weld);
    EXPECT_FALSE(again.report.changed());
    EXPECT_EQ(again.mesh.triangles, r.mesh.triangles);
  }
  EXPECT_LT(non_orientable, 30);
}

TEST(RepairMesh, RejectsBadIndicesAndOptions) {
  Mesh mesh = tetrahedron();
  mesh.triangles(2, 1) = 9;
  try {
    repair_mesh(mesh);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("repair_mesh: face 2 uses vertex 9, outside [0, 4)"),
              std::string::npos)
        << e.what();
  }
  RepairOptions options;
  for (const double bad : {-1.0, 1e-20, std::nan("")}) {
    options.weld_tolerance = bad;
    EXPECT_THROW(repair_mesh(tetrahedron(), options), InvalidInput) << bad;
  }
  options = {};
  for (const double bad : {-1.0, 1.0, std::nan("")}) {
    options.zero_area_tolerance = bad;
    EXPECT_THROW(repair_mesh(tetrahedron(), options), InvalidInput) << bad;
  }
}

}  // namespace
}  // namespace ricci
