#include "ricci/param/cones/refine_curvatures.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "ricci/errors.hpp"
#include "ricci/flow/flow_problem.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/param/cones/cones.hpp"

namespace ricci {
namespace {

/// A generated genus-2 surface, its problem and cone model.
struct GenusTwo {
  Mesh mesh = make_closed_surface(2, 10);
  FlowProblem problem = make_flow_problem(mesh, StructureOptions{});
  ConeModel model = build_cone_model(problem);
};

std::vector<Cone> cones_of(const ConeSelection& s) {
  std::vector<Cone> cones;
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    cones.push_back({s.vertices[i], s.linear_curvature[i]});
  }
  return cones;
}

TEST(LevelCones, HoldEveryConeAtOneLevelAndSumToTwoPiChi) {
  const GenusTwo g;
  const ConeSelection s = select_level_cones(g.model, 4);
  ASSERT_EQ(s.vertices.size(), 4U);
  double sum = 0;
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    sum += s.linear_curvature[i];
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(s.vertices[i], s.vertices[j]);
  }
  EXPECT_NEAR(sum, 2 * std::numbers::pi * -2, 1e-9);
  // The linearised flat metric with these cones has one log scale at all of them.
  const Eigen::VectorXd u = linearised_log_factors(g.model, cones_of(s));
  for (int v : s.vertices) EXPECT_NEAR(u[v], u[s.vertices[0]], 1e-7) << "cone " << v;
  EXPECT_THROW(select_level_cones(g.model, 0), InvalidInput);
}

TEST(CurvatureRefinement, LowersTheFlatMetricsDistortionKeepingTheSum) {
  const GenusTwo g;
  const std::vector<Cone> start = cones_of(select_level_cones(g.model, 4));
  const FlowOptions flow = layout_flow_options();
  const CurvatureRefinement r = refine_cone_curvatures(g.problem, start, flow);
  ASSERT_TRUE(r.converged);
  ASSERT_EQ(r.cones.size(), start.size());
  EXPECT_GE(r.steps, 1);
  EXPECT_LT(r.area_energy, r.area_energy_before);
  double sum = 0;
  for (std::size_t i = 0; i < start.size(); ++i) {
    EXPECT_EQ(r.cones[i].vertex, start[i].vertex);
    sum += r.cones[i].curvature;
  }
  EXPECT_NEAR(sum, 2 * std::numbers::pi * -2, 1e-12);
  // u is the flat metric with the refined cones: a flow started there has nothing left to do.
  FlowOptions warm = flow;
  warm.start_u = r.u;
  const FlowResult again = ricci_flow(g.problem.topology, g.problem.structure.structure,
                                      flat_target(g.problem.topology, r.cones), warm);
  ASSERT_TRUE(again.converged);
  EXPECT_EQ(again.iterations, 0);
}

TEST(CurvatureRefinement, KeepsEveryConeAboveItsLowerBound) {
  const GenusTwo g;
  const std::vector<Cone> start = cones_of(select_level_cones(g.model, 4));
  CurvatureRefinementOptions options;
  for (const Cone& c : start) options.lower_bounds.push_back(c.curvature - 0.05);
  const CurvatureRefinement r =
      refine_cone_curvatures(g.problem, start, layout_flow_options(), options);
  ASSERT_TRUE(r.converged);
  for (std::size_t i = 0; i < start.size(); ++i) {
    EXPECT_GE(r.cones[i].curvature, options.lower_bounds[i] - 1e-9) << "cone " << i;
  }
  EXPECT_LE(r.area_energy, r.area_energy_before);
}

TEST(CurvatureRefinement, NoStepsMeasuresTheConesAsGiven) {
  const GenusTwo g;
  const std::vector<Cone> start = cones_of(select_level_cones(g.model, 4));
  CurvatureRefinementOptions none;
  none.max_steps = 0;
  const CurvatureRefinement r =
      refine_cone_curvatures(g.problem, start, layout_flow_options(), none);
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.steps, 0);
  EXPECT_EQ(r.flows, 1);
  EXPECT_EQ(r.area_energy, r.area_energy_before);
  for (std::size_t i = 0; i < start.size(); ++i)
    EXPECT_EQ(r.cones[i].curvature, start[i].curvature);
}

}  // namespace
}  // namespace ricci
