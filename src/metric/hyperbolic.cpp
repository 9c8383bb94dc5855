#include "ricci/metric/hyperbolic.hpp"

#include <cmath>
#include <limits>

namespace ricci {

double hyperbolic_radius(double u) {
  if (!(u < 0)) return std::numeric_limits<double>::quiet_NaN();
  return 2.0 * std::atanh(std::exp(u));
}

double hyperbolic_log_radius(double r) {
  return std::log(std::tanh(0.5 * r));
}

double hyperbolic_edge_length(double r_i, double r_j, double eta) {
  const double c = std::cosh(r_i) * std::cosh(r_j) + eta * std::sinh(r_i) * std::sinh(r_j);
  if (!(c >= 1.0)) return std::numeric_limits<double>::quiet_NaN();
  return std::acosh(c);
}

double hyperbolic_angle_from_lengths(double a, double b, double c) {
  if (!(a > 0 && b > 0 && c > 0)) return std::numeric_limits<double>::quiet_NaN();
  // The differences s - a etc. as (b + c - a) / 2: no cancellation against s itself.
  const double s = 0.5 * (a + b + c);
  const double sa = 0.5 * (b + c - a), sb = 0.5 * (a + c - b), sc = 0.5 * (a + b - c);
  if (!(sa >= 0 && sb >= 0 && sc >= 0)) return std::numeric_limits<double>::quiet_NaN();
  return 2.0 * std::atan2(std::sqrt(std::sinh(sb) * std::sinh(sc)),
                          std::sqrt(std::sinh(s) * std::sinh(sa)));
}

}  // namespace ricci
