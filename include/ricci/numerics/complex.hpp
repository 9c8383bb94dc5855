#pragma once
/// \file
/// Internal: |z| of a complex number as sqrt(x^2 + y^2), for the per-face and per-edge loops
/// (std::abs of std::complex is a hypot call in libstdc++, several times slower). Within one
/// rounding of std::abs; outside the range where the squares neither overflow nor lose bits to
/// underflow it falls back to std::abs.

#include <cmath>
#include <complex>

namespace ricci::complex_length {

inline double length(std::complex<double> z) {
  const double r = std::sqrt(z.real() * z.real() + z.imag() * z.imag());
  return r > 1e-140 && r < 1e140 ? r : std::abs(z);
}

}  // namespace ricci::complex_length
