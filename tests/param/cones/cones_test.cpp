#include "ricci/param/cones/cones.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/flow/flow_problem.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/mesh/generate.hpp"

namespace ricci {
namespace {

TEST(ConeSelection, CountModeGivesThatManyDistinctCones) {
  const Mesh sphere = make_icosphere(3);
  ConeSelectionOptions options;
  options.count = 6;
  const ConeSelection s = select_cones(sphere, options);
  ASSERT_EQ(s.vertices.size(), 6u);
  std::vector<int> sorted = s.vertices;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::unique(sorted.begin(), sorted.end()), sorted.end());
  // The linearised cones carry the sphere's whole curvature 4 pi.
  double total = 0;
  for (double k : s.linear_curvature) total += k;
  EXPECT_NEAR(total, 4 * std::numbers::pi, 1e-6);
}

TEST(ConeSelection, NoCapOnTheNumberOfCones) {
  // A count places that many cones (64 was the cap before), and the automatic count goes past
  // 64 while its bound asks for it.
  const Mesh sphere = make_icosphere(4);
  ConeSelectionOptions count;
  count.count = 70;
  EXPECT_EQ(select_cones(sphere, count).vertices.size(), 70u);
  ConeSelectionOptions automatic;
  automatic.max_log_scale = 0.02;
  const ConeSelection s = select_cones(sphere, automatic);
  EXPECT_GT(s.vertices.size(), 64u);
  // Asked for, a cap holds.
  automatic.max_cones = 10;
  EXPECT_LE(select_cones(sphere, automatic).vertices.size(), 10u);
}

TEST(ConeSelection, MoreConesLowerTheAreaScale) {
  // An elongated, bumpy closed surface distorts area strongly with few cones.
  const Mesh surface = make_closed_surface(0, 16);
  ConeSelectionOptions options;
  options.max_log_scale = 1.2;
  const ConeSelection s = select_cones(surface, options);
  ASSERT_GE(s.max_log_scale.size(), 2u);
  EXPECT_LE(s.max_log_scale.back(), 1.2);
  EXPECT_LT(s.max_log_scale.back(), s.max_log_scale.front());
  EXPECT_EQ(s.max_log_scale.size(), s.vertices.size());  // one solve per cone, the first seeded
}

TEST(ConeSelection, FlatDiskNeedsNoCone) {
  ConeSelectionOptions options;
  options.structure.scheme = Scheme::VertexScaling;  // reproduces the flat input exactly
  const ConeSelection s = select_cones(make_disk(6), options);
  EXPECT_TRUE(s.vertices.empty());
  EXPECT_LT(s.max_log_scale.front(), 1e-9);
}

TEST(ConeSelection, RejectsBadOptionsAndSeveralComponents) {
  ConeSelectionOptions options;
  options.max_log_scale = 0;
  EXPECT_THROW(select_cones(make_icosphere(1), options), InvalidInput);
  Mesh two = make_tetrahedron();
  Mesh both;
  both.positions.resize(8, 3);
  both.positions << two.positions, (two.positions.array() + 5.0).matrix();
  both.triangles.resize(8, 3);
  both.triangles << two.triangles, (two.triangles.array() + 4).matrix();
  EXPECT_THROW(select_cones(both, {}), InvalidInput);
}

TEST(ConeSelection, LinearisedLogFactorsAreTheFlowsFirstNewtonStep) {
  // The flow started there is where the flow from the input metric is after one full step.
  const Mesh mesh = make_icosphere(3);
  ConeSelectionOptions options;
  options.count = 6;
  const FlowProblem problem = make_flow_problem(mesh, options.structure);
  const ConeModel model = build_cone_model(problem);
  const ConeSelection selection = select_cones(model, options);
  std::vector<Cone> cones;
  for (std::size_t i = 0; i < selection.vertices.size(); ++i) {
    cones.push_back({selection.vertices[i], selection.linear_curvature[i]});
  }
  const Target target = flat_target(problem.topology, cones);
  FlowOptions flow = layout_flow_options();
  const FlowResult cold = ricci_flow(problem.topology, problem.structure.structure, target, flow);
  ASSERT_TRUE(cold.converged) << cold.message;
  ASSERT_GE(cold.history.size(), 2U);
  ASSERT_EQ(cold.history[1].step_length, 1.0);
  flow.start_u = problem.structure.structure.initial_u + linearised_log_factors(model, cones);
  const FlowResult warm = ricci_flow(problem.topology, problem.structure.structure, target, flow);
  ASSERT_TRUE(warm.converged) << warm.message;
  EXPECT_NEAR(warm.history.front().max_error, cold.history[1].max_error,
              1e-9 * (1 + cold.history[1].max_error));
  EXPECT_EQ(warm.iterations, cold.iterations - 1);
  EXPECT_THROW(linearised_log_factors(model, {{mesh.num_vertices(), 1.0}}), InvalidInput);
}

TEST(QuantizeCones, RoundsToQuarterTurnsKeepingTheSum) {
  const std::vector<Cone> cones = {{1, 1.4}, {2, 1.7}, {3, 3.0}, {4, 6.5}, {5, 0.3}};
  double raw = 0;
  for (const Cone& c : cones) raw += c.curvature;
  ASSERT_NEAR(raw, 12.9, 1e-12);  // about 4 pi = 12.566: the rounding must move it there
  const std::vector<Cone> q = quantize_cones(cones, 4 * std::numbers::pi);
  double total = 0;
  for (const Cone& c : q) {
    const double units = c.curvature / (std::numbers::pi / 2);
    EXPECT_NEAR(units, std::round(units), 1e-12);
    EXPECT_LT(c.curvature, 2 * std::numbers::pi);
    EXPECT_NE(c.curvature, 0.0);
    total += c.curvature;
  }
  EXPECT_NEAR(total, 4 * std::numbers::pi, 1e-12);
  // A cone whose curvature rounds to nothing is dropped.
  const std::vector<Cone> small = quantize_cones({{1, std::numbers::pi + 0.1},
                                                  {2, std::numbers::pi - 0.1},
                                                  {3, std::numbers::pi},
                                                  {4, std::numbers::pi},
                                                  {5, 0.2}},
                                                 4 * std::numbers::pi);
  ASSERT_EQ(small.size(), 4u);
  for (const Cone& c : small) EXPECT_DOUBLE_EQ(c.curvature, std::numbers::pi);
}

}  // namespace
}  // namespace ricci
