#include "ricci/sphere/spherical.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace ricci {

double spherical_angle_from_lengths(double a, double b, double c) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(a > 0 && b > 0 && c > 0)) return nan;
  // s - a as (b + c - a) / 2: no cancellation against s itself.
  const double s = 0.5 * (a + b + c);
  const double sa = 0.5 * (b + c - a), sb = 0.5 * (a + c - b), sc = 0.5 * (a + b - c);
  if (!(sa >= 0 && sb >= 0 && sc >= 0) || !(s < std::numbers::pi)) return nan;
  return 2.0 *
         std::atan2(std::sqrt(std::sin(sb) * std::sin(sc)), std::sqrt(std::sin(s) * std::sin(sa)));
}

}  // namespace ricci
