#include "ricci/numerics/convex_hull.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "ricci/numerics/predicates.hpp"

namespace ricci {
namespace {

/// Two bounding rectangles whose areas differ by less than this (relative) are the same
/// rectangle (a rectangle's four edge directions, computed with rounding): the smaller turn wins.
constexpr double kAreaTie = 1e-12;

}  // namespace

std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && orientation_sign(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, lower = k + 1; i > 0; --i) {
    while (k >= lower && orientation_sign(hull[k - 2], hull[k - 1], p[i - 1]) <= 0) --k;
    hull[k++] = p[i - 1];
  }
  hull.resize(k - 1);
  return hull;
}

double minimal_rectangle_rotation(const std::vector<Eigen::Vector2d>& hull) {
  if (hull.size() < 3) return 0;
  double best_area = std::numeric_limits<double>::infinity(), best_angle = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d d = hull[(i + 1) % hull.size()] - hull[i];
    double angle = -std::atan2(d.y(), d.x());
    // A quarter turn gives the same rectangle: keep the angle nearest to the hull as it is.
    angle -= std::numbers::pi / 2 * std::round(angle / (std::numbers::pi / 2));
    const double c = std::cos(angle), s = std::sin(angle);
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    for (const Eigen::Vector2d& q : hull) {
      const double x = c * q.x() - s * q.y(), y = s * q.x() + c * q.y();
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    const double area = (x1 - x0) * (y1 - y0);
    if (area < best_area * (1 - kAreaTie) ||
        (area <= best_area * (1 + kAreaTie) && std::abs(angle) < std::abs(best_angle))) {
      best_area = std::min(area, best_area);
      best_angle = angle;
    }
  }
  return best_angle;
}

}  // namespace ricci
