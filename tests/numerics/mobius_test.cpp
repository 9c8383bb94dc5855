// Moebius maps of the Poincare disk: group laws, isometry, disk_isometry, the distance's
// accuracy for close points and near the boundary; the long double maps and the frames.

#include "ricci/numerics/mobius.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;

/// A random map moving the origin by up to hyperbolic distance 2 atanh(0.9) (about 2.9).
Mobius random_map(std::mt19937& random) {
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi),
      radius(0.0, 0.9);
  const Complex w = std::polar(radius(random), angle(random));
  return compose(inverse(translation_to_origin(w)), rotation(angle(random)));
}

Complex random_point(std::mt19937& random, double max_radius = 0.95) {
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi), unit(0.0, 1.0);
  return std::polar(max_radius * std::sqrt(unit(random)), angle(random));
}

/// A random map f, two random points and their images, drawn in that order.
struct MappedPair {
  Mobius f;
  Complex z1, z2, w1, w2;  ///< w = f(z)
};

MappedPair random_mapped_pair(std::mt19937& random) {
  MappedPair p;
  p.f = random_map(random);
  p.z1 = random_point(random);
  p.z2 = random_point(random);
  p.w1 = apply_mobius(p.f, p.z1);
  p.w2 = apply_mobius(p.f, p.z2);
  return p;
}

/// 2 atanh(|z - w| / |1 - conj(z) w|) in long double: an independent reference, accurate for
/// close points (atanh of a small argument), not for points near the circle.
double reference_distance(Complex z, Complex w) {
  using L = long double;
  const L zr = z.real(), zi = z.imag(), wr = w.real(), wi = w.imag();
  const L num = std::hypot(zr - wr, zi - wi);
  const L den = std::hypot(1.0L - (zr * wr + zi * wi), -(zr * wi - zi * wr));
  return static_cast<double>(2.0L * std::atanh(num / den));
}

TEST(Mobius, ComposeIsApplicationAfterApplication) {
  std::mt19937 random(1);
  for (int trial = 0; trial < 200; ++trial) {
    const Mobius f = random_map(random), g = random_map(random);
    const Complex z = random_point(random);
    EXPECT_LT(std::abs(apply_mobius(compose(f, g), z) - apply_mobius(f, apply_mobius(g, z))),
              1e-13);
    EXPECT_NEAR(determinant(compose(f, g)), 1.0, 1e-13);
  }
}

TEST(Mobius, GroupLaws) {
  std::mt19937 random(2);
  for (int trial = 0; trial < 200; ++trial) {
    const Mobius f = random_map(random), g = random_map(random), h = random_map(random);
    const Mobius left = compose(compose(f, g), h), right = compose(f, compose(g, h));
    EXPECT_LT(distance_to_identity(compose(left, inverse(right))), 1e-12);
    EXPECT_LT(distance_to_identity(compose(f, inverse(f))), 1e-13);
    EXPECT_LT(distance_to_identity(compose(inverse(f), f)), 1e-13);
    EXPECT_LT(distance_to_identity(compose(inverse(compose(f, g)), compose(f, g))), 1e-12);
    // (f g)^-1 = g^-1 f^-1
    EXPECT_LT(distance_to_identity(compose(inverse(compose(f, g)), compose(f, g))), 1e-12);
    EXPECT_LT(distance_to_identity(compose(compose(inverse(g), inverse(f)), compose(f, g))), 1e-12);
    // Powers: f^3 f^-3 = I, f^2 = f f, f^0 = I.
    EXPECT_LT(distance_to_identity(compose(power(f, 3), power(f, -3))), 1e-11);
    EXPECT_LT(distance_to_identity(compose(power(f, 2), inverse(compose(f, f)))), 1e-12);
    EXPECT_EQ(distance_to_identity(power(f, 0)), 0.0);
  }
  EXPECT_EQ(distance_to_identity(Mobius{}), 0.0);
  EXPECT_EQ(distance_to_identity(Mobius{-1.0, 0.0}), 0.0);  // -I is the identity map
  EXPECT_NEAR(distance_to_identity(rotation(1e-3)), std::abs(std::polar(1.0, 5e-4) - 1.0), 1e-16);
}

TEST(Mobius, NormalizedRestoresDeterminantOneAndFixesTheSign) {
  const Mobius m = translation_to_origin({0.3, -0.4});
  const Mobius scaled{-2.5 * m.a, -2.5 * m.b};
  const Mobius n = normalized(scaled);
  EXPECT_NEAR(determinant(n), 1.0, 1e-15);
  EXPECT_GE(n.a.real(), 0.0);
  EXPECT_LT(std::abs(n.a - m.a) + std::abs(n.b - m.b), 1e-15);
  EXPECT_THROW(normalized(Mobius{0.5, 1.0}), InvalidInput);
  EXPECT_THROW(normalized(Mobius{1.0, 1.0}), InvalidInput);
}

TEST(Mobius, MapsPreserveTheDiskAndTheDistance) {
  std::mt19937 random(3);
  for (int trial = 0; trial < 500; ++trial) {
    const auto [f, z, w, fz, fw] = random_mapped_pair(random);
    EXPECT_LT(std::abs(fz), 1.0);
    const double d = disk_distance(z, w);
    EXPECT_NEAR(disk_distance(fz, fw), d, 1e-11 * std::max(1.0, d));
    // The unit circle maps onto itself.
    EXPECT_NEAR(std::abs(apply_mobius(f, std::polar(1.0, 0.1 * trial))), 1.0, 1e-14);
  }
}

TEST(Mobius, TranslationToOriginAndTranslationLength) {
  const Complex z(0.6, -0.3);
  const Mobius t = translation_to_origin(z);
  EXPECT_LT(std::abs(apply_mobius(t, z)), 1e-16);
  EXPECT_NEAR(determinant(t), 1.0, 1e-15);
  // The translation moves the origin to -z: distance d(0, z), which is its translation length.
  EXPECT_NEAR(disk_distance(0.0, apply_mobius(t, 0.0)), disk_distance(0.0, z), 1e-14);
  EXPECT_NEAR(translation_length(t), disk_distance(0.0, z), 1e-13);
  EXPECT_GT(half_trace(t), 1.0);
  EXPECT_LT(half_trace(rotation(1.0)), 1.0);
  EXPECT_EQ(translation_length(rotation(1.0)), 0.0);
  EXPECT_THROW(translation_to_origin({1.0, 0.0}), InvalidInput);
  EXPECT_THROW(translation_to_origin({std::nan(""), 0.0}), InvalidInput);
}

TEST(Mobius, DiskIsometryIsExactOnRandomPairs) {
  std::mt19937 random(5);
  for (int trial = 0; trial < 500; ++trial) {
    const auto [f, z1, z2, w1, w2] = random_mapped_pair(random);
    double mismatch = -1;
    const Mobius g = disk_isometry(z1, z2, w1, w2, &mismatch);
    // Exact at z1, relative to the local scale 1 - |w1|^2 of the disk there.
    EXPECT_LT(std::abs(apply_mobius(g, z1) - w1), 1e-14 * std::max(1.0, 1.0 / (1 - std::norm(w1))));
    EXPECT_LT(disk_distance(apply_mobius(g, z1), w1), 1e-12);
    EXPECT_LT(disk_distance(apply_mobius(g, z2), w2), 1e-12 * std::max(1.0, disk_distance(z1, z2)));
    EXPECT_LT(mismatch, 1e-13);
    EXPECT_LT(distance_to_identity(compose(inverse(f), g)), 1e-11);  // the same map
  }
}

TEST(Mobius, DiskIsometryMatchesTheDirectionAndReportsTheMismatch) {
  std::mt19937 random(6);
  for (int trial = 0; trial < 200; ++trial) {
    const Complex z1 = random_point(random, 0.8), z2 = random_point(random, 0.8);
    const Complex w1 = random_point(random, 0.8), w2 = random_point(random, 0.8);
    double mismatch = -1;
    const Mobius g = disk_isometry(z1, z2, w1, w2, &mismatch);
    EXPECT_LT(disk_distance(apply_mobius(g, z1), w1), 1e-12);
    // g(z2) lies on the geodesic ray from w1 through w2: d(w1, g z2) + d(g z2, w2) or
    // |d(w1, g z2) - d(g z2, w2)| equals d(w1, w2).
    const double d1 = disk_distance(z1, z2), d2 = disk_distance(w1, w2);
    const Complex gz2 = apply_mobius(g, z2);
    EXPECT_NEAR(disk_distance(w1, gz2), d1, 1e-11 * std::max(1.0, d1));
    EXPECT_NEAR(disk_distance(gz2, w2), std::abs(d1 - d2), 1e-10 * std::max(1.0, d1));
    EXPECT_NEAR(mismatch, std::abs(d1 - d2) / std::max(d1, d2), 1e-12);
  }
  EXPECT_THROW(disk_isometry(0.1, 0.1, 0.0, 0.5), InvalidInput);
  EXPECT_THROW(disk_isometry(0.1, 0.2, 0.0, 1.5), InvalidInput);
}

TEST(Mobius, DistanceOfClosePointsHasFullRelativeAccuracy) {
  // On the real axis with exact differences: d = log1p(2 (w - z) / ((1 - w)(1 + z))), z < w.
  const double delta = std::ldexp(1.0, -30);  // about 9.3e-10
  for (double z : {0.0, 0.25, -0.5, 0.75, 0.96875}) {
    const double w = z + delta;  // exact: z has few bits
    const double expected = std::log1p(2 * delta / ((1 - w) * (1 + z)));
    EXPECT_NEAR(disk_distance(z, w), expected, 4e-16 * expected) << "z = " << z;
    EXPECT_NEAR(disk_distance(w, z), expected, 4e-16 * expected);
  }
  // Anywhere in the disk, against the long-double atanh form.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  for (int trial = 0; trial < 500; ++trial) {
    const Complex z = random_point(random);
    const Complex w = z + std::polar(1e-9, angle(random));
    const double expected = reference_distance(z, w);
    EXPECT_NEAR(disk_distance(z, w), expected, 1e-14 * expected);
  }
}

TEST(Mobius, DistanceNearTheBoundary) {
  // 1 - z exact for z = 1 - 2^-k; d = log((1 + z)(1 - w) / ((1 - z)(1 + w))) for w < z.
  for (int k : {20, 30, 40, 50}) {
    const double z = 1 - std::ldexp(1.0, -k), w = 1 - std::ldexp(1.0, -k + 1);
    const double expected = std::log1p(2 * (z - w) / ((1 - z) * (1 + w)));  // about ln 2
    EXPECT_NEAR(disk_distance(z, w), expected, 1e-15 * expected) << "k = " << k;
    // Across the disk: 2 atanh(z) + 2 atanh(z) = 2 ln((1 + z) / (1 - z)).
    const double across = 2 * std::log((1 + z) / (1 - z));
    EXPECT_NEAR(disk_distance(z, -z), across, 1e-15 * across);
    EXPECT_NEAR(disk_distance(Complex(0, z), Complex(0, -z)), across, 1e-15 * across);
  }
  EXPECT_TRUE(std::isinf(disk_distance(1.0, 0.0)));
}

/// As random_map, in long double (the angles and radius drawn in double, then widened).
WideMobius random_wide_map(std::mt19937& random) {
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi),
      radius(0.0, 0.9);
  const std::complex<long double> w = std::polar<long double>(radius(random), angle(random));
  return compose(inverse(translation_to_origin<long double>(w)),
                 rotation<long double>(angle(random)));
}

TEST(WideMobius, GroupLawsToLongDoublePrecision) {
  // Bounds a thousandfold below the double ones above: the same arithmetic, 11 more bits.
  std::mt19937 random(8);
  using WideComplex = std::complex<long double>;
  for (int trial = 0; trial < 200; ++trial) {
    const WideMobius f = random_wide_map(random), g = random_wide_map(random);
    const Complex z0 = random_point(random);
    const WideComplex z(z0.real(), z0.imag());
    EXPECT_LT(std::abs(apply_mobius(compose(f, g), z) - apply_mobius(f, apply_mobius(g, z))),
              1e-16L);
    EXPECT_LT(std::abs(determinant(compose(f, g)) - 1.0L), 1e-16L);
    EXPECT_LT(distance_to_identity(compose(f, inverse(f))), 1e-16L);
    EXPECT_LT(distance_to_identity(compose(compose(inverse(g), inverse(f)), compose(f, g))),
              1e-15L);
    // The translation of z to the origin, and the frame centred at z, agree.
    const WideMobius t = translation_to_origin<long double>(z);
    EXPECT_LT(std::abs(apply_mobius(t, z)), 1e-19L);
    const WideComplex w = apply_mobius(g, WideComplex{0.25L, -0.5L});
    EXPECT_LT(std::abs(to_frame(z, w) - apply_mobius(t, w)), 1e-17L);
    EXPECT_LT(std::abs(from_frame(z, to_frame(z, w)) - w), 1e-17L);
  }
  EXPECT_THROW(translation_to_origin<long double>({1.0L, 0.0L}), InvalidInput);
  EXPECT_THROW(normalized(WideMobius{0.5L, 1.0L}), InvalidInput);
}

TEST(Mobius, CastRoundsEachPart) {
  const WideMobius wide = translation_to_origin<long double>({0.3L, -0.4L});
  const Mobius rounded = mobius_cast<double>(wide);
  const Mobius direct = translation_to_origin({0.3, -0.4});
  EXPECT_EQ(rounded.a.real(), static_cast<double>(wide.a.real()));
  EXPECT_EQ(rounded.b.imag(), static_cast<double>(wide.b.imag()));
  // Widening is exact, so the round trip gives the double map back bit for bit.
  const Mobius back = mobius_cast<double>(mobius_cast<long double>(direct));
  EXPECT_EQ(back.a, direct.a);
  EXPECT_EQ(back.b, direct.b);
  EXPECT_LT(std::abs(rounded.a - direct.a) + std::abs(rounded.b - direct.b), 1e-15);
}

TEST(Mobius, FramesAreTheTranslationToTheOrigin) {
  std::mt19937 random(9);
  for (int trial = 0; trial < 200; ++trial) {
    const Complex p = random_point(random), z = random_point(random);
    EXPECT_LT(std::abs(to_frame(p, z) - apply_mobius(translation_to_origin(p), z)), 1e-13);
    EXPECT_LT(std::abs(from_frame(p, to_frame(p, z)) - z), 1e-13);
    EXPECT_EQ(to_frame(p, p), Complex(0.0));  // p - p is exact
  }
}

}  // namespace
}  // namespace ricci
