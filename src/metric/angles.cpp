#include "ricci/metric/angles.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace ricci {

namespace {

/// Twice (s, s - l0, s - l1, s - l2) of a triangle with sides l0, l1, l2, computed as Kahan
/// ("Miscalculating area and angles of a needle-like triangle") does: sort the sides and group
/// the sums so that no subtraction cancels catastrophically. Returns false when a triangle
/// inequality fails (or a side is not positive).
bool half_perimeter_terms(const double l[3], double& two_s, double two_s_minus[3]) {
  int order[3] = {0, 1, 2};  // order[0] longest
  if (l[order[0]] < l[order[1]]) std::swap(order[0], order[1]);
  if (l[order[1]] < l[order[2]]) std::swap(order[1], order[2]);
  if (l[order[0]] < l[order[1]]) std::swap(order[0], order[1]);
  const double a = l[order[0]], b = l[order[1]], c = l[order[2]];
  if (!(c > 0)) return false;
  two_s = a + (b + c);
  two_s_minus[order[0]] = c - (a - b);
  two_s_minus[order[1]] = c + (a - b);
  two_s_minus[order[2]] = a + (b - c);
  return two_s_minus[order[0]] > 0 && std::isfinite(two_s);
}

}  // namespace

double angle_from_lengths(double a, double b, double c) {
  const double l[3] = {a, b, c};
  double two_s, d[3];
  if (!half_perimeter_terms(l, two_s, d)) return std::numeric_limits<double>::quiet_NaN();
  return 2.0 * std::atan2(std::sqrt(d[1] * d[2]), std::sqrt(two_s * d[0]));
}

namespace {

/// Every face's angles from its half-perimeter terms: `half_angles(two_s, d, theta)` fills the
/// three angles from 2 s and 2 (s - l_k), which half_perimeter_terms computed without
/// cancellation. Faces that break a triangle inequality get NaN.
template <class HalfAngles>
int corner_angles_with(const Topology& topology, const Eigen::VectorXd& lengths,
                       CornerAngles& angles, HalfAngles half_angles) {
  const int nf = topology.num_faces;
  angles.resize(nf, 3);
  int first_bad = -1;
  for (int f = 0; f < nf; ++f) {
    // Edge opposite corner k has index face_edges(f, k).
    const double l[3] = {lengths[topology.face_edges(f, 0)], lengths[topology.face_edges(f, 1)],
                         lengths[topology.face_edges(f, 2)]};
    double two_s, d[3];
    if (!half_perimeter_terms(l, two_s, d)) {
      angles.row(f).setConstant(std::numeric_limits<double>::quiet_NaN());
      if (first_bad < 0) first_bad = f;
      continue;
    }
    double theta[3];
    half_angles(two_s, d, theta);
    for (int k = 0; k < 3; ++k) angles(f, k) = theta[k];
  }
  return first_bad;
}

}  // namespace

int corner_angles(const Topology& topology, const Eigen::VectorXd& lengths, CornerAngles& angles,
                  Geometry geometry) {
  if (geometry == Geometry::Euclidean) return corner_angles(topology, lengths, angles);
  return corner_angles_with(
      topology, lengths, angles, [](double two_s, const double d[3], double theta[3]) {
        // tan(theta_k / 2) = sqrt(sinh(s - l_{k+1}) sinh(s - l_{k+2}) /
        // (sinh s sinh(s - l_k))), every sinh of a difference that did not
        // cancel.
        const double sinh_s = std::sinh(0.5 * two_s);
        const double sh[3] = {std::sinh(0.5 * d[0]), std::sinh(0.5 * d[1]), std::sinh(0.5 * d[2])};
        for (int k = 0; k < 3; ++k) {
          theta[k] = 2.0 * std::atan2(std::sqrt(sh[(k + 1) % 3] * sh[(k + 2) % 3]),
                                      std::sqrt(sinh_s * sh[k]));
        }
      });
}

int corner_angles(const Topology& topology, const Eigen::VectorXd& lengths, CornerAngles& angles) {
  // tan(theta_k / 2) = sqrt((s - l_{k+1})(s - l_{k+2}) / (s (s - l_k))) keeps full relative
  // accuracy for tiny and for near-pi angles.
  return corner_angles_with(
      topology, lengths, angles, [](double two_s, const double d[3], double theta[3]) {
        for (int k = 0; k < 3; ++k) {
          theta[k] =
              2.0 * std::atan2(std::sqrt(d[(k + 1) % 3] * d[(k + 2) % 3]), std::sqrt(two_s * d[k]));
        }
      });
}

}  // namespace ricci
