#include "flow/detail/stopping.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace ricci::flow_detail {
namespace {

/// The room the error floor leaves over its rounding estimate.
constexpr double floor_room = 4;
/// A step that does not halve the error stagnates (Newton's quadratic convergence halves it
/// many times over).
constexpr double stagnation_ratio = 0.5;

}  // namespace

CurvatureErrors curvature_errors(const Topology& t, const Target& target,
                                 const Eigen::VectorXd& k) {
  CurvatureErrors e;
  for (int v = 0; v < t.num_vertices; ++v) {
    if (target.fixed[v] || t.vertex_component[v] < 0) continue;
    const double d = target.curvature[v] - k[v];
    e.max = std::max(e.max, std::abs(d));
    e.sum_sq += d * d;
    ++e.count;
  }
  return e;
}

double error_floor(const Topology& t, const Target& target, const Eigen::VectorXd& u,
                   const Eigen::VectorXd& edge_weights) {
  // The weights of the last assembly (or of the gradient flow's step size): one step stale
  // at most, which an estimate with a factor of room tolerates.
  if (edge_weights.size() != t.num_edges) return 0.0;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  std::vector<double> weight(t.num_vertices, 0.0);
  for (int e = 0; e < t.num_edges; ++e) {
    const int i = t.edge_vertices(e, 0), j = t.edge_vertices(e, 1);
    const double w = std::abs(edge_weights[e]) * (1 + std::max(std::abs(u[i]), std::abs(u[j])));
    weight[i] += w;
    weight[j] += w;
  }
  double worst = 0;
  for (int v = 0; v < t.num_vertices; ++v) {
    if (target.fixed[v] || t.vertex_component[v] < 0) continue;
    const double floor =
        floor_room * eps * (2 * std::numbers::pi * t.vertex_degree[v] + 2 * weight[v]);
    worst = std::max(worst, floor);
  }
  return worst;
}

std::string short_number(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

std::optional<Stop> stop_at_floor(double max_error, double floor, double tolerance) {
  if (!(max_error <= floor)) return std::nullopt;
  return Stop{FlowStatus::Converged, "reached max |K-bar - K| = " + short_number(max_error) +
                                         ", the floating-point floor of this metric (about " +
                                         short_number(floor) + "), above the tolerance " +
                                         short_number(tolerance)};
}

std::optional<Stop> stopping_rule(const std::vector<IterationRecord>& history, int iteration,
                                  const FlowOptions& options,
                                  const std::function<double()>& floor) {
  const double max_error = history.back().max_error;
  std::optional<Stop> stop;
  auto at_floor = [&] {
    stop = stop_at_floor(max_error, floor(), options.tolerance);
    return stop.has_value();
  };
  const bool stagnating =
      history.size() >= 2 && max_error > stagnation_ratio * history[history.size() - 2].max_error;
  if (max_error <= options.tolerance) {
    return Stop{FlowStatus::Converged, "reached max |K-bar - K| = " + short_number(max_error) +
                                           " <= " + short_number(options.tolerance)};
  }
  if (!(stagnating && at_floor()) && iteration >= options.max_iterations && !at_floor()) {
    return Stop{FlowStatus::MaxIterations,
                "stopped after " + std::to_string(iteration) +
                    " iterations at max |K-bar - K| = " + short_number(max_error)};
  }
  if (stop) return stop;
  const int window = options.stall_iterations;
  if (window > 0 && options.solver == FlowSolver::Newton &&
      history.size() > static_cast<std::size_t>(window)) {
    const double before = history[history.size() - 1 - window].max_error;
    if (!(max_error < stagnation_ratio * before) && !at_floor()) {
      return Stop{FlowStatus::MaxIterations,
                  "stalled: max |K-bar - K| = " + short_number(max_error) + " after " +
                      std::to_string(iteration) + " iterations, not half of its " +
                      short_number(before) + " " + std::to_string(window) + " iterations before"};
    }
  }
  return stop;
}

}  // namespace ricci::flow_detail
