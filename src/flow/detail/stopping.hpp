#pragma once
/// \file
/// Internal to ricci_flow: the curvature errors, the floating-point floor of a metric, and the
/// rules that stop the flow (converged, at the floor, out of iterations, stalled).

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/ricci_flow.hpp"
#include "ricci/flow/target.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci::flow_detail {

/// max and sum of squares of |K-bar - K| over the vertices with a target, and their count.
struct CurvatureErrors {
  double max = 0;
  double sum_sq = 0;
  int count = 0;
};

/// The errors of curvature k against the target (fixed and unreferenced vertices left out).
CurvatureErrors curvature_errors(const Topology& t, const Target& target, const Eigen::VectorXd& k);

/// The smallest max |K-bar - K| double arithmetic can resolve at the metric u, per vertex: the
/// rounding of its angle sum (about eps per angle, 2 pi in all, times its valence) and of its
/// angles' dependence on the log radii (eps (1 + |u|) each, times dK/du, the edge weights: large
/// next to needles), with a factor 4 of room. Well-shaped meshes sit near 1e-14; 0.1-degree
/// needles bring it to the 1e-12 a parameterization asks for. 0 when edge_weights are not those
/// of t (none assembled yet).
double error_floor(const Topology& t, const Target& target, const Eigen::VectorXd& u,
                   const Eigen::VectorXd& edge_weights);

/// x with 3 significant digits, for messages.
std::string short_number(double x);

/// Why the flow stops.
struct Stop {
  FlowStatus status = FlowStatus::Converged;
  std::string message;
};

/// A flow that cannot improve on an error within the floating-point floor has converged as far
/// as the arithmetic goes: that stop (saying so) when max_error <= floor.
std::optional<Stop> stop_at_floor(double max_error, double floor, double tolerance);

/// The stopping rules after an iteration recorded as history.back() (the flow at `iteration`):
/// converged; stagnating (the error not halved by the last step) within the floor; out of
/// iterations (or within the floor then); Newton with options.stall_iterations = w: the error
/// not half of what it was w iterations before, outside the floor. floor() is evaluated only
/// where a rule needs it.
std::optional<Stop> stopping_rule(const std::vector<IterationRecord>& history, int iteration,
                                  const FlowOptions& options, const std::function<double()>& floor);

}  // namespace ricci::flow_detail
