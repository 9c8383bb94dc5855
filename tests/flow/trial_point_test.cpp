// The trial point of ricci_flow's line search (src/flow/detail/trial_point.hpp): evaluated on
// the current triangulation, or with flips on a flipped copy that leaves the current one alone.

#include "flow/detail/trial_point.hpp"

#include <numbers>

#include <gtest/gtest.h>

#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/background.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/lengths.hpp"

namespace ricci {
namespace {

using flow_detail::Evaluation;
using flow_detail::TrialPoint;

struct Surface {
  Topology topology;
  ConformalStructure structure;
};

Surface vertex_scaling(const Mesh& mesh) {
  Surface s;
  s.topology = build_topology(mesh.triangles, mesh.num_vertices());
  StructureOptions options;
  options.scheme = Scheme::VertexScaling;
  s.structure =
      make_conformal_structure(s.topology, input_edge_lengths(mesh, s.topology), options).structure;
  return s;
}

/// The initial log radii raised by `height` at the grid's first interior vertex: its edges
/// grow by exp(height / 2), which breaks the right triangles whose hypotenuse it shares (a
/// factor above 1 / (sqrt 2 - 1)) and, with flips, makes edges around it fail the Delaunay test.
Eigen::VectorXd bump(const Surface& s, double height) {
  Eigen::VectorXd u = s.structure.initial_u;
  int v = 0;
  while (s.topology.is_boundary_vertex[v]) ++v;
  u[v] += height;
  return u;
}

TEST(EvaluateMetric, GivesTheLengthsAnglesAndCurvatureOfTheMetric) {
  const Surface s = vertex_scaling(make_disk(3));
  Eigen::VectorXd l, k;
  CornerAngles a;
  ASSERT_EQ(flow_detail::evaluate_metric(s.topology, s.structure, s.structure.initial_u, l, a, k),
            Evaluation::Valid);
  Eigen::VectorXd l2;
  ASSERT_TRUE(edge_lengths(s.topology, s.structure, s.structure.initial_u, l2).ok());
  EXPECT_EQ(l, l2);
  EXPECT_EQ(k, vertex_curvature(s.topology, a));
  Eigen::VectorXd k2;
  CornerAngles a2;
  EXPECT_EQ(flow_detail::evaluate_angles(s.topology, s.structure.geometry, l, a2, k2),
            Evaluation::Valid);
  EXPECT_EQ(k2, k);
}

TEST(TrialPoint, WithoutFlipsABrokenTriangleIsATriangleInequality) {
  const Surface s = vertex_scaling(make_grid(4, 4));
  const IntrinsicTriangulation current(s.topology, s.structure);
  TrialPoint trial;
  trial.u = bump(s, 3.0);
  EXPECT_EQ(trial.evaluate(current, current.topology(), current.structure(), false, {}),
            Evaluation::TriangleInequality);
  EXPECT_FALSE(trial.flipped);
  trial.u = s.structure.initial_u;
  EXPECT_EQ(trial.evaluate(current, current.topology(), current.structure(), false, {}),
            Evaluation::Valid);
}

TEST(TrialPoint, WithFlipsFlipsACopyToTheDelaunayTriangulationAtItsLogRadii) {
  const Surface s = vertex_scaling(make_grid(4, 4));
  const IntrinsicTriangulation current(s.topology, s.structure);
  TrialPoint trial;
  // Delaunay already at the initial metric: evaluated on the current triangulation.
  trial.u = s.structure.initial_u;
  ASSERT_EQ(trial.evaluate(current, current.topology(), current.structure(), true, {}),
            Evaluation::Valid);
  EXPECT_FALSE(trial.flipped);
  EXPECT_EQ(trial.flips, 0);

  trial.u = bump(s, 3.0);
  ASSERT_EQ(trial.evaluate(current, current.topology(), current.structure(), true, {}),
            Evaluation::Valid);
  EXPECT_TRUE(trial.flipped);
  EXPECT_GT(trial.flips, 0);
  EXPECT_FALSE(current.owns_topology());  // the current triangulation is untouched
  const Topology& flipped = trial.triangulation.topology();
  EXPECT_EQ(count_non_delaunay_edges(flipped, trial.lengths), 0);
  EXPECT_EQ(trial.curvature, vertex_curvature(flipped, trial.angles));
  // Gauss-Bonnet on the flipped triangulation of the disk: sum K = 2 pi.
  EXPECT_NEAR(trial.curvature.sum(), 2 * std::numbers::pi, 1e-9);
}

}  // namespace
}  // namespace ricci
