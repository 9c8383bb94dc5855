#include "ricci/numerics/mobius.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

/// 1 - |z|^2 without the cancellation of 1 - (x^2 + y^2) near the circle.
template <class T>
T one_minus_norm2(std::complex<T> z) {
  const T r = std::abs(z);  // hypot: no overflow, correctly rounded to an ulp or so
  return (T{1} - r) * (T{1} + r);
}

template <class T>
void check_inside(const char* fn, std::complex<T> z, const char* name) {
  if (!std::isfinite(z.real()) || !std::isfinite(z.imag()) || !(std::abs(z) < T{1})) {
    throw InvalidInput(std::string(fn) + ": " + name + " = (" + std::to_string(z.real()) + ", " +
                       std::to_string(z.imag()) + ") is not inside the unit circle");
  }
}

}  // namespace

template <class T>
T determinant(const BasicMobius<T>& m) {
  const T p = std::abs(m.a), q = std::abs(m.b);
  return (p - q) * (p + q);
}

template <class T>
BasicMobius<T> normalized(const BasicMobius<T>& m) {
  const T det = determinant(m);
  if (!(det > 0) || !std::isfinite(det)) {
    throw InvalidInput("normalized: the Moebius map has determinant " + std::to_string(det) +
                       " (|a|^2 - |b|^2 must be positive and finite)");
  }
  const T s = (m.a.real() < 0 ? T{-1} : T{1}) / std::sqrt(det);
  return {s * m.a, s * m.b};
}

template <class T>
BasicMobius<T> rotation(std::type_identity_t<T> angle) {
  return {std::polar(T{1}, T{0.5} * angle), T{0}};
}

template <class T>
BasicMobius<T> translation_to_origin(std::type_identity_t<std::complex<T>> z) {
  check_inside("translation_to_origin", z, "z");
  const T s = T{1} / std::sqrt(one_minus_norm2(z));
  return {std::complex<T>(s, T{0}), -s * z};
}

template <class T>
T disk_distance(std::type_identity_t<std::complex<T>> z, std::type_identity_t<std::complex<T>> w) {
  const T dz = one_minus_norm2(z), dw = one_minus_norm2(w);
  if (!(dz > 0) || !(dw > 0)) return std::numeric_limits<T>::infinity();
  return T{2} * std::asinh(std::abs(z - w) / std::sqrt(dz * dw));
}

template <class T>
BasicMobius<T> disk_isometry(std::type_identity_t<std::complex<T>> z1,
                             std::type_identity_t<std::complex<T>> z2,
                             std::type_identity_t<std::complex<T>> w1,
                             std::type_identity_t<std::complex<T>> w2,
                             std::type_identity_t<T>* relative_mismatch) {
  using Complex = std::complex<T>;
  const char* fn = "disk_isometry";
  check_inside(fn, z1, "z1");
  check_inside(fn, z2, "z2");
  check_inside(fn, w1, "w1");
  check_inside(fn, w2, "w2");
  if (z1 == z2) throw InvalidInput(std::string(fn) + ": z1 = z2 gives no direction");
  if (w1 == w2) throw InvalidInput(std::string(fn) + ": w1 = w2 gives no direction");
  const BasicMobius<T> from = translation_to_origin<T>(z1), to = translation_to_origin<T>(w1);
  // At the origin geodesics are straight: the directions are the arguments of the images.
  const Complex u = apply_mobius(from, z2), v = apply_mobius(to, w2);
  const Complex turn = (v / std::abs(v)) / (u / std::abs(u));
  const BasicMobius<T> spin{std::sqrt(turn), T{0}};  // a / conj(a) = turn
  const BasicMobius<T> map = normalized(compose(inverse(to), compose(spin, from)));
  if (relative_mismatch) {
    const T d1 = disk_distance<T>(z1, z2), d2 = disk_distance<T>(w1, w2);
    const T scale = std::max(d1, d2);
    *relative_mismatch = scale > 0 ? std::abs(d1 - d2) / scale : T{0};
  }
  return map;
}

template <class T>
T distance_to_identity(const BasicMobius<T>& m) {
  const BasicMobius<T> n = normalized(m);
  const T off = std::abs(n.b);
  return std::min(std::max(std::abs(n.a - T{1}), off), std::max(std::abs(n.a + T{1}), off));
}

template <class T>
T operator_norm(const BasicMobius<T>& m) {
  return std::abs(m.a) + std::abs(m.b);
}

template <class T>
T half_trace(const BasicMobius<T>& m) {
  // A map of huge translation length (entries near 1e8) was normalised in higher precision;
  // its determinant in T is rounding noise, so take it as normalised rather than fail.
  const T det = determinant(m);
  const T scale = det > 0 && std::isfinite(det) ? std::sqrt(det) : T{1};
  return std::abs(m.a.real()) / scale;
}

template <class T>
T translation_length(const BasicMobius<T>& m) {
  const T t = half_trace(m);
  return t > T{1} ? T{2} * std::acosh(t) : T{0};
}

// The scalars with a standard library of square roots and hyperbolic functions. (T is a type
// here: it cannot be parenthesised.)
// NOLINTBEGIN(bugprone-macro-parentheses)
#define RICCI_INSTANTIATE_MOBIUS(T)                                                           \
  template T determinant(const BasicMobius<T>&);                                              \
  template BasicMobius<T> normalized(const BasicMobius<T>&);                                  \
  template BasicMobius<T> rotation<T>(T);                                                     \
  template BasicMobius<T> translation_to_origin<T>(std::complex<T>);                          \
  template T disk_distance<T>(std::complex<T>, std::complex<T>);                              \
  template BasicMobius<T> disk_isometry<T>(std::complex<T>, std::complex<T>, std::complex<T>, \
                                           std::complex<T>, T*);                              \
  template T distance_to_identity(const BasicMobius<T>&);                                     \
  template T operator_norm(const BasicMobius<T>&);                                            \
  template T half_trace(const BasicMobius<T>&);                                               \
  template T translation_length(const BasicMobius<T>&);

RICCI_INSTANTIATE_MOBIUS(double)
RICCI_INSTANTIATE_MOBIUS(long double)
// NOLINTEND(bugprone-macro-parentheses)

#undef RICCI_INSTANTIATE_MOBIUS

}  // namespace ricci
