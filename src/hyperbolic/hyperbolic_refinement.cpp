#include "ricci/hyperbolic/hyperbolic_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

#include "ricci/errors.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace ricci {

namespace {

using Wide = long double;

/// max |K-bar - K| over the vertices with a target, K from wide angles; r receives K-bar - K.
double curvature_error(const Topology& t, const Target& target, const WideAngles& angles,
                       WideVector& r) {
  r.setZero(t.num_vertices);
  for (int v = 0; v < t.num_vertices; ++v) {
    r[v] = (t.is_boundary_vertex[v] ? std::numbers::pi_v<Wide> : 2 * std::numbers::pi_v<Wide>);
  }
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) r[t.triangles(f, k)] -= angles(f, k);
  }
  double worst = 0;
  for (int v = 0; v < t.num_vertices; ++v) {
    if (t.vertex_component[v] < 0 || target.fixed[v]) {
      r[v] = 0;
      continue;
    }
    r[v] = static_cast<Wide>(target.curvature[v]) - r[v];
    worst = std::max(worst, static_cast<double>(std::abs(r[v])));
  }
  return worst;
}

}  // namespace

HyperbolicRefinement refine_hyperbolic_metric(const Topology& t, const ConformalStructure& s,
                                              const Target& target, const Eigen::VectorXd& u,
                                              int max_iterations) {
  if (s.geometry != Geometry::Hyperbolic) {
    throw InvalidInput("refine_hyperbolic_metric: the structure is not hyperbolic");
  }
  HyperbolicRefinement result;
  result.u = u.cast<Wide>();
  WideAngles angles;
  WideVector r;
  auto evaluate = [&]() {
    if (!hyperbolic_edge_lengths_wide(t, s, result.u, result.lengths).ok() ||
        !hyperbolic_corner_angles_wide(t, result.lengths, angles).ok()) {
      throw InvalidInput("refine_hyperbolic_metric: the metric is not valid at these log radii");
    }
    return curvature_error(t, target, angles, r);
  };
  double error = evaluate();
  result.max_error_before = result.max_error_after = error;

  // The Hessian at the input u, rows for the vertices with a target.
  std::vector<int> row(t.num_vertices, -1), vertex_of_row;
  for (int v = 0; v < t.num_vertices; ++v) {
    if (t.vertex_component[v] >= 0 && !target.fixed[v]) {
      row[v] = static_cast<int>(vertex_of_row.size());
      vertex_of_row.push_back(v);
    }
  }
  const int n = static_cast<int>(vertex_of_row.size());
  if (n == 0 || max_iterations <= 0) return result;
  Eigen::VectorXd lengths = result.lengths.cast<double>();
  CornerAngles double_angles = angles.cast<double>();
  Eigen::VectorXd weights, corner_diagonal, edge_w;
  hyperbolic_hessian_terms(t, s, u, lengths, double_angles, weights, corner_diagonal);
  edge_weights(t, weights, edge_w);
  std::vector<Eigen::Triplet<double>> triplets;
  for (int e = 0; e < t.num_edges; ++e) {
    const int ri = row[t.edge_vertices(e, 0)], rj = row[t.edge_vertices(e, 1)];
    if (ri >= 0) triplets.emplace_back(ri, ri, edge_w[e]);
    if (rj >= 0) triplets.emplace_back(rj, rj, edge_w[e]);
    if (ri >= 0 && rj >= 0) {
      triplets.emplace_back(ri, rj, -edge_w[e]);
      triplets.emplace_back(rj, ri, -edge_w[e]);
    }
  }
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int rv = row[t.triangles(f, k)];
      if (rv >= 0) triplets.emplace_back(rv, rv, corner_diagonal[3 * f + k]);
    }
  }
  Eigen::SparseMatrix<double> h(n, n);
  h.setFromTriplets(triplets.begin(), triplets.end());
  SparseCholesky cholesky;
  cholesky.analyze(h);
  cholesky.factorize(h);

  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    Eigen::VectorXd rhs(n);
    for (int k = 0; k < n; ++k) rhs[k] = static_cast<double>(r[vertex_of_row[k]]);
    const Eigen::VectorXd delta = cholesky.solve(rhs);
    const WideVector previous = result.u;
    for (int k = 0; k < n; ++k) result.u[vertex_of_row[k]] += delta[k];
    const double next = evaluate();
    if (!(next < error)) {  // no progress: keep the better point
      result.u = previous;
      evaluate();
      break;
    }
    error = next;
    ++result.iterations;
    result.max_error_after = error;
  }
  return result;
}

}  // namespace ricci
