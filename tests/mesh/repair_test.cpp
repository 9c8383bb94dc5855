#include "ricci/mesh/repair.hpp"

#include <gtest/gtest.h>

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

/// The maps are what the header promises: every output vertex sits where its input vertex does,
/// and every output face is its input face (corners 1 and 2 exchanged when flipped) up to the
/// vertices that were welded.
void expect_maps_consistent(const Mesh& input, const RepairResult& r) {
  ASSERT_EQ(static_cast<int>(r.vertex_map.size()), r.mesh.num_vertices());
  ASSERT_EQ(static_cast<int>(r.face_map.size()), r.mesh.num_faces());
  ASSERT_EQ(static_cast<int>(r.face_flipped.size()), r.mesh.num_faces());
  for (int v = 0; v < r.mesh.num_vertices(); ++v) {
    EXPECT_EQ(r.mesh.positions.row(v), input.positions.row(r.vertex_map[v])) << "vertex " << v;
  }
  for (int f = 0; f < r.mesh.num_faces(); ++f) {
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

TEST(RepairMesh, ZeroAreaFacesAndNonFiniteCoordinatesAreLeft) {
  Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}}, {{0, 1, 2}, {0, 3, 1}});
  mesh.triangles.row(1) << 1, 3, 0;  // collinear, and oriented like face 0
  RepairResult r = repair_mesh(mesh);
  EXPECT_EQ(r.mesh.num_faces(), 2);
  EXPECT_EQ(find_defects(r.mesh).count(DefectKind::ZeroAreaFace), 1);

  mesh = tetrahedron();
  mesh.positions(2, 1) = std::nan("");
  r = repair_mesh(mesh);
  EXPECT_FALSE(r.report.changed());
  EXPECT_EQ(find_defects(r.mesh).count(DefectKind::NonFiniteCoordinate), 1);
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
  std::uniform_real_distribution<double> coordinate(-1, 1);
  int non_orientable = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int nv = 4 + trial % 9, nf = 1 + trial % 40;
    std::uniform_int_distribution<int> vertex(0, nv - 1);
    Mesh mesh;
    mesh.positions.resize(nv, 3);
    for (int v = 0; v < nv; ++v) {
      mesh.positions.row(v) << coordinate(random), coordinate(random), coordinate(random);
    }
    mesh.triangles.resize(nf, 3);
    for (int f = 0; f < nf; ++f) {
      mesh.triangles.row(f) << vertex(random), vertex(random), vertex(random);
    }
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
}

}  // namespace
}  // namespace ricci
