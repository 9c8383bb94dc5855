// The charts route (ComponentMethod::Charts, src/param/atlas/charts.cpp): where the exact map fails
// its checks, the component is cut into charts flattened with free boundary. Pinned down here on
// generated cases the exact map cannot serve: a high-genus surface with one boundary loop (its
// flat metric with free boundary spans more scale than double precision lays out) and a CAD
// cylinder with 0.1-degree needles (faces drawn flipped that untangling cannot reach). Every
// figure is measured from the uv itself, not taken from the result's own counters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/hard_cases.hpp"
#include "ricci/param/atlas/chart_packing.hpp"
#include "ricci/param/parameterize.hpp"
#include "support/uv_checks.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

using testing::count_flipped;

/// Over the mesh edges cut open (two faces, two different uv edges): the largest relative
/// difference between the two sides.
struct Seams {
  int cut_edges = 0;
  double mismatch = 0;
};

Seams measure_seams(const Mesh& mesh, const Triangles& t, const UV& uv) {
  struct Side {
    int a, b;
    double length;
  };
  std::map<std::pair<int, int>, std::vector<Side>> sides;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int u = mesh.triangles(f, k), v = mesh.triangles(f, (k + 1) % 3);
      const int a = t(f, k), b = t(f, (k + 1) % 3);
      sides[{std::min(u, v), std::max(u, v)}].push_back(
          {std::min(a, b), std::max(a, b), (uv.row(a) - uv.row(b)).norm()});
    }
  }
  Seams out;
  for (const auto& [edge, s] : sides) {
    if (s.size() != 2 || (s[0].a == s[1].a && s[0].b == s[1].b)) continue;
    ++out.cut_edges;
    out.mismatch = std::max(
        out.mismatch, std::abs(s[0].length - s[1].length) / std::max(s[0].length, s[1].length));
  }
  return out;
}

void expect_fold_free_charts(const Mesh& mesh, const MeshParamResult& r, const std::string& what) {
  ASSERT_TRUE(r.converged) << what << ": " << r.message;
  ASSERT_EQ(r.routes.size(), 1u) << what;
  EXPECT_EQ(r.routes[0].method, ComponentMethod::Charts) << what;
  EXPECT_FALSE(r.routes[0].why.empty()) << what;
  EXPECT_GE(r.routes[0].charts, 2) << what;
  EXPECT_EQ(r.routes[0].flipped, 0) << what;
  // The output's faces are the input's.
  ASSERT_EQ(r.mesh.num_faces(), mesh.num_faces()) << what;
  EXPECT_EQ(r.mesh.triangles, mesh.triangles) << what;
  EXPECT_EQ(count_flipped(r.uv, r.cut_mesh.triangles), 0) << what;
  EXPECT_EQ(r.distortion.flipped_faces, 0) << what;
  EXPECT_EQ(find_uv_overlaps(r.uv, r.cut_mesh.triangles).count, 0) << what;
  EXPECT_GE(r.uv.minCoeff(), 0) << what;
  EXPECT_LE(r.uv.maxCoeff(), 1) << what;
  const Seams seams = measure_seams(r.mesh, r.cut_mesh.triangles, r.uv);
  EXPECT_GT(seams.cut_edges, 0) << what;
  EXPECT_LE(seams.mismatch, 1e-9) << what;
  EXPECT_NEAR(r.routes[0].seam_length, r.seam_length, 1e-9 * r.seam_length) << what;
}

// Genus 20 with one hole: by default no cone (a flat metric with free boundary exists), but its
// scale spans more than double precision lays out (layout length error about 1e19).
TEST(Charts, AHighGenusSurfaceWithOneHoleIsLaidOutAsCharts) {
  const Mesh surface = pull_vertices_to_neighbours(make_surface_with_holes(20, 1, 24), 0.9, 1, 2);
  const MeshParamResult r = parameterize(surface, ParamOptions{});
  expect_fold_free_charts(surface, r, "genus 20, one hole");
  EXPECT_NE(r.routes[0].why.find("does not close up"), std::string::npos) << r.routes[0].why;
  // The charts are the disk's: cut once, free boundary, no face needed its own shape.
  EXPECT_LE(r.routes[0].charts, 40);

  // Without the charts route the exact map comes back as it is, and says it failed.
  ParamOptions exact;
  exact.fold_free.charts = false;
  const MeshParamResult failed = parameterize(surface, exact);
  EXPECT_GT(failed.layout.max_length_relative_error, 1e-6);
  ASSERT_EQ(failed.routes.size(), 1u);
  EXPECT_EQ(failed.routes[0].method, ComponentMethod::Flow);
}

// 0.1-degree needles on a CAD cylinder: the exact map with its automatic cones draws 246 faces
// flipped that untangling cannot free (measured); charts do without a fold.
TEST(Charts, NeedlesTheExactMapFoldsAreLaidOutWithoutAFold) {
  const Mesh needles = pull_vertices_to_neighbours(make_cad_cylinder(360), 0.998, 1, 2);
  const MeshParamResult r = parameterize(needles, ParamOptions{});
  expect_fold_free_charts(needles, r, "needle cylinder");
  EXPECT_GT(r.routes[0].flipped_before, 0);
  EXPECT_NE(r.routes[0].why.find("flipped"), std::string::npos) << r.routes[0].why;
}

// A surface the exact map serves takes no other route, and its result is that of the exact map.
TEST(Charts, AMeshTheExactMapServesKeepsIt) {
  const Mesh torus = make_torus(32, 12);
  const MeshParamResult r = parameterize(torus, ParamOptions{});
  ASSERT_TRUE(r.converged) << r.message;
  ASSERT_EQ(r.routes.size(), 1u);
  EXPECT_EQ(r.routes[0].method, ComponentMethod::Flow);
  EXPECT_TRUE(r.routes[0].why.empty());
  EXPECT_EQ(r.routes[0].charts, 1);
  EXPECT_TRUE(r.components.empty());
}

}  // namespace
}  // namespace ricci
