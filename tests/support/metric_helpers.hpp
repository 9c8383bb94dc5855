#pragma once
/// \file
/// Curvature at given log radii, for tests that probe K(u) directly.

#include <Eigen/Core>

#include "ricci/metric/curvature.hpp"
#include "ricci/metric/lengths.hpp"

namespace ricci::testing {

/// K(u) for a conformal structure; an empty vector when u breaks a length or a triangle
/// inequality.
inline Eigen::VectorXd curvature_at(const Topology& t, const ConformalStructure& s,
                                    const Eigen::VectorXd& u) {
  Eigen::VectorXd l;
  CornerAngles a;
  if (!edge_lengths(t, s, u, l).ok() || !corner_angles(t, l, a).ok()) return {};
  return vertex_curvature(t, a);
}

}  // namespace ricci::testing
