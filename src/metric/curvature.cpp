#include "ricci/metric/curvature.hpp"

#include <cmath>
#include <numbers>

namespace ricci {

void vertex_curvature(const Topology& topology, const CornerAngles& angles,
                      Eigen::VectorXd& curvature) {
  const int nv = topology.num_vertices;
  curvature.resize(nv);
  for (int v = 0; v < nv; ++v) {
    if (topology.vertex_component[v] < 0) {
      curvature[v] = 0;
    } else {
      curvature[v] = topology.is_boundary_vertex[v] ? std::numbers::pi : 2 * std::numbers::pi;
    }
  }
  for (int f = 0; f < topology.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) curvature[topology.triangles(f, k)] -= angles(f, k);
  }
}

Eigen::VectorXd vertex_curvature(const Topology& topology, const CornerAngles& angles) {
  Eigen::VectorXd curvature;
  vertex_curvature(topology, angles, curvature);
  return curvature;
}

double accurate_sum(const Eigen::VectorXd& values) {
  double sum = 0, compensation = 0;
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    const double x = values[i];
    const double t = sum + x;
    compensation += std::abs(sum) >= std::abs(x) ? (sum - t) + x : (x - t) + sum;
    sum = t;
  }
  return sum + compensation;
}

double gauss_bonnet_relative_error(const Topology& topology, const Eigen::VectorXd& curvature) {
  const double expected = 2 * std::numbers::pi * topology.euler_characteristic();
  const double scale = std::max(1.0, 2 * std::numbers::pi * topology.num_referenced_vertices());
  return std::abs(accurate_sum(curvature) - expected) / scale;
}

double hyperbolic_gauss_bonnet_relative_error(const Topology& topology,
                                              const Eigen::VectorXd& curvature, double area) {
  const double expected = 2 * std::numbers::pi * topology.euler_characteristic();
  const double scale = std::max(1.0, 2 * std::numbers::pi * topology.num_referenced_vertices());
  return std::abs((accurate_sum(curvature) - area) - expected) / scale;
}

}  // namespace ricci
