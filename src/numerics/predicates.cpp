#include "ricci/numerics/predicates.hpp"

#include <array>
#include <cmath>
#include <utility>

namespace ricci {
namespace {

/// Shewchuk's error bound for the plain evaluation of the 2 x 2 orientation determinant,
/// (3 + 16 eps) eps with eps = 2^-53: a determinant larger than this times (|left| + |right|)
/// has the right sign.
constexpr double kOrientationErrorBound = 3.3306690738754716e-16;

/// a + b = x + y exactly (Knuth's two-sum; x the rounded sum, y its error).
void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

/// A nonoverlapping expansion (components in increasing magnitude) of at most 12 components,
/// on the stack: the exact path runs for every pair of triangles that share a vertex (the
/// filter cannot decide a zero), so it must not allocate.
struct Expansion {
  std::array<double, 12> components{};
  int size = 0;

  /// Adds b, exactly.
  void grow(double b) {
    double q = b;
    for (int i = 0; i < size; ++i) {
      double sum, error;
      two_sum(q, components[i], sum, error);
      components[i] = error;
      q = sum;
    }
    components[size++] = q;
  }
};

/// Sign of sum over terms of x_i y_i, exact unless a product underflows: each product is split
/// into its rounded value and its error (fma), and the pieces summed as an expansion, whose sign
/// is that of its largest nonzero component.
int exact_sign_of_products(const std::array<std::array<double, 2>, 6>& products) {
  Expansion h;
  for (const auto& [x, y] : products) {
    const double p = x * y;
    h.grow(p);
    h.grow(std::fma(x, y, -p));
  }
  for (int i = h.size - 1; i >= 0; --i) {
    if (h.components[i] > 0) return 1;
    if (h.components[i] < 0) return -1;
  }
  return 0;
}

/// Whether an edge line of counter-clockwise triangle a has all of triangle b on its closed outer
/// side.
bool separated_by_edges_of(const std::array<Eigen::Vector2d, 3>& a,
                           const std::array<Eigen::Vector2d, 3>& b) {
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d& p = a[k];
    const Eigen::Vector2d& q = a[(k + 1) % 3];
    if (orientation_sign(p, q, b[0]) <= 0 && orientation_sign(p, q, b[1]) <= 0 &&
        orientation_sign(p, q, b[2]) <= 0) {
      return true;
    }
  }
  return false;
}

}  // namespace

int orientation_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const double left = (b.x() - a.x()) * (c.y() - a.y());
  const double right = (b.y() - a.y()) * (c.x() - a.x());
  const double det = left - right;
  const double bound = kOrientationErrorBound * (std::abs(left) + std::abs(right));
  if (det > bound) return 1;
  if (-det > bound) return -1;
  // Repeated points, the common undecided case (triangles that share a vertex), are exactly 0.
  if (c == a || c == b || a == b) return 0;
  // det = bx cy - bx ay - ax cy - by cx + by ax + ay cx (the ax ay terms cancel).
  return exact_sign_of_products({{{b.x(), c.y()},
                                  {-b.x(), a.y()},
                                  {-a.x(), c.y()},
                                  {-b.y(), c.x()},
                                  {b.y(), a.x()},
                                  {a.y(), c.x()}}});
}

bool ccw_triangles_overlap(const std::array<Eigen::Vector2d, 3>& a,
                           const std::array<Eigen::Vector2d, 3>& b) {
  return !separated_by_edges_of(a, b) && !separated_by_edges_of(b, a);
}

bool triangles_overlap(const std::array<Eigen::Vector2d, 3>& a,
                       const std::array<Eigen::Vector2d, 3>& b) {
  std::array<Eigen::Vector2d, 3> p = a, q = b;
  for (auto* t : {&p, &q}) {
    const int sign = orientation_sign((*t)[0], (*t)[1], (*t)[2]);
    if (sign == 0) return false;
    if (sign < 0) std::swap((*t)[1], (*t)[2]);
  }
  return ccw_triangles_overlap(p, q);
}

}  // namespace ricci
