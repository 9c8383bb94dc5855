#pragma once
/// \file
/// The angle distortion of one face: the one kernel behind measure_distortion
/// (param/distortion.cpp), the sphere map's figures (sphere/sphere.cpp) and the angle polish
/// (param/layout/polish.cpp).
///
/// The linear map from a triangle of R^3, in complex coordinates z of its own plane, to its image
/// is w = alpha z + beta conj(z). Its singular values are |alpha| + |beta| and
/// ||alpha| - |beta||, its determinant (the area ratio) is |alpha|^2 - |beta|^2, so
///     sigma_max / sigma_min = (|alpha| + |beta|) / ||alpha| - |beta||
///                           = (|alpha| + |beta|)^2 / |area ratio|.
/// With z0 = w0 = 0 and D = z1 conj(z2) - z2 conj(z1) = -2 i twice_area (|D| = 2 twice_area):
///     alpha D = w1 conj(z2) - w2 conj(z1),   beta D = z1 w2 - z2 w1,
/// and the ratio is (|alpha D| + |beta D|)^2 / (4 twice_area |twice_image|): the determinant
/// form, which takes the area ratio from the cross products instead of from the cancelling
/// difference |alpha D| - |beta D| (angle_distortion below). The polish minimises the ratio as
/// (A + B) / (A - B) with A = |alpha D| and B = |beta D| written as linear functionals of the
/// three corners' images (FaceCoefficients): a vertex moving alone changes A and B as distances
/// to two points, which its Newton steps need; its figures keep that form (ratio_from_moduli).

#include <cmath>
#include <complex>
#include <limits>

#include <Eigen/Geometry>

#include "ricci/numerics/complex.hpp"

namespace ricci::detail {

/// A triangle in complex coordinates of its plane: corner 0 at 0, corner 1 at z1 on the positive
/// real axis, corner 2 at z2 above it (below it for sign -1); twice_area is the triangle's twice
/// area times sign.
struct PlaneTriangle {
  std::complex<double> z1, z2;
  double twice_area = 0;
};

/// The triangle with edge vectors e1 = p1 - p0 and e2 = p2 - p0 in its plane's coordinates,
/// mirrored when sign is -1.
inline PlaneTriangle plane_triangle(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                                    double sign = 1.0) {
  const double twice_area = e1.cross(e2).norm();
  const double length1 = e1.norm();
  return {std::complex<double>(length1, 0.0),
          std::complex<double>(e1.dot(e2) / length1, sign * twice_area / length1),
          sign * twice_area};
}

/// How angle_distortion takes a modulus: fast_abs (sqrt of the squares, the measures' per-face
/// loop) or std::abs (hypot, the sphere map's). They agree within one rounding.
enum class Modulus { Fast, Exact };

/// sigma_max / sigma_min of the map taking `from` (twice_area > 0) onto the triangle
/// (0, w1, w2) whose twice signed area is twice_image (finite, != 0): the determinant form of
/// the file comment.
inline double angle_distortion(const PlaneTriangle& from, std::complex<double> w1,
                               std::complex<double> w2, double twice_image, Modulus modulus) {
  auto modulus_of = [modulus](std::complex<double> z) {
    return modulus == Modulus::Fast ? fast_abs(z) : std::abs(z);
  };
  const double alpha_d = modulus_of(w1 * std::conj(from.z2) - w2 * std::conj(from.z1));
  const double beta_d = modulus_of(from.z1 * w2 - from.z2 * w1);
  const double sum = alpha_d + beta_d;
  return sum * sum / (4.0 * from.twice_area * std::abs(twice_image));
}

/// alpha D = sum_k a_k w_k and beta D = sum_k b_k w_k over the three corners' images w_k (not
/// their differences): the coefficients of a triangle (z0 = 0).
struct FaceCoefficients {
  std::complex<double> a[3], b[3];
  bool valid = false;  ///< positive, finite 3D area
};

inline FaceCoefficients face_coefficients(const PlaneTriangle& t) {
  FaceCoefficients c;
  if (!(std::isfinite(t.twice_area) && t.twice_area > 0 && t.z1.real() > 0)) return c;
  c.a[0] = -(std::conj(t.z2) - std::conj(t.z1));
  c.a[1] = std::conj(t.z2);
  c.a[2] = -std::conj(t.z1);
  c.b[0] = -(t.z1 - t.z2);
  c.b[1] = -t.z2;
  c.b[2] = t.z1;
  c.valid = true;
  return c;
}

/// A - B at most this fraction of A: the face has collapsed to rounding (or flipped).
constexpr double kCollapsedFace = 1e-12;

/// sigma_max / sigma_min from A = |alpha D| and B = |beta D| as (A + B) / (A - B); infinity
/// when the face is flipped or degenerate (A - B <= kCollapsedFace A).
inline double ratio_from_moduli(double a, double b) {
  if (!(a - b > kCollapsedFace * a)) return std::numeric_limits<double>::infinity();
  return (a + b) / (a - b);
}

}  // namespace ricci::detail
