// Seams and cones of texture layouts: hand-made layouts with known answers, and a
// parameterization whose cones the pipeline reports independently.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/param/parameterize.hpp"
#include "ricci/render/uv_chart.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

using testing::TexturedMesh;
using testing::unrolled_pyramid;

TEST(UvChart, GridWithContinuousLayoutHasOnlyItsBoundaryAsSeam) {
  const auto g = testing::grid_with_uv(5);
  const UvChart chart = analyse_uv_chart(g.mesh, g.uv_triangles, g.uv);
  EXPECT_EQ(chart.seam_edges, 20);  // 4 sides of 5 edges
  EXPECT_EQ(chart.seam_halfedges.size(), 20u);
  EXPECT_TRUE(chart.cones.empty());
}

TEST(UvChart, DiagonalCutOfASquare) {
  // Two triangles whose texture coordinates are separate copies: the diagonal is a seam even
  // though the copies have the same values in one case and different values in the other.
  Mesh mesh;
  mesh.positions.resize(4, 3);
  mesh.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  mesh.triangles.resize(2, 3);
  mesh.triangles << 0, 1, 2, 0, 2, 3;
  Triangles uv_triangles(2, 3);
  uv_triangles << 0, 1, 2, 3, 4, 5;
  UV uv(6, 2);
  uv << 0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1;  // copies at equal values: one chart
  EXPECT_EQ(analyse_uv_chart(mesh, uv_triangles, uv).seam_edges, 4);
  uv.row(4) << 2, 1;  // the second triangle's copy of vertex 2 moved: the diagonal is a seam
  const UvChart chart = analyse_uv_chart(mesh, uv_triangles, uv);
  EXPECT_EQ(chart.seam_edges, 5);
  EXPECT_EQ(chart.seam_halfedges.size(), 6u);  // the diagonal once per side
  EXPECT_TRUE(chart.cones.empty());            // every vertex is on the boundary
}

TEST(UvChart, ApexOfAnUnrolledPyramidIsACone) {
  const TexturedMesh flat =
      unrolled_pyramid(std::numbers::pi / 2);  // angles add up to 2 pi: not a cone
  EXPECT_TRUE(analyse_uv_chart(flat.mesh, flat.uv_triangles, flat.uv).cones.empty());
  const TexturedMesh p = unrolled_pyramid(std::numbers::pi / 3);
  const UvChart chart = analyse_uv_chart(p.mesh, p.uv_triangles, p.uv);
  ASSERT_EQ(chart.cones.size(), 1u);
  EXPECT_EQ(chart.cones[0], 0);
  EXPECT_NEAR(chart.cone_angles[0], 4 * std::numbers::pi / 3, 1e-14);
  // Seams: the cut edge (two halfedges) and the four base edges.
  EXPECT_EQ(chart.seam_edges, 5);
  EXPECT_EQ(chart.seam_halfedges.size(), 6u);
}

TEST(UvChart, FindsTheConesOfAParameterization) {
  ParamOptions options;
  options.cone_mode = ConeMode::Auto;
  options.auto_cones.count = 8;
  const MeshParamResult result = parameterize(make_icosphere(2), options);
  ASSERT_TRUE(result.converged) << result.message;
  const UvChart chart = analyse_uv_chart(result.mesh, result.cut_mesh.triangles, result.uv);
  std::set<int> expected;
  for (const Cone& c : result.cones) {
    if (std::abs(c.curvature) > 1e-6) expected.insert(c.vertex);
  }
  EXPECT_EQ(std::set<int>(chart.cones.begin(), chart.cones.end()), expected);
  for (std::size_t i = 0; i < chart.cones.size(); ++i) {
    for (const Cone& c : result.cones) {
      // The layout reproduces the flat metric to ~1e-9: the angle sum is 2 pi - K to that order.
      if (c.vertex == chart.cones[i]) {
        EXPECT_NEAR(chart.cone_angles[i], 2 * std::numbers::pi - c.curvature, 1e-6);
      }
    }
  }
}

TEST(UvChart, RejectsMismatchedArrays) {
  const auto g = testing::grid_with_uv(2);
  EXPECT_THROW(analyse_uv_chart(g.mesh, g.uv_triangles.topRows(3), g.uv), InvalidInput);
  Triangles bad = g.uv_triangles;
  bad(1, 2) = static_cast<int>(g.uv.rows());
  EXPECT_THROW(analyse_uv_chart(g.mesh, bad, g.uv), InvalidInput);
}

}  // namespace
}  // namespace ricci
