// The stopping rules of ricci_flow (src/flow/detail/stopping.hpp): the curvature errors, the
// floating-point floor and which rule stops the flow, with its message.

#include "flow/detail/stopping.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "ricci/mesh/generate.hpp"

namespace ricci {
namespace {

using flow_detail::Stop;
using flow_detail::stopping_rule;

std::vector<IterationRecord> history_of(const std::vector<double>& errors) {
  std::vector<IterationRecord> h;
  for (std::size_t k = 0; k < errors.size(); ++k) {
    IterationRecord r;
    r.iteration = static_cast<int>(k);
    r.max_error = errors[k];
    h.push_back(r);
  }
  return h;
}

TEST(CurvatureErrors, SkipFixedVertices) {
  const Mesh mesh = make_tetrahedron();
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  Target target;
  target.curvature = Eigen::VectorXd::Constant(4, 1.0);
  target.fixed = {0, 0, 0, 1};
  const Eigen::VectorXd k = (Eigen::VectorXd(4) << 1.5, 0.0, 1.0, 100.0).finished();
  const flow_detail::CurvatureErrors e = flow_detail::curvature_errors(t, target, k);
  EXPECT_EQ(e.max, 1.0);
  EXPECT_EQ(e.sum_sq, 1.25);
  EXPECT_EQ(e.count, 3);
}

TEST(ErrorFloor, FromValenceAndWeights) {
  const Mesh mesh = make_tetrahedron();
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  Target target;
  target.curvature = Eigen::VectorXd::Zero(4);
  target.fixed.assign(4, 0);
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(4);
  // No weights of this triangulation yet: no floor.
  EXPECT_EQ(flow_detail::error_floor(t, target, u, Eigen::VectorXd()), 0.0);
  // Valence 3, three edges of weight 1 at each vertex: 4 eps (2 pi 3 + 2 * 3).
  const double eps = std::numeric_limits<double>::epsilon();
  EXPECT_DOUBLE_EQ(flow_detail::error_floor(t, target, u, Eigen::VectorXd::Ones(6)),
                   4 * eps * (6 * std::numbers::pi + 6));
}

TEST(StoppingRule, ConvergedAtTheTolerance) {
  FlowOptions o;
  o.tolerance = 1e-10;
  o.max_iterations = 200;
  const auto stop = stopping_rule(history_of({1.0, 5e-11}), 1, o, [] { return 0.0; });
  ASSERT_TRUE(stop);
  EXPECT_EQ(stop->status, FlowStatus::Converged);
  EXPECT_EQ(stop->message, "reached max |K-bar - K| = 5e-11 <= 1e-10");
}

TEST(StoppingRule, StagnatingWithinTheFloorHasConverged) {
  FlowOptions o;
  o.tolerance = 1e-12;
  o.max_iterations = 200;
  int floors = 0;
  auto floor = [&] {
    ++floors;
    return 1e-11;
  };
  // Halved: not stagnating, and iterations remain: the floor is not asked.
  EXPECT_FALSE(stopping_rule(history_of({1e-10, 4e-12}), 1, o, floor));
  EXPECT_EQ(floors, 0);
  const auto stop = stopping_rule(history_of({4e-12, 3e-12}), 2, o, floor);
  ASSERT_TRUE(stop);
  EXPECT_EQ(stop->status, FlowStatus::Converged);
  EXPECT_EQ(stop->message,
            "reached max |K-bar - K| = 3e-12, the floating-point floor of this metric (about "
            "1e-11), above the tolerance 1e-12");
}

TEST(StoppingRule, OutOfIterations) {
  FlowOptions o;
  o.max_iterations = 3;
  const auto stop = stopping_rule(history_of({1, 0.1, 0.01, 0.001}), 3, o, [] { return 0.0; });
  ASSERT_TRUE(stop);
  EXPECT_EQ(stop->status, FlowStatus::MaxIterations);
  EXPECT_EQ(stop->message, "stopped after 3 iterations at max |K-bar - K| = 0.001");
  EXPECT_FALSE(stopping_rule(history_of({1, 0.1, 0.01}), 2, o, [] { return 0.0; }));
}

TEST(StoppingRule, StalledNewton) {
  FlowOptions o;
  o.max_iterations = 200;
  o.stall_iterations = 2;
  const auto stop = stopping_rule(history_of({3.0, 2.9, 2.0}), 2, o, [] { return 0.0; });
  ASSERT_TRUE(stop);
  EXPECT_EQ(stop->status, FlowStatus::MaxIterations);
  EXPECT_EQ(stop->message,
            "stalled: max |K-bar - K| = 2 after 2 iterations, not half of its 3 2 iterations "
            "before");
  EXPECT_FALSE(stopping_rule(history_of({3.0, 2.9, 1.4}), 2, o, [] { return 0.0; }));
  o.solver = FlowSolver::Gradient;  // the gradient flow does not stall
  EXPECT_FALSE(stopping_rule(history_of({3.0, 2.9, 2.0}), 2, o, [] { return 0.0; }));
}

TEST(StopAtFloor, OnlyWithinTheFloor) {
  EXPECT_FALSE(flow_detail::stop_at_floor(2e-11, 1e-11, 1e-12));
  EXPECT_TRUE(flow_detail::stop_at_floor(1e-11, 1e-11, 1e-12));
  EXPECT_FALSE(flow_detail::stop_at_floor(std::nan(""), 1e-11, 1e-12));
}

}  // namespace
}  // namespace ricci
