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

/// Angle opposite side a in a triangle with sides a, b, c, by the half-angle formula
/// theta = 2 atan2(sqrt((s-b)(s-c)), sqrt(s(s-a))), which keeps full relative accuracy for tiny
/// and near-pi angles. Returns NaN when the triangle inequality fails or a side is not positive.
double angle_from_lengths(double a, double b, double c);

/// Computes every corner angle.
/// \param lengths #E edge lengths
/// \param[out] angles #F by 3 (resized)
/// \return index of the first face that breaks a triangle inequality (its angles are NaN), or -1
int corner_angles(const Topology& topology, const Eigen::VectorXd& lengths, CornerAngles& angles);

/// The same in a chosen background geometry: hyperbolic triangles by the half-angle form of the
/// hyperbolic law of cosines, tan(theta_k / 2) = sqrt(sinh(s - l_{k+1}) sinh(s - l_{k+2}) /
/// (sinh s sinh(s - l_k))).
int corner_angles(const Topology& topology, const Eigen::VectorXd& lengths, CornerAngles& angles,
                  Geometry geometry);

}  // namespace ricci
