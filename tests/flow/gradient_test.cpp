#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "ricci/flow/ricci_flow.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/lengths.hpp"

namespace ricci {
namespace {

// The tutorial's fig. 7: the curvature error of the gradient flow decays exponentially. Near the
// solution the explicit step multiplies the error by I - dt L, so the asymptotic rate per
// iteration is max over the non-zero eigenvalues lambda of L of |1 - dt lambda|.
TEST(GradientFlow, ErrorDecaysExponentiallyAtThePredictedRate) {
  // The tutorial's setting: Thurston's packing (no flips, so the rate is that of one Hessian).
  const Mesh mesh = make_icosphere(1);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  StructureOptions thurston;
  thurston.scheme = Scheme::Thurston;
  const ConformalStructure s =
      make_conformal_structure(t, input_edge_lengths(mesh, t), thurston).structure;
  const Target target = flat_target(
      t,
      {{0, std::numbers::pi}, {3, std::numbers::pi}, {5, std::numbers::pi}, {9, std::numbers::pi}});
  FlowOptions options;
  options.solver = FlowSolver::Gradient;
  const FlowResult r = ricci_flow(t, s, target, options);
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_LE(r.max_error, 1e-10);
  EXPECT_LT(r.gauss_bonnet_relative_error, 1e-12);
  EXPECT_GT(r.iterations, 20);  // it is the slow method

  // Least-squares fit of log(error) = a + b k over the tail where the error is between 1e-4
  // and 1e-9 (the asymptotic regime, above the rounding floor).
  std::vector<double> ks, logs;
  for (const auto& record : r.history) {
    if (record.max_error < 1e-4 && record.max_error > 1e-9) {
      ks.push_back(record.iteration);
      logs.push_back(std::log(record.max_error));
    }
  }
  ASSERT_GT(ks.size(), 10u);
  const Eigen::Map<Eigen::VectorXd> x(ks.data(), ks.size()), y(logs.data(), logs.size());
  Eigen::MatrixXd design(ks.size(), 2);
  design.col(0).setOnes();
  design.col(1) = x;
  const Eigen::Vector2d fit = design.colPivHouseholderQr().solve(y);
  const Eigen::VectorXd residual = y - design * fit;
  const double r2 = 1 - residual.squaredNorm() / (y.array() - y.mean()).matrix().squaredNorm();
  EXPECT_GT(r2, 0.999) << "log error is not linear in the iteration count";
  const double fitted_rate = std::exp(fit[1]);

  // Predicted rate from the Hessian at the solution and the step the flow chose.
  Eigen::VectorXd l, hw, ew;
  CornerAngles a;
  edge_lengths(t, s, r.u, l);
  corner_angles(t, l, a);
  halfedge_weights(t, s, r.u, l, a, hw);
  edge_weights(t, hw, ew);
  const Eigen::MatrixXd L(curvature_hessian(t, ew));
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(L).eigenvalues();
  const double dt = r.history[1].step_length;
  double predicted = 0;
  for (int i = 1; i < eig.size(); ++i) predicted = std::max(predicted, std::abs(1 - dt * eig[i]));
  EXPECT_NEAR(fitted_rate, predicted, 0.01 * (1 - predicted))
      << "fitted " << fitted_rate << " predicted " << predicted;
}

TEST(GradientFlow, ReachesTheSameMetricAsNewton) {
  const Mesh mesh = make_torus(12, 6);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const ConformalStructure s = make_conformal_structure(t, input_edge_lengths(mesh, t)).structure;
  const Target target = flat_target(t, {});
  FlowOptions options;
  const FlowResult newton = ricci_flow(t, s, target, options);
  options.solver = FlowSolver::Gradient;
  const FlowResult gradient = ricci_flow(t, s, target, options);
  ASSERT_TRUE(newton.converged && gradient.converged);
  EXPECT_GT(gradient.iterations, 10 * newton.iterations);
  // Both hold the mean of u: the metrics agree, not only up to scale.
  EXPECT_LT((newton.u - gradient.u).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(GradientFlow, UserStepLengthIsUsedAndNormalisationHoldsTheMean) {
  const Mesh mesh = make_icosphere(1);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  const ConformalStructure s = make_conformal_structure(t, input_edge_lengths(mesh, t)).structure;
  FlowOptions options;
  options.solver = FlowSolver::Gradient;
  options.gradient_step = 0.05;
  options.max_iterations = 50;
  const FlowResult r = ricci_flow(t, s, uniform_target(t), options);
  EXPECT_EQ(r.history[1].step_length, 0.05);
  // The tutorial normalises prod gamma = const: the mean of u stays where it started.
  EXPECT_NEAR(r.u.mean(), s.initial_u.mean(), 1e-13);
}

}  // namespace
}  // namespace ricci
