#include "ricci/metric/angles.hpp"

#include <cmath>
#include <limits>

#include "metric/detail/triangle_terms.hpp"

namespace ricci {

using triangle_terms::half_perimeter_terms;

double angle_from_lengths(double a, double b, double c) {
  const double l[3] = {a, b, c};
  double two_s, d[3];
  if (!half_perimeter_terms(l, two_s, d)) return std::numeric_limits<double>::quiet_NaN();
  double theta[3];
  triangle_terms::euclidean_angles(two_s, d, theta);
  return theta[0];
}

AnglesCheck corner_angles(const Topology& topology, const Eigen::VectorXd& lengths,
                          CornerAngles& angles) {
  // tan(theta_k / 2) = sqrt((s - l_{k+1})(s - l_{k+2}) / (s (s - l_k))) keeps full relative
  // accuracy for tiny and for near-pi angles.
  return {triangle_terms::corner_angles_with<double>(topology, lengths, angles,
                                                     triangle_terms::euclidean_angles<double>)};
}

}  // namespace ricci
