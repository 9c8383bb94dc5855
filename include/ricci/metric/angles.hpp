#pragma once
/// \file
/// Corner angles from edge lengths, accurate for needle triangles, with triangle-inequality
/// violations detected instead of fed to acos.

#include <Eigen/Core>

#include "ricci/mesh/topology.hpp"
#include "ricci/metric/geometry.hpp"

namespace ricci {

/// #F by 3 corner angles: angle(f, k) is the angle of face f at vertex triangles(f, k).
using CornerAngles = Eigen::Matrix<double, Eigen::Dynamic, 3>;

/// What corner_angles found: the first face whose lengths break a triangle inequality (or are
/// not positive). Its angles, and those of every later such face, are NaN.
struct AnglesCheck {
  int first_bad_face = -1;  ///< the lowest such face, -1 when every face is a triangle
  /// True when every face's lengths form a triangle.
  bool ok() const { return first_bad_face < 0; }
};

/// Angle opposite side a in a triangle with sides a, b, c, by the half-angle formula
/// theta = 2 atan2(sqrt((s-b)(s-c)), sqrt(s(s-a))), which keeps full relative accuracy for tiny
/// and near-pi angles. Returns NaN when the triangle inequality fails or a side is not positive.
double angle_from_lengths(double a, double b, double c);

/// Computes every corner angle.
/// \param lengths #E edge lengths
/// \param[out] angles #F by 3 (resized)
/// \return the first face that breaks a triangle inequality (its angles are NaN), if any
AnglesCheck corner_angles(const Topology& topology, const Eigen::VectorXd& lengths,
                          CornerAngles& angles);

/// The same in a chosen background geometry: the Euclidean corner_angles above, or
/// hyperbolic_corner_angles (ricci/metric/hyperbolic.hpp). The switch is defined in
/// background.cpp beside the background's other dispatches (ricci/metric/background.hpp).
AnglesCheck corner_angles(const Topology& topology, const Eigen::VectorXd& lengths,
                          CornerAngles& angles, Geometry geometry);

}  // namespace ricci
