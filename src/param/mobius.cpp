#include "ricci/param/mobius.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;

/// 1 - |z|^2 without the cancellation of 1 - (x^2 + y^2) near the circle.
double one_minus_norm2(Complex z) {
  const double r = std::abs(z);  // hypot: no overflow, correctly rounded to an ulp or so
  return (1.0 - r) * (1.0 + r);
}

void check_inside(const char* fn, Complex z, const char* name) {
  if (!std::isfinite(z.real()) || !std::isfinite(z.imag()) || !(std::abs(z) < 1.0)) {
    throw InvalidInput(std::string(fn) + ": " + name + " = (" + std::to_string(z.real()) + ", " +
                       std::to_string(z.imag()) + ") is not inside the unit circle");
  }
}

}  // namespace

Complex apply_mobius(const Mobius& m, Complex z) {
  return (m.a * z + m.b) / (std::conj(m.b) * z + std::conj(m.a));
}

Mobius compose(const Mobius& f, const Mobius& g) {
  // [[a1, b1], [b1*, a1*]] [[a2, b2], [b2*, a2*]]: the product keeps the SU(1,1) shape.
  return {f.a * g.a + f.b * std::conj(g.b), f.a * g.b + f.b * std::conj(g.a)};
}

Mobius inverse(const Mobius& m) {
  return {std::conj(m.a), -m.b};
}

Mobius power(const Mobius& m, int k) {
  Mobius base = k < 0 ? inverse(m) : m;
  // Unsigned magnitude: -INT_MIN overflows an int.
  unsigned long long n = k < 0 ? -static_cast<long long>(k) : static_cast<long long>(k);
  Mobius result;
  while (n > 0) {
    if (n & 1U) result = compose(result, base);
    base = compose(base, base);
    n >>= 1U;
  }
  return result;
}

double determinant(const Mobius& m) {
  const double p = std::abs(m.a), q = std::abs(m.b);
  return (p - q) * (p + q);
}

Mobius normalized(const Mobius& m) {
  const double det = determinant(m);
  if (!(det > 0) || !std::isfinite(det)) {
    throw InvalidInput("normalized: the Moebius map has determinant " + std::to_string(det) +
                       " (|a|^2 - |b|^2 must be positive and finite)");
  }
  const double s = (m.a.real() < 0 ? -1.0 : 1.0) / std::sqrt(det);
  return {s * m.a, s * m.b};
}

Mobius rotation(double angle) {
  return {std::polar(1.0, 0.5 * angle), 0.0};
}

Mobius translation_to_origin(Complex z) {
  check_inside("translation_to_origin", z, "z");
  const double s = 1.0 / std::sqrt(one_minus_norm2(z));
  return {Complex(s, 0.0), -s * z};
}

double disk_distance(Complex z, Complex w) {
  const double dz = one_minus_norm2(z), dw = one_minus_norm2(w);
  if (!(dz > 0) || !(dw > 0)) return std::numeric_limits<double>::infinity();
  return 2.0 * std::asinh(std::abs(z - w) / std::sqrt(dz * dw));
}

Mobius disk_isometry(Complex z1, Complex z2, Complex w1, Complex w2, double* relative_mismatch) {
  const char* fn = "disk_isometry";
  check_inside(fn, z1, "z1");
  check_inside(fn, z2, "z2");
  check_inside(fn, w1, "w1");
  check_inside(fn, w2, "w2");
  if (z1 == z2) throw InvalidInput(std::string(fn) + ": z1 = z2 gives no direction");
  if (w1 == w2) throw InvalidInput(std::string(fn) + ": w1 = w2 gives no direction");
  const Mobius from = translation_to_origin(z1), to = translation_to_origin(w1);
  // At the origin geodesics are straight: the directions are the arguments of the images.
  const Complex u = apply_mobius(from, z2), v = apply_mobius(to, w2);
  const Complex turn = (v / std::abs(v)) / (u / std::abs(u));
  const Mobius spin{std::sqrt(turn), 0.0};  // a / conj(a) = turn
  const Mobius map = normalized(compose(inverse(to), compose(spin, from)));
  if (relative_mismatch) {
    const double d1 = disk_distance(z1, z2), d2 = disk_distance(w1, w2);
    const double scale = std::max(d1, d2);
    *relative_mismatch = scale > 0 ? std::abs(d1 - d2) / scale : 0.0;
  }
  return map;
}

double distance_to_identity(const Mobius& m) {
  const Mobius n = normalized(m);
  const double off = std::abs(n.b);
  return std::min(std::max(std::abs(n.a - 1.0), off), std::max(std::abs(n.a + 1.0), off));
}

double operator_norm(const Mobius& m) {
  return std::abs(m.a) + std::abs(m.b);
}

double half_trace(const Mobius& m) {
  // A map of huge translation length (entries near 1e8) was normalised in higher precision;
  // its double determinant is rounding noise, so take it as normalised rather than fail.
  const double det = determinant(m);
  const double scale = det > 0 && std::isfinite(det) ? std::sqrt(det) : 1.0;
  return std::abs(m.a.real()) / scale;
}

double translation_length(const Mobius& m) {
  const double t = half_trace(m);
  return t > 1.0 ? 2.0 * std::acosh(t) : 0.0;
}

}  // namespace ricci
