#pragma once
/// \file
/// Planar vectors as `std::complex<double>`: the cross and dot products and a fast modulus, the
/// one set of helpers the layouts, the developments, the distortion and the refinement share.

#include <cmath>
#include <complex>

namespace ricci {

/// The z-component of the cross product a x b: twice the signed area of the triangle (0, a, b),
/// positive when b lies counter-clockwise of a.
inline double cross(std::complex<double> a, std::complex<double> b) {
  return a.real() * b.imag() - a.imag() * b.real();
}

/// |z| as sqrt(x^2 + y^2), for the per-face and per-edge loops (std::abs of std::complex is a
/// hypot call in libstdc++, several times slower). Within one rounding of std::abs; outside the
/// range where the squares neither overflow nor lose bits to underflow it falls back to
/// std::abs.
inline double fast_abs(std::complex<double> z) {
  const double r = std::sqrt(z.real() * z.real() + z.imag() * z.imag());
  // Squares of moduli in (1e-140, 1e140) stay inside double's normal range (1e-308 to 1e308).
  constexpr double kSmall = 1e-140, kLarge = 1e140;
  return r > kSmall && r < kLarge ? r : std::abs(z);
}

}  // namespace ricci
