#pragma once
/// \file
/// Discrete Gaussian curvature: K_i = 2 pi - (angle sum) inside, pi - (angle sum) on the boundary.

#include <Eigen/Core>

#include "ricci/metric/angles.hpp"

namespace ricci {

/// Vertex curvatures from corner angles (unreferenced vertices get 0).
/// \param[out] curvature #V (resized)
void vertex_curvature(const Topology& topology, const CornerAngles& angles,
                      Eigen::VectorXd& curvature);

/// Convenience overload returning the vector.
Eigen::VectorXd vertex_curvature(const Topology& topology, const CornerAngles& angles);

/// |sum K - 2 pi chi| / max(1, 2 pi #V): the Gauss-Bonnet defect relative to the size of the sum
/// (the angle sums that make up K are each of order 2 pi).
double gauss_bonnet_relative_error(const Topology& topology, const Eigen::VectorXd& curvature);

/// Gauss-Bonnet in the hyperbolic background: |sum K - area - 2 pi chi| / max(1, 2 pi #V).
double hyperbolic_gauss_bonnet_relative_error(const Topology& topology,
                                              const Eigen::VectorXd& curvature, double area);
/// Compensated (Neumaier) sum, for totals that must hold to the last digits.
double accurate_sum(const Eigen::VectorXd& values);

}  // namespace ricci
