#pragma once
/// \file
/// Floating-point arithmetic wider than double, for the stages whose figures span more than
/// double resolves (the sphere map lays out limbs a conformal map shrinks e^-25 times): long
/// double (64-bit significand on x86) and quad, GCC's __float128 (113 bits, in software through
/// libgcc: about 30 times slower than double) where the compiler has it, else long double again.
/// The standard library knows no __float128 in strict mode, so its significand and square root
/// are here.

#include <cmath>
#include <limits>
#include <type_traits>

namespace ricci {

#if defined(__SIZEOF_FLOAT128__) && defined(__GLIBCXX__)
#define RICCI_HAVE_QUAD 1
/// Quadruple precision (113-bit significand).
using Quad = __float128;
#else
/// Quadruple precision is not available: long double stands in.
using Quad = long double;
#endif

/// Significand bits of the floating-point type T (53 for double, 64 for x86 long double, 113
/// for __float128).
template <class T>
constexpr int significand_bits() {
#ifdef RICCI_HAVE_QUAD
  if constexpr (std::is_same_v<T, __float128>) return 113;
#endif
  return std::numeric_limits<T>::digits;
}

/// sqrt(x) in each precision.
inline double square_root(double x) {
  return std::sqrt(x);
}
inline long double square_root(long double x) {
  return std::sqrt(x);
}
#ifdef RICCI_HAVE_QUAD
/// The long double root refined by one Newton step, which doubles its 64 correct bits; 0 for
/// x <= 0.
inline __float128 square_root(__float128 x) {
  if (!(x > 0)) return 0;
  const __float128 s = std::sqrt(static_cast<long double>(x));
  return (s + x / s) / 2;
}
#endif

}  // namespace ricci
