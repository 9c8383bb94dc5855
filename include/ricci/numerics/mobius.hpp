#pragma once
/// \file
/// Orientation-preserving isometries of the Poincare disk (Moebius maps in SU(1,1)) and the
/// hyperbolic distance (curvature -1), in any floating-point precision. A map is stored as the
/// matrix [[a, b], [conj b, conj a]] with det = |a|^2 - |b|^2 = 1, acting by
/// z -> (a z + b) / (conj(b) z + conj(a)); M and -M are the same map. Composition is the matrix
/// product, so every function here keeps the SU(1,1) shape exactly (up to rounding of the
/// determinant, which `normalized` restores).
///
/// One type over the scalar: `Mobius` (double) for results and the API, `WideMobius` (long
/// double) for the hyperbolic layout's deck transformations near the rim of the disk, and the
/// Fuchsian group's quadruple precision (src/hyperbolic/fuchsian.cpp). The algebra (apply, compose,
/// inverse, power, casts, frames) is defined here for every scalar; the functions that need the
/// standard library's square roots and hyperbolic functions are compiled for double and long
/// double. Where no map argument fixes the scalar, it is double unless given:
/// `translation_to_origin<long double>(p)` (a std::complex<long double> does not convert
/// implicitly to the double version's argument, so forgetting it does not compile).

#include <complex>
#include <type_traits>

namespace ricci {

/// A Moebius map of the unit disk onto itself, z -> (a z + b) / (conj(b) z + conj(a)), with
/// entries of scalar type T.
/// \pre |a|^2 - |b|^2 = 1 (see `normalized`); the default is the identity
template <class T>
struct BasicMobius {
  std::complex<T> a{T{1}};
  std::complex<T> b{T{0}};
};

using Mobius = BasicMobius<double>;
using WideMobius = BasicMobius<long double>;

/// M(z). Points of the closed disk map into the closed disk; z on the unit circle stays on it.
/// (Not named `apply`: argument-dependent lookup on std::complex would find std::apply.)
template <class T>
std::complex<T> apply_mobius(const BasicMobius<T>& m, std::type_identity_t<std::complex<T>> z) {
  return (m.a * z + m.b) / (std::conj(m.b) * z + std::conj(m.a));
}

/// f after g: z -> f(g(z)) (the matrix product F G).
template <class T>
BasicMobius<T> compose(const BasicMobius<T>& f, const BasicMobius<T>& g) {
  // [[a1, b1], [b1*, a1*]] [[a2, b2], [b2*, a2*]]: the product keeps the SU(1,1) shape.
  return {f.a * g.a + f.b * std::conj(g.b), f.a * g.b + f.b * std::conj(g.a)};
}

/// The inverse map (matrix [[conj a, -b], [-conj b, a]]).
template <class T>
BasicMobius<T> inverse(const BasicMobius<T>& m) {
  return {std::conj(m.a), -m.b};
}

/// m^k for any integer k (k < 0: powers of the inverse), by repeated squaring.
template <class T>
BasicMobius<T> power(const BasicMobius<T>& m, int k) {
  BasicMobius<T> base = k < 0 ? inverse(m) : m;
  // Unsigned magnitude: -INT_MIN overflows an int.
  unsigned long long n = k < 0 ? -static_cast<long long>(k) : static_cast<long long>(k);
  BasicMobius<T> result;
  while (n > 0) {
    if (n & 1U) result = compose(result, base);
    base = compose(base, base);
    n >>= 1U;
  }
  return result;
}

/// The same entries rounded (or widened) to scalar type To, each part on its own.
template <class To, class From>
BasicMobius<To> mobius_cast(const BasicMobius<From>& m) {
  return {std::complex<To>(static_cast<To>(m.a.real()), static_cast<To>(m.a.imag())),
          std::complex<To>(static_cast<To>(m.b.real()), static_cast<To>(m.b.imag()))};
}

/// z in the frame centred at p: the image of z under the isometry moving p to the centre,
/// (z - p) / (1 - conj(p) z). The map of translation_to_origin(p) applied without forming its
/// matrix: no scaling by 1 / sqrt(1 - |p|^2), so fewer roundings, and no check of p.
template <class T>
std::complex<T> to_frame(std::complex<T> p, std::complex<T> z) {
  return (z - p) / (T{1} - std::conj(p) * z);
}

/// The inverse of to_frame: w in the frame centred at p back in the disk,
/// (w + p) / (1 + conj(p) w).
template <class T>
std::complex<T> from_frame(std::complex<T> p, std::complex<T> w) {
  return (w + p) / (T{1} + std::conj(p) * w);
}

// Compiled for T = double and long double (src/numerics/mobius.cpp).

/// |a|^2 - |b|^2, computed as (|a| - |b|)(|a| + |b|): 1 for a valid map.
template <class T>
T determinant(const BasicMobius<T>& m);

/// m scaled to determinant 1, sign fixed so that Re a >= 0 (M and -M are one map).
/// \throw InvalidInput (naming normalized) when the determinant is not positive and finite
template <class T>
BasicMobius<T> normalized(const BasicMobius<T>& m);

/// The rotation z -> e^{i angle} z about the origin.
template <class T = double>
BasicMobius<T> rotation(std::type_identity_t<T> angle);

/// The isometry moving z to the origin along the geodesic through both,
/// w -> (w - z) / (1 - conj(z) w).
/// \throw InvalidInput when |z| >= 1 or z is not finite
template <class T = double>
BasicMobius<T> translation_to_origin(std::type_identity_t<std::complex<T>> z);

/// Hyperbolic distance between two points of the open disk, 2 asinh(|z - w| /
/// sqrt((1 - |z|^2)(1 - |w|^2))): full relative accuracy for close points (acosh of a number near
/// 1 loses half the digits) and near the boundary (1 - |z|^2 computed as (1 - |z|)(1 + |z|)).
/// Returns +inf when a point is on or outside the unit circle.
template <class T = double>
T disk_distance(std::type_identity_t<std::complex<T>> z, std::type_identity_t<std::complex<T>> w);

/// The orientation-preserving isometry taking z1 to w1 and the geodesic direction from z1 towards
/// z2 to the direction from w1 towards w2 (exact at z1 up to rounding). It takes z2 to w2 only
/// when d(z1, z2) = d(w1, w2); the optional `relative_mismatch` receives
/// |d(z1, z2) - d(w1, w2)| / max(d(z1, z2), d(w1, w2)) (the hyperbolic distance between the image
/// of z2 and w2, relative to the distance matched; 0 when both distances are 0).
/// \throw InvalidInput when a point is not inside the unit circle or z1 = z2 or w1 = w2
template <class T = double>
BasicMobius<T> disk_isometry(std::type_identity_t<std::complex<T>> z1,
                             std::type_identity_t<std::complex<T>> z2,
                             std::type_identity_t<std::complex<T>> w1,
                             std::type_identity_t<std::complex<T>> w2,
                             std::type_identity_t<T>* relative_mismatch = nullptr);

/// How far a map is from the identity: after `normalized`, min(max(|a - 1|, |b|),
/// max(|a + 1|, |b|)), the max-norm of M - I or of M + I. Rounding makes a product of maps of
/// operator norm N_1 ... N_k differ from the identity by about 1e-16 N_1 ... N_k (in double).
template <class T>
T distance_to_identity(const BasicMobius<T>& m);

/// Operator norm of the matrix (its largest singular value, |a| + |b| >= 1 for a valid map).
template <class T>
T operator_norm(const BasicMobius<T>& m);

/// |trace| / 2 = |Re a| (normalised): > 1 hyperbolic, = 1 parabolic, < 1 elliptic.
template <class T>
T half_trace(const BasicMobius<T>& m);

/// Translation length of a hyperbolic map, 2 acosh(|Re a|) after normalisation (0 when not
/// hyperbolic): how far it moves the points of its axis.
template <class T>
T translation_length(const BasicMobius<T>& m);

}  // namespace ricci
