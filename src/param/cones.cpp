#include "ricci/param/cones.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "ricci/errors.hpp"
#include "ricci/flow/cholesky.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/delaunay_flips.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/lengths.hpp"

namespace ricci {
namespace {

/// Whether L plus a large penalty on vertex 0 (the gauge) factorises: a connected component's
/// Laplacian with non-negative enough weights does.
bool positive_definite_with_one_pin(const Eigen::SparseMatrix<double>& L) {
  Eigen::SparseMatrix<double> A = L;
  A.coeffRef(0, 0) += 1e10 * std::max(1.0, L.diagonal().cwiseAbs().maxCoeff());
  SparseCholesky cholesky;
  try {
    cholesky.factorize(A);
  } catch (const SolverError&) {
    return false;
  }
  return true;
}

/// The cotangent Laplacian of the input metric's intrinsic Delaunay triangulation (#V by #V).
Eigen::SparseMatrix<double> intrinsic_delaunay_laplacian(const Mesh& mesh, const Topology& t) {
  Topology flipped = t;
  StructureOptions vertex_scaling;
  vertex_scaling.scheme = Scheme::VertexScaling;
  Eigen::VectorXd lengths = input_edge_lengths(mesh, t);
  ConformalStructure s = make_conformal_structure(t, lengths, vertex_scaling).structure;
  DelaunayFlipOptions isometric;
  isometric.isometric = true;
  flip_to_delaunay(flipped, s, s.initial_u, lengths, isometric);
  CornerAngles angles;
  corner_angles(flipped, lengths, angles);
  Eigen::VectorXd hw, ew;
  halfedge_weights(flipped, s, s.initial_u, lengths, angles, hw);
  edge_weights(flipped, hw, ew);
  return curvature_hessian(flipped, ew);
}

/// Lowers hops[v] to the number of edges from `source` to v, for every v within max_rings edges
/// of it (breadth-first over the vertex neighbour lists).
void grow_rings(const std::vector<std::vector<int>>& neighbours, int source, int max_rings,
                std::vector<int>& hops) {
  std::vector<int> frontier = {source};
  hops[source] = 0;
  for (int r = 1; r <= max_rings && !frontier.empty(); ++r) {
    std::vector<int> next;
    for (int a : frontier) {
      for (int b : neighbours[a]) {
        if (hops[b] > r) {
          hops[b] = r;
          next.push_back(b);
        }
      }
    }
    frontier = std::move(next);
  }
}

}  // namespace

ConeSelection select_cones(const Mesh& mesh, const ConeSelectionOptions& options) {
  if (options.count < 0 || options.max_cones < 0 || !(options.max_log_scale > 0)) {
    throw InvalidInput("select_cones: count and max_cones must be >= 0 and max_log_scale > 0");
  }
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  if (t.components.size() != 1) {
    throw InvalidInput("select_cones: the mesh has " + std::to_string(t.components.size()) +
                       " connected components; choose cones for each on its own");
  }
  const int nv = t.num_vertices;
  const ConformalStructure s =
      make_conformal_structure(t, input_edge_lengths(mesh, t), options.structure).structure;
  Eigen::VectorXd lengths, hw, ew, curvature;
  CornerAngles angles;
  edge_lengths(t, s, s.initial_u, lengths);
  if (corner_angles(t, lengths, angles) >= 0) {
    throw InvalidInput("select_cones: the initial metric breaks a triangle inequality");
  }
  vertex_curvature(t, angles, curvature);
  halfedge_weights(t, s, s.initial_u, lengths, angles, hw);
  edge_weights(t, hw, ew);
  Eigen::SparseMatrix<double> L = curvature_hessian(t, ew);
  if (!positive_definite_with_one_pin(L)) {
    // Obtuse needles make some weights negative enough that L is indefinite (the repaired
    // Stanford dragon): the linearised problem then uses the cotangent Laplacian of the input's
    // intrinsic Delaunay triangulation, whose weights are all non-negative.
    L = intrinsic_delaunay_laplacian(mesh, t);
  }

  // Dirichlet vertices are held at u = 0 by a penalty on the diagonal, so that the sparsity
  // pattern (and CHOLMOD's analysis) stays the same while the cone set grows.
  const double penalty = 1e10 * std::max(1.0, L.diagonal().cwiseAbs().maxCoeff());
  const bool has_boundary = t.num_boundary_loops() > 0;
  const int chi = t.euler_characteristic();
  std::vector<char> held(nv, 0);
  if (has_boundary) {
    for (int v = 0; v < nv; ++v) held[v] = t.is_boundary_vertex[v];
  }
  ConeSelection result;
  std::vector<char> is_cone(nv, 0);
  // A cone of curvature K makes u behave like -(K / 2 pi) log r next to it: that singularity is
  // the cone, not distortion more cones could remove. Vertices within `kSeparation` rings of a
  // cone neither count in the measure nor become cones themselves (else the greedy choice would
  // pile cones next to each other).
  constexpr int kSeparation = 3;
  std::vector<int> ring(nv, kSeparation + 1);
  std::vector<std::vector<int>> neighbours(nv);
  for (int e = 0; e < t.num_edges; ++e) {
    neighbours[t.edge_vertices(e, 0)].push_back(t.edge_vertices(e, 1));
    neighbours[t.edge_vertices(e, 1)].push_back(t.edge_vertices(e, 0));
  }
  auto add_cone = [&](int v) {
    is_cone[v] = 1;
    held[v] = 1;
    result.vertices.push_back(v);
    grow_rings(neighbours, v, kSeparation, ring);
  };
  if (!has_boundary && chi != 0) {
    // Curvature 2 pi chi must go somewhere before the linear problem has a solution: start at the
    // sharpest vertex of the right sign.
    int first = 0;
    for (int v = 1; v < nv; ++v) {
      if ((chi > 0 && curvature[v] > curvature[first]) ||
          (chi < 0 && curvature[v] < curvature[first])) {
        first = v;
      }
    }
    add_cone(first);
  }

  SparseCholesky cholesky;
  Eigen::SparseMatrix<double> A = L;
  cholesky.analyze(A);
  struct Solution {
    Eigen::VectorXd u;
    double largest = 0;  // max |u - mean| away from the cones
    int worst = -1;      // the free vertex where it is reached
  };
  auto solve = [&](const std::vector<char>& hold, const std::vector<int>& rings) {
    bool any_held = false;
    for (char h : hold) any_held = any_held || h;
    // A closed torus with no cone yet: pin vertex 0 as the gauge (it is not a cone), and take
    // the mean out of the right-hand side so that the system is consistent.
    const int gauge = any_held ? -1 : 0;
    A = L;
    Eigen::VectorXd rhs = -curvature;
    if (gauge >= 0) rhs.array() -= rhs.mean();
    for (int v = 0; v < nv; ++v) {
      if (hold[v] || v == gauge) {
        A.coeffRef(v, v) += penalty;
        rhs[v] = 0;
      }
    }
    cholesky.factorize(A);
    Solution sol;
    sol.u = cholesky.solve(rhs);
    // The cones' own u = 0 only fixes the global scale; the distortion is the spread of u over
    // the other vertices (a free boundary, held at its true scale, counts).
    double mean = 0;
    int counted = 0;
    for (int v = 0; v < nv; ++v) {
      if (rings[v] <= kSeparation) continue;
      mean += sol.u[v];
      ++counted;
    }
    mean /= std::max(counted, 1);
    for (int v = 0; v < nv; ++v) {
      if (rings[v] <= kSeparation) continue;
      const double d = std::abs(sol.u[v] - mean);
      sol.largest = std::max(sol.largest, d);
      if (!hold[v] && (sol.worst < 0 || d > std::abs(sol.u[sol.worst] - mean))) sol.worst = v;
    }
    return sol;
  };

  if (options.try_first_cone_candidates > 1 && result.vertices.size() == 1) {
    // Try well-spread candidates for the first cone (farthest-point samples in edge hops from
    // the sharpest vertex) and keep the one whose linearised metric spreads least.
    std::vector<int> hops(nv, std::numeric_limits<int>::max());
    std::vector<int> candidates = {result.vertices.front()};
    auto spread_hops = [&](int from) {
      grow_rings(neighbours, from, std::numeric_limits<int>::max(), hops);
    };
    spread_hops(candidates.front());
    while (static_cast<int>(candidates.size()) < std::min(options.try_first_cone_candidates, nv)) {
      const int far = static_cast<int>(std::max_element(hops.begin(), hops.end()) - hops.begin());
      if (hops[far] == 0) break;
      candidates.push_back(far);
      spread_hops(far);
    }
    int best = candidates.front();
    double best_spread = INFINITY;
    for (int c : candidates) {
      std::vector<char> hold = held;
      std::fill(hold.begin(), hold.end(), 0);
      for (int v = 0; v < nv; ++v) hold[v] = has_boundary && t.is_boundary_vertex[v];
      hold[c] = 1;
      std::vector<int> rings(nv, kSeparation + 1);
      grow_rings(neighbours, c, kSeparation, rings);
      const double spread = solve(hold, rings).largest;
      if (spread < best_spread) {
        best_spread = spread;
        best = c;
      }
    }
    if (best != result.vertices.front()) {
      // Restart the cone set from the best candidate.
      const int old = result.vertices.front();
      is_cone[old] = 0;
      held[old] = has_boundary && t.is_boundary_vertex[old];
      result.vertices.clear();
      std::fill(ring.begin(), ring.end(), kSeparation + 1);
      add_cone(best);
    }
  }

  const int wanted = options.count > 0 ? std::min(options.count, options.max_cones) : -1;
  for (;;) {
    const Solution sol = solve(held, ring);
    result.max_log_scale.push_back(sol.largest);
    const int have = static_cast<int>(result.vertices.size());
    const bool done = wanted >= 0
                          ? have >= wanted
                          : (sol.largest <= options.max_log_scale || have >= options.max_cones);
    if (done || sol.worst < 0) {
      const Eigen::VectorXd absorbed = curvature + L * sol.u;
      result.linear_curvature.clear();
      for (int v : result.vertices) result.linear_curvature.push_back(absorbed[v]);
      break;
    }
    add_cone(sol.worst);
  }
  return result;
}

std::vector<Cone> quantize_cones(const std::vector<Cone>& cones, double total) {
  const double quarter = std::numbers::pi / 2;
  const long target_units = std::lround(total / quarter);
  std::vector<long> units(cones.size());
  long sum = 0;
  for (std::size_t i = 0; i < cones.size(); ++i) {
    units[i] = std::min(std::lround(cones[i].curvature / quarter), 3L);  // below 2 pi
    sum += units[i];
  }
  // Move the cones whose curvature lies closest to the other rounding, one quarter turn each.
  while (sum != target_units && !cones.empty()) {
    const long step = sum < target_units ? 1 : -1;
    std::size_t best = 0;
    double best_cost = INFINITY;
    for (std::size_t i = 0; i < cones.size(); ++i) {
      const double cost =
          std::abs(cones[i].curvature / quarter - static_cast<double>(units[i] + step));
      if (units[i] + step < 4 && cost < best_cost) {  // a cone stays below 2 pi
        best_cost = cost;
        best = i;
      }
    }
    if (!std::isfinite(best_cost)) break;
    units[best] += step;
    sum += step;
  }
  std::vector<Cone> out;
  for (std::size_t i = 0; i < cones.size(); ++i) {
    if (units[i] != 0) out.push_back({cones[i].vertex, static_cast<double>(units[i]) * quarter});
  }
  return out;
}

}  // namespace ricci
