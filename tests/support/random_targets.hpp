#pragma once
/// \file
/// Random admissible targets for the robustness tests and the stress suite (bench/stress.cpp):
/// header-only, so that the benchmark uses them without the test framework.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/target.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci::testing {

/// Per-vertex curvatures that satisfy Gauss-Bonnet on every component: uniform noise in
/// [-amplitude, amplitude] added to 2 pi chi / n (closed components) or to the input's own
/// curvature (components with boundary), the noise's mean removed. Boundary vertices of a single
/// face keep the input's curvature: theirs must stay in (0, pi) whatever the metric, and no flip
/// reaches them.
inline Eigen::VectorXd random_admissible_curvature(const Mesh& mesh, const Topology& t,
                                                   unsigned long long seed,
                                                   double amplitude = 0.25) {
  CornerAngles angles;
  corner_angles(t, input_edge_lengths(mesh, t), angles);
  const Eigen::VectorXd input_curvature = vertex_curvature(t, angles);
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> noise(-amplitude, amplitude);
  Eigen::VectorXd values = Eigen::VectorXd::Zero(t.num_vertices);
  for (const Component& comp : t.components) {
    const bool closed = comp.num_boundary_loops == 0;
    const double base = 2 * std::numbers::pi * comp.euler_characteristic /
                        static_cast<double>(comp.vertices.size());
    std::vector<int> noisy;
    double mean = 0;
    for (int v : comp.vertices) {
      values[v] = closed ? base : input_curvature[v];
      if (t.is_boundary_vertex[v] && t.vertex_degree[v] == 2) continue;
      noisy.push_back(v);
      const double x = noise(random);
      values[v] += x;
      mean += x;
    }
    mean /= static_cast<double>(std::max<std::size_t>(noisy.size(), 1));
    for (int v : noisy) values[v] -= mean;
  }
  return values;
}

/// 3 to 12 cones at distinct random vertices of a closed genus-0 mesh, curvatures drawn uniformly
/// in [-pi, 1.5 pi] and shifted to sum to 4 pi, redrawn while one reaches 2 pi - 0.05 (a cone
/// angle under 0.05 rad) or goes below -3 pi. (Two cones below 2 pi cannot sum to 4 pi.)
inline std::vector<Cone> random_sphere_cones(int num_vertices, std::mt19937_64& random) {
  constexpr double pi = std::numbers::pi;
  std::uniform_int_distribution<int> count(3, 12);
  std::uniform_int_distribution<int> vertex(0, num_vertices - 1);
  std::uniform_real_distribution<double> curvature(-pi, 1.5 * pi);
  const int k = count(random);
  std::vector<Cone> cones;
  for (;;) {
    cones.clear();
    double sum = 0;
    for (int i = 0; i < k; ++i) {
      int v;
      do {
        v = vertex(random);
      } while (
          std::any_of(cones.begin(), cones.end(), [v](const Cone& c) { return c.vertex == v; }));
      cones.push_back({v, curvature(random)});
      sum += cones.back().curvature;
    }
    const double shift = (4 * pi - sum) / k;
    bool ok = true;
    for (Cone& c : cones) {
      c.curvature += shift;
      ok = ok && c.curvature < 2 * pi - 0.05 && c.curvature > -3 * pi;
    }
    if (ok) return cones;
  }
}

}  // namespace ricci::testing
