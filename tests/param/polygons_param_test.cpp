// Polygon meshes through the parameterization: the cut never runs along a polygon's diagonal
// (cut_graph with uncut edges, on quad tori, grids, cylinders, quad spheres with cones and a
// non-convex octagon), the pipeline and the piece splitting keep every polygon in one piece with
// one uv per corner, and the polygons written start where their fans are sound, with the flip
// counts of those fans.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <string>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/hyperbolic/hyperbolic_param.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/param/cut/cut_graph.hpp"
#include "ricci/param/layout/polygon_fans.hpp"
#include "ricci/param/output_mesh.hpp"
#include "ricci/param/parameterize.hpp"
#include "support/polygon_meshes.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

using testing::PolygonSoup;

struct PolygonCase {
  std::string name;
  PolygonSoup soup;
  std::vector<int> cones;  // file vertices (cut tests)
};

/// The generated polygon meshes, each with the cones a cut through it joins.
std::vector<PolygonCase> polygon_cases() {
  std::vector<PolygonCase> cases;
  cases.push_back({"quad torus", testing::quad_torus(12, 6), {}});
  cases.push_back({"quad torus with cones", testing::quad_torus(12, 6), {3, 40, 41}});
  cases.push_back({"quad grid", testing::quad_grid(6, 5), {}});
  cases.push_back({"quad grid with interior cones", testing::quad_grid(6, 5), {8, 15, 26}});
  cases.push_back({"quad cylinder", testing::quad_cylinder(10, 4), {}});
  cases.push_back({"quad cylinder with a cone", testing::quad_cylinder(10, 4), {23}});
  PolygonSoup sphere = testing::quad_sphere(3);
  cases.push_back({"quad sphere, two cones", sphere, {0, 40}});
  cases.push_back({"octagon grid with cones", testing::l_octagon_grid(true), {5, 10}});
  // The eight corners of the cube (valence 3).
  PolygonCase cube{"cube of quads, eight corner cones", testing::quad_sphere(2, false), {}};
  for (int v = 0; v < static_cast<int>(cube.soup.positions.size()); ++v) {
    const auto& p = cube.soup.positions[v];
    if (std::abs(p[0]) == 1 && std::abs(p[1]) == 1 && std::abs(p[2]) == 1) cube.cones.push_back(v);
  }
  cases.push_back(cube);
  return cases;
}

/// Whether no cut edge is a diagonal.
void expect_no_diagonal_cut(const Topology& t, const Polygons& polygons, const CutGraph& cut,
                            const std::string& what) {
  const std::vector<char> diagonal = polygon_diagonals(t, polygons);
  for (int e = 0; e < t.num_edges; ++e) {
    EXPECT_FALSE(diagonal[e] && cut.is_cut_edge[e])
        << what << ": diagonal " << t.edge_vertices(e, 0) << "-" << t.edge_vertices(e, 1)
        << " is cut";
  }
}

/// Every polygon has one uv index per corner: its triangles agree on each vertex they share.
void expect_whole_polygons(const Polygons& polygons, const Triangles& triangles,
                           const Triangles& uv_triangles, const std::string& what) {
  std::vector<std::vector<int>> members(polygons.num_polygons());
  for (int t = 0; t < static_cast<int>(triangles.rows()); ++t) {
    members[polygons.triangle_polygon[t]].push_back(t);
  }
  for (int p = 0; p < polygons.num_polygons(); ++p) {
    for (int i = polygons.corner_start[p]; i < polygons.corner_start[p + 1]; ++i) {
      const int c = polygons.corners[i];
      const int v = triangles(c / 3, c % 3), uv = uv_triangles(c / 3, c % 3);
      for (const int t : members[p]) {
        for (int k = 0; k < 3; ++k) {
          if (triangles(t, k) != v) continue;
          EXPECT_EQ(uv_triangles(t, k), uv)
              << what << ": polygon " << p << " has two uv rows at vertex " << v;
        }
      }
    }
  }
}

/// Vertex lists of the polygons (through the triangle corners they name).
std::vector<std::vector<int>> faces_of(const Polygons& polygons, const Triangles& triangles) {
  std::vector<std::vector<int>> faces;
  for (int p = 0; p < polygons.num_polygons(); ++p) {
    std::vector<int>& face = faces.emplace_back();
    for (int i = polygons.corner_start[p]; i < polygons.corner_start[p + 1]; ++i) {
      face.push_back(triangles(polygons.corners[i] / 3, polygons.corners[i] % 3));
    }
  }
  return faces;
}

/// Whether b lists a's corners in the same cyclic order, from any start.
bool same_face(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t s = 0; s < b.size(); ++s) {
    bool same = true;
    for (std::size_t i = 0; i < a.size() && same; ++i) same = a[i] == b[(s + i) % b.size()];
    if (same) return true;
  }
  return false;
}

/// The fan triangles of the written polygons flipped or flat in uv, counted here.
int unsound_fan_triangles(const Polygons& polygons, const Triangles& uv_triangles,
                          const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv) {
  const Triangles fans = polygon_fans(polygons, uv_triangles);
  int count = 0;
  for (Eigen::Index f = 0; f < fans.rows(); ++f) {
    const Eigen::Vector2d a = uv.row(fans(f, 0)), b = uv.row(fans(f, 1)), c = uv.row(fans(f, 2));
    const double twice = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    count += !(twice > 0);
  }
  return count;
}

TEST(PolygonCut, NeverRunsAlongADiagonal) {
  int crossings_unconstrained = 0;
  for (const PolygonCase& c : polygon_cases()) {
    const ReadResult read = testing::read_soup(c.soup, "cut.obj");
    ASSERT_FALSE(read.polygons.empty()) << c.name;
    const Topology t = build_topology(read.mesh.triangles, read.mesh.num_vertices());
    const Eigen::VectorXd lengths = input_edge_lengths(read.mesh, t);
    CutGraphOptions options;
    options.cones = c.cones;  // no vertex is dropped: file indices are mesh indices
    options.uncut_edges = polygon_diagonals(t, read.polygons);
    const CutGraph cut = cut_graph(t, lengths, options);
    expect_no_diagonal_cut(t, read.polygons, cut, c.name);
    int genus = 0;
    for (const Component& component : t.components) genus += component.genus;
    EXPECT_EQ(cut.num_generators, 2 * genus) << c.name;
    // The sliced mesh is one disk (a closed genus-0 surface needs two cones to open), with
    // every cone on its boundary, and every polygon in one piece on it.
    const CutMesh sliced = slice(t, cut);
    ASSERT_EQ(sliced.topology.components.size(), 1u) << c.name;
    const Component& disk = sliced.topology.components[0];
    EXPECT_EQ(disk.euler_characteristic, 1) << c.name;
    EXPECT_EQ(disk.num_boundary_loops, 1) << c.name;
    for (const int cone : c.cones) {
      EXPECT_TRUE(sliced.topology.is_boundary_vertex[cone]) << c.name << ": cone " << cone;
    }
    expect_whole_polygons(read.polygons, read.mesh.triangles, sliced.triangles, c.name);
    options.uncut_edges.clear();
    const CutGraph free_cut = cut_graph(t, lengths, options);
    const std::vector<char> diagonal = polygon_diagonals(t, read.polygons);
    for (int e = 0; e < t.num_edges; ++e)
      crossings_unconstrained += diagonal[e] && free_cut.is_cut_edge[e];
  }
  // Without the constraint the same cuts do run along diagonals: the constraint is what keeps
  // the polygons whole, not luck.
  EXPECT_GT(crossings_unconstrained, 0);
}

TEST(PolygonCut, TwoAdjacentConesAreJoinedAroundTheirPolygon) {
  // Two cones at the ends of one quad edge on a closed genus-0 mesh: the one-edge cut cannot
  // open the surface; it is replaced by the other three edges of one of the edge's quads, not by
  // a diagonal.
  const ReadResult read = testing::read_soup(testing::quad_sphere(3), "adjacent.obj");
  const Topology t = build_topology(read.mesh.triangles, read.mesh.num_vertices());
  const Polygons& polygons = read.polygons;
  const std::vector<char> diagonal = polygon_diagonals(t, polygons);
  int edge = 0;
  while (diagonal[edge]) ++edge;
  CutGraphOptions options;
  options.cones = {t.edge_vertices(edge, 0), t.edge_vertices(edge, 1)};
  options.uncut_edges = diagonal;
  const CutGraph cut = cut_graph(t, input_edge_lengths(read.mesh, t), options);
  EXPECT_EQ(std::count(cut.is_cut_edge.begin(), cut.is_cut_edge.end(), 1), 3);
  EXPECT_FALSE(cut.is_cut_edge[edge]);
  expect_no_diagonal_cut(t, polygons, cut, "adjacent cones");
  const CutMesh sliced = slice(t, cut);
  EXPECT_EQ(sliced.topology.components[0].euler_characteristic, 1);
}

TEST(PolygonCut, RefusesUncutEdgesThatCloseALoopOrHaveTheWrongSize) {
  const Mesh mesh = testing::torus(8, 5);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const Eigen::VectorXd lengths = input_edge_lengths(mesh, t);
  CutGraphOptions options;
  options.uncut_edges.assign(t.num_edges, 1);
  try {
    cut_graph(t, lengths, options);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("join triangles in a loop"), std::string::npos)
        << e.what();
  }
  options.uncut_edges.assign(3, 0);
  EXPECT_THROW(cut_graph(t, lengths, options), InvalidInput);
}

/// parameterize on a polygon mesh: converged, no diagonal cut, every polygon whole, the written
/// polygons the input's faces, and flips counted on their fans as written.
MeshParamResult expect_polygons_kept(const ReadResult& read, ParamOptions options,
                                     const std::string& what) {
  options.polygons = read.polygons;
  MeshParamResult r = parameterize(read.mesh, options);
  EXPECT_TRUE(r.converged) << what << ": " << r.message;
  if (!r.converged) return r;
  EXPECT_EQ(r.mesh.triangles, read.mesh.triangles) << what;
  const Topology t = build_topology(r.mesh.triangles, r.mesh.num_vertices());
  expect_no_diagonal_cut(t, read.polygons, r.cut, what);
  expect_whole_polygons(read.polygons, r.mesh.triangles, r.cut_mesh.triangles, what);
  EXPECT_NO_THROW(check_polygons(r.polygons, r.mesh.triangles, what));
  const auto input = faces_of(read.polygons, read.mesh.triangles);
  const auto written = faces_of(r.polygons, r.mesh.triangles);
  EXPECT_EQ(written.size(), input.size()) << what;
  for (std::size_t p = 0; p < std::min(written.size(), input.size()); ++p) {
    EXPECT_TRUE(same_face(input[p], written[p])) << what << ": polygon " << p;
  }
  const int unsound = unsound_fan_triangles(r.polygons, r.cut_mesh.triangles, r.uv);
  EXPECT_EQ(r.distortion.flipped_faces + r.distortion.degenerate_faces, unsound) << what;
  // What the file holds (textured_mesh) is these polygons.
  const TexturedMesh textured = textured_mesh(r);
  EXPECT_EQ(textured.polygons.corners, r.polygons.corners) << what;
  return r;
}

TEST(PolygonParameterize, KeepsEveryPolygonWholeWithSoundFans) {
  ParamOptions options;
  struct Run {
    std::string name;
    PolygonSoup soup;
  };
  for (const Run& run :
       {Run{"quad torus", testing::quad_torus(16, 8)}, Run{"quad grid", testing::quad_grid(8, 6)},
        Run{"quad cylinder", testing::quad_cylinder(12, 5)},
        Run{"quad sphere (automatic cones)", testing::quad_sphere(4)},
        Run{"octagon grid", testing::l_octagon_grid(true)}}) {
    const ReadResult read = testing::read_soup(run.soup, "param.obj");
    const MeshParamResult r = expect_polygons_kept(read, options, run.name);
    EXPECT_EQ(r.distortion.flipped_faces, 0) << run.name;
    EXPECT_EQ(r.distortion.degenerate_faces, 0) << run.name;
  }
}

TEST(PolygonParameterize, TheOctagonIsWrittenFromItsReflexCorner) {
  // In the plane the layout of a free-boundary disk is the disk itself: the octagon's fan is
  // sound only from its reflex corner (1, 1), vertex 5; from its first corner the fan would
  // hold a flat triangle and a flipped one.
  const ReadResult read = testing::read_soup(testing::l_octagon_grid(false), "octagon.obj");
  ParamOptions options;
  options.polish.enabled = false;
  const MeshParamResult r = expect_polygons_kept(read, options, "planar octagon grid");
  const auto written = faces_of(r.polygons, r.mesh.triangles);
  ASSERT_EQ(written.front().size(), 8u);
  EXPECT_EQ(written.front().front(), 5);
  EXPECT_EQ(r.distortion.flipped_faces, 0);
  EXPECT_EQ(r.distortion.degenerate_faces, 0);
  EXPECT_NEAR(r.distortion.angle_distortion_max, 1.0, 1e-9);
  EXPECT_GT(unsound_fan_triangles(read.polygons, r.cut_mesh.triangles, r.uv), 0);
}

TEST(PolygonParameterize, ACubeOfQuadsWithItsCornersAsCones) {
  const PolygonSoup cube = testing::quad_sphere(3, false);
  const ReadResult read = testing::read_soup(cube, "cube.obj");
  ParamOptions options;
  options.cone_mode = ConeMode::User;
  for (int v = 0; v < read.mesh.num_vertices(); ++v) {
    const Eigen::RowVector3d p = read.mesh.positions.row(v);
    if (p.cwiseAbs().minCoeff() == 1) options.cones.push_back({v, std::numbers::pi / 2});
  }
  ASSERT_EQ(options.cones.size(), 8u);
  const MeshParamResult r = expect_polygons_kept(read, options, "cube with corner cones");
  // The cube is flat away from its corners: the layout is its net, without distortion.
  EXPECT_EQ(r.distortion.flipped_faces, 0);
  EXPECT_NEAR(r.distortion.angle_distortion_max, 1.0, 1e-6);
}

TEST(PolygonParameterize, ComponentsUnfoldedPatchesAndChartsKeepTheirPolygons) {
  // A quad torus, a lone quad (two triangles: unfolded) and the saddle of four quads around a
  // vertex of 787 degrees whose cone the flow refuses: its own shape in patches, or charts.
  const Mesh torus = make_torus(16, 8);
  const Mesh saddle = testing::saddle_fan();
  const Mesh quad =
      testing::make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.3}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}});
  Mesh mesh;
  const std::vector<const Mesh*> parts = {&torus, &quad, &saddle};
  int nv = 0, nf = 0;
  for (const Mesh* m : parts) nv += m->num_vertices(), nf += m->num_faces();
  mesh.positions.resize(nv, 3);
  mesh.triangles.resize(nf, 3);
  nv = nf = 0;
  double x = 0;
  for (const Mesh* m : parts) {
    Eigen::MatrixXd p = m->positions;
    p.col(0).array() += x - p.col(0).minCoeff();
    x = p.col(0).maxCoeff() + 1;
    mesh.positions.middleRows(nv, m->num_vertices()) = p;
    mesh.triangles.middleRows(nf, m->num_faces()) = m->triangles.array() + nv;
    nv += m->num_vertices(), nf += m->num_faces();
  }
  for (const bool charts : {false, true}) {
    // Without the charts route the saddle's own shape is laid out in patches; with it the saddle
    // is cut and flattened as charts (fold_free.charts, the default).
    const std::string what = charts ? "charts route" : "patches";
    ParamOptions options;
    options.fold_free.charts = charts;
    options.cone_mode = ConeMode::User;
    options.cones = {{torus.num_vertices() + quad.num_vertices(), 7.0}};  // the saddle's centre
    options.polygons = testing::pair_triangles(mesh);
    ASSERT_EQ(options.polygons.num_polygons(), nf / 2);
    const MeshParamResult r = parameterize(mesh, options);
    ASSERT_EQ(r.components.size(), 3u) << what;
    EXPECT_EQ(r.components[1].method, ComponentMethod::Unfolded) << what;
    if (charts) {
      EXPECT_EQ(r.components[2].method, ComponentMethod::Charts) << what;
    } else {
      EXPECT_EQ(r.components[2].method, ComponentMethod::Patches) << what;
      EXPECT_GE(r.components[2].charts.size(), 2u) << what;
    }
    ASSERT_EQ(r.mesh.triangles, mesh.triangles) << what;
    expect_whole_polygons(options.polygons, mesh.triangles, r.cut_mesh.triangles, what);
    ASSERT_EQ(r.polygons.num_polygons(), options.polygons.num_polygons()) << what;
    // The charts hold whole polygons.
    std::vector<int> chart_of(nf, -1);
    for (std::size_t c = 0; c < r.packing.charts.size(); ++c) {
      for (const int f : r.packing.charts[c].faces) chart_of[f] = static_cast<int>(c);
    }
    for (int f = 0; f < nf; f += 2) {
      EXPECT_EQ(chart_of[f], chart_of[f + 1]) << what << ": quad " << f / 2;
    }
    EXPECT_EQ(r.distortion.flipped_faces + r.distortion.degenerate_faces,
              unsound_fan_triangles(r.polygons, r.cut_mesh.triangles, r.uv))
        << what;
  }
}

TEST(PolygonParameterize, AnOverlappingLayoutIsSplitBetweenPolygons) {
  // Genus 3 with 8 holes, cut into one disk: the layout overlaps itself and is split into
  // charts; with its triangles paired into quads no chart boundary runs through a quad.
  const Mesh holes = make_surface_with_holes(3, 8);
  const Mesh triangle = testing::make_mesh({{9, 0, 0}, {10, 0, 0}, {9.2, 0.9, 0}}, {{0, 1, 2}});
  Mesh mesh;
  mesh.positions.resize(holes.num_vertices() + 3, 3);
  mesh.positions << holes.positions, triangle.positions;
  mesh.triangles.resize(holes.num_faces() + 1, 3);
  mesh.triangles << holes.triangles, triangle.triangles.array() + holes.num_vertices();
  ParamOptions options;
  options.structure.scheme = Scheme::VertexScaling;
  options.polygons = testing::pair_triangles(mesh);
  const MeshParamResult r = parameterize(mesh, options);
  ASSERT_TRUE(r.converged) << r.message;
  const ComponentParam& comp = r.components[0];
  EXPECT_GT(comp.overlapping_face_pairs, 0);
  EXPECT_GE(comp.charts.size(), 2u);
  expect_whole_polygons(options.polygons, mesh.triangles, r.cut_mesh.triangles, "holes");
  std::vector<int> chart_of(mesh.num_faces(), -1);
  for (std::size_t c = 0; c < r.packing.charts.size(); ++c) {
    for (const int f : r.packing.charts[c].faces) chart_of[f] = static_cast<int>(c);
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int p = options.polygons.triangle_polygon[f];
    const int first = options.polygons.corners[options.polygons.corner_start[p]] / 3;
    EXPECT_EQ(chart_of[f], chart_of[first]) << "face " << f;
  }
}

TEST(PolygonParameterize, HyperbolicCutsKeepPolygonsWhole) {
  // A quad grid with two holes (chi = -1): the uniformization metric in the Poincare disk.
  PolygonSoup soup = testing::quad_grid(7, 7);
  soup.faces.erase(soup.faces.begin() + 5 * 7 + 5);
  soup.faces.erase(soup.faces.begin() + 1 * 7 + 1);
  const ReadResult read = testing::read_soup(soup, "pants.obj");
  HyperbolicParamOptions options;
  options.structure.scheme = Scheme::VertexScaling;
  options.polygons = read.polygons;
  const HyperbolicParamResult r = parameterize_hyperbolic(read.mesh, options);
  ASSERT_TRUE(r.converged) << r.message;
  const Topology t = build_topology(read.mesh.triangles, read.mesh.num_vertices());
  expect_no_diagonal_cut(t, read.polygons, r.cut, "pants");
  expect_whole_polygons(read.polygons, read.mesh.triangles, r.cut_mesh.triangles, "pants");
  EXPECT_EQ(r.polygons.num_polygons(), read.polygons.num_polygons());
  EXPECT_EQ(r.distortion.flipped_faces + r.distortion.degenerate_faces,
            unsound_fan_triangles(r.polygons, r.cut_mesh.triangles, r.uv));
}

TEST(PolygonFans, StartWhereTheFanIsSound) {
  // A dart A (0,0), B (2,1), C (0,2), D (0.5,1), reflex at D, laid out as itself and split along
  // B-D: its fan from A folds (A, C, D); from B (the first sound corner) it does not.
  const Mesh dart =
      testing::make_mesh({{0, 0, 0}, {2, 1, 0}, {0, 2, 0}, {0.5, 1, 0}}, {{0, 1, 3}, {1, 2, 3}});
  Polygons polygons;
  polygons.triangle_polygon = {0, 0};
  polygons.corner_start = {0, 4};
  polygons.corners = {0, 1, 4, 5};  // A, B (triangle 0), C, D (triangle 1)
  ASSERT_NO_THROW(check_polygons(polygons, dart.triangles, "dart"));
  const Eigen::Matrix<double, Eigen::Dynamic, 2> uv = dart.positions.leftCols<2>();
  const Distortion as_given = measure_polygon_distortion(dart, polygons, dart.triangles, uv);
  EXPECT_EQ(as_given.flipped_faces, 1);
  const Polygons started = start_fans_where_valid(polygons, dart, dart.triangles, uv);
  EXPECT_EQ(started.corners, (std::vector<int>{1, 4, 5, 0}));
  const Distortion written = measure_polygon_distortion(dart, started, dart.triangles, uv);
  EXPECT_EQ(written.flipped_faces, 0);
  EXPECT_NEAR(written.angle_distortion_max, 1.0, 1e-12);
  // Without polygons: the triangles themselves.
  const Distortion triangles = measure_polygon_distortion(dart, {}, dart.triangles, uv);
  EXPECT_EQ(triangles.flipped_faces, 0);
  EXPECT_EQ(start_fans_where_valid({}, dart, dart.triangles, uv).num_polygons(), 0);
}

// A U (its notch down to y = 0.5) is seen whole from none of its corners: every corner's fan
// folds in the layout (here the plane itself), so the polygon is written as its own triangles.
TEST(PolygonFans, APolygonNoCornerSeesWholeIsWrittenAsItsTriangles) {
  const Mesh u = testing::make_mesh(
      {{0, 0, 0}, {3, 0, 0}, {3, 2, 0}, {2, 2, 0}, {2, 0.5, 0}, {1, 0.5, 0}, {1, 2, 0}, {0, 2, 0}},
      {{0, 1, 4}, {0, 4, 5}, {1, 2, 4}, {2, 3, 4}, {0, 5, 7}, {5, 6, 7}});
  Polygons polygons;
  polygons.triangle_polygon.assign(6, 0);
  polygons.corner_start = {0, 8};
  polygons.corners = {0, 1, 7, 10, 2, 5, 16, 14};  // vertices 0 .. 7, each at one of its corners
  ASSERT_NO_THROW(check_polygons(polygons, u.triangles, "U"));
  const Eigen::Matrix<double, Eigen::Dynamic, 2> uv = u.positions.leftCols<2>();
  EXPECT_GT(measure_polygon_distortion(u, polygons, u.triangles, uv).flipped_faces, 0);
  const Polygons written = start_fans_where_valid(polygons, u, u.triangles, uv);
  ASSERT_NO_THROW(check_polygons(written, u.triangles, "U written"));
  ASSERT_EQ(written.num_polygons(), 6);
  for (int p = 0; p < 6; ++p) EXPECT_EQ(written.size(p), 3);
  EXPECT_EQ(measure_polygon_distortion(u, written, u.triangles, uv).flipped_faces, 0);
}

}  // namespace
}  // namespace ricci
