#include "ricci/metric/angles.hpp"

#include <cmath>
#include <limits>

namespace ricci {

double angle_from_lengths(double a, double b, double c) {
  // Differences are formed from the sides directly ((b + c - a) / 2 rather than s - a) so that
  // a needle triangle keeps its tiny angle to full relative precision.
  const double s = 0.5 * (a + b + c);
  const double sa = 0.5 * (b + c - a);
  const double sb = 0.5 * (a + c - b);
  const double sc = 0.5 * (a + b - c);
  if (!(a > 0 && b > 0 && c > 0 && sa > 0 && sb > 0 && sc > 0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return 2.0 * std::atan2(std::sqrt(sb * sc), std::sqrt(s * sa));
}

int corner_angles(const Topology& topology, const Eigen::VectorXd& lengths, CornerAngles& angles) {
  const int nf = topology.num_faces;
  angles.resize(nf, 3);
  int first_bad = -1;
  for (int f = 0; f < nf; ++f) {
    // Edge opposite corner k has index face_edges(f, k).
    const double l0 = lengths[topology.face_edges(f, 0)];
    const double l1 = lengths[topology.face_edges(f, 1)];
    const double l2 = lengths[topology.face_edges(f, 2)];
    const double a0 = angle_from_lengths(l0, l1, l2);
    const double a1 = angle_from_lengths(l1, l2, l0);
    const double a2 = angle_from_lengths(l2, l0, l1);
    angles(f, 0) = a0;
    angles(f, 1) = a1;
    angles(f, 2) = a2;
    if (first_bad < 0 && std::isnan(a0)) first_bad = f;
  }
  return first_bad;
}

}  // namespace ricci
