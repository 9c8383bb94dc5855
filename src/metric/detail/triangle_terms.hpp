#pragma once
/// \file
/// Kernels of the metric module shared by its double and long double paths (internal): Kahan's
/// half-perimeter terms, the half-angle laws of cosines, and the hyperbolic unified form's
/// sinh^2(l / 2). Templates on the scalar type, so that the extended-precision refinement of a
/// hyperbolic metric (ricci/hyperbolic/hyperbolic_refinement.hpp) computes exactly what the double
/// flow computes, only with more bits.

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "numerics/detail/parallel.hpp"

#include "ricci/mesh/topology.hpp"

namespace ricci::triangle_terms {

/// Twice (s, s - l0, s - l1, s - l2) of a triangle with sides l0, l1, l2, computed as Kahan
/// ("Miscalculating area and angles of a needle-like triangle") does: sort the sides and group
/// the sums so that no subtraction cancels catastrophically. Returns false when a triangle
/// inequality fails (or a side is not positive).
template <class T>
bool half_perimeter_terms(const T l[3], T& two_s, T two_s_minus[3]) {
  int order[3] = {0, 1, 2};  // order[0] longest
  if (l[order[0]] < l[order[1]]) std::swap(order[0], order[1]);
  if (l[order[1]] < l[order[2]]) std::swap(order[1], order[2]);
  if (l[order[0]] < l[order[1]]) std::swap(order[0], order[1]);
  const T a = l[order[0]], b = l[order[1]], c = l[order[2]];
  if (!(c > 0)) return false;
  two_s = a + (b + c);
  two_s_minus[order[0]] = c - (a - b);
  two_s_minus[order[1]] = c + (a - b);
  two_s_minus[order[2]] = a + (b - c);
  return two_s_minus[order[0]] > 0 && std::isfinite(two_s);
}

/// Euclidean angles from the half-perimeter terms: tan(theta_k / 2) =
/// sqrt((s - l_{k+1})(s - l_{k+2}) / (s (s - l_k))).
template <class T>
void euclidean_angles(T two_s, const T d[3], T theta[3]) {
  for (int k = 0; k < 3; ++k) {
    theta[k] = 2 * std::atan2(std::sqrt(d[(k + 1) % 3] * d[(k + 2) % 3]), std::sqrt(two_s * d[k]));
  }
}

/// Hyperbolic angles from the half-perimeter terms: tan(theta_k / 2) =
/// sqrt(sinh(s - l_{k+1}) sinh(s - l_{k+2}) / (sinh s sinh(s - l_k))), every sinh of a
/// difference that did not cancel.
template <class T>
void hyperbolic_angles(T two_s, const T d[3], T theta[3]) {
  const T sinh_s = std::sinh(two_s / 2);
  const T sh[3] = {std::sinh(d[0] / 2), std::sinh(d[1] / 2), std::sinh(d[2] / 2)};
  for (int k = 0; k < 3; ++k) {
    theta[k] =
        2 * std::atan2(std::sqrt(sh[(k + 1) % 3] * sh[(k + 2) % 3]), std::sqrt(sinh_s * sh[k]));
  }
}

/// Every face's angles (#F by 3) from its edge lengths: `half_angles(two_s, d, theta)` fills the
/// three angles from 2 s and 2 (s - l_k). Faces that break a triangle inequality get NaN.
/// \return the first such face, or -1
template <class T, class Lengths, class Angles, class HalfAngles>
int corner_angles_with(const Topology& topology, const Lengths& lengths, Angles& angles,
                       HalfAngles half_angles) {
  const int nf = topology.num_faces;
  angles.resize(nf, 3);
  // Faces in parallel (each face's angles are its own); the first bad face whatever the split.
  return static_cast<int>(parallel::first_failing(
      nf,
      [&](std::int64_t f) {
        // Edge opposite corner k has index face_edges(f, k).
        const T l[3] = {lengths[topology.face_edges(f, 0)], lengths[topology.face_edges(f, 1)],
                        lengths[topology.face_edges(f, 2)]};
        T two_s, d[3];
        if (!half_perimeter_terms(l, two_s, d)) {
          for (int k = 0; k < 3; ++k) angles(f, k) = std::numeric_limits<T>::quiet_NaN();
          return false;
        }
        T theta[3];
        half_angles(two_s, d, theta);
        for (int k = 0; k < 3; ++k) angles(f, k) = theta[k];
        return true;
      },
      parallel::kDefaultMinChunk / 4));
}

/// q = sinh^2(l / 2) of the hyperbolic unified form, t = e^u, and the denominator's factors
/// f = 1 - eps t^2 (a length exists when q > 0 and both factors are positive).
template <class T>
struct HyperbolicEdge {
  T q, ti, tj, fi, fj;
  bool valid() const { return fi > 0 && fj > 0 && q > 0 && std::isfinite(q); }
};

template <class T>
HyperbolicEdge<T> hyperbolic_edge(T u_i, T u_j, T epsilon_i, T epsilon_j, T eta) {
  HyperbolicEdge<T> e;
  e.ti = std::exp(u_i);
  e.tj = std::exp(u_j);
  const T ai = epsilon_i * e.ti * e.ti, aj = epsilon_j * e.tj * e.tj;
  e.fi = 1 - ai;
  e.fj = 1 - aj;
  // The numerator is the Euclidean unified form's l^2 at radii t.
  e.q = (ai + aj + 2 * eta * e.ti * e.tj) / (e.fi * e.fj);
  return e;
}

}  // namespace ricci::triangle_terms
