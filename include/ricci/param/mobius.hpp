#pragma once
/// \file
/// Orientation-preserving isometries of the Poincare disk (Moebius maps in SU(1,1)) and the
/// hyperbolic distance (curvature -1). A map is stored as the matrix [[a, b], [conj b, conj a]]
/// with det = |a|^2 - |b|^2 = 1, acting by z -> (a z + b) / (conj(b) z + conj(a)); M and -M are
/// the same map. Composition is the matrix product, so every function here keeps the SU(1,1)
/// shape exactly (up to rounding of the determinant, which `normalized` restores).

#include <complex>

namespace ricci {

/// A Moebius map of the unit disk onto itself, z -> (a z + b) / (conj(b) z + conj(a)).
/// \pre |a|^2 - |b|^2 = 1 (see `normalized`); the default is the identity
struct Mobius {
  std::complex<double> a{1.0};
  std::complex<double> b{0.0};
};

/// M(z). Points of the closed disk map into the closed disk; z on the unit circle stays on it.
/// (Not named `apply`: argument-dependent lookup on std::complex would find std::apply.)
std::complex<double> apply_mobius(const Mobius& m, std::complex<double> z);

/// f after g: z -> f(g(z)) (the matrix product F G).
Mobius compose(const Mobius& f, const Mobius& g);

/// The inverse map (matrix [[conj a, -b], [-conj b, a]]).
Mobius inverse(const Mobius& m);

/// m^k for any integer k (k < 0: powers of the inverse), by repeated squaring.
Mobius power(const Mobius& m, int k);

/// |a|^2 - |b|^2, computed as (|a| - |b|)(|a| + |b|): 1 for a valid map.
double determinant(const Mobius& m);

/// m scaled to determinant 1, sign fixed so that Re a >= 0 (M and -M are one map).
/// \throw InvalidInput (naming normalized) when the determinant is not positive and finite
Mobius normalized(const Mobius& m);

/// The rotation z -> e^{i angle} z about the origin.
Mobius rotation(double angle);

/// The isometry moving z to the origin along the geodesic through both,
/// w -> (w - z) / (1 - conj(z) w).
/// \throw InvalidInput when |z| >= 1 or z is not finite
Mobius translation_to_origin(std::complex<double> z);

/// Hyperbolic distance between two points of the open disk, 2 asinh(|z - w| /
/// sqrt((1 - |z|^2)(1 - |w|^2))): full relative accuracy for close points (acosh of a number near
/// 1 loses half the digits) and near the boundary (1 - |z|^2 computed as (1 - |z|)(1 + |z|)).
/// Returns +inf when a point is on or outside the unit circle.
double disk_distance(std::complex<double> z, std::complex<double> w);

/// The orientation-preserving isometry taking z1 to w1 and the geodesic direction from z1 towards
/// z2 to the direction from w1 towards w2 (exact at z1 up to rounding). It takes z2 to w2 only
/// when d(z1, z2) = d(w1, w2); the optional `relative_mismatch` receives
/// |d(z1, z2) - d(w1, w2)| / max(d(z1, z2), d(w1, w2)) (the hyperbolic distance between the image
/// of z2 and w2, relative to the distance matched; 0 when both distances are 0).
/// \throw InvalidInput when a point is not inside the unit circle or z1 = z2 or w1 = w2
Mobius disk_isometry(std::complex<double> z1, std::complex<double> z2, std::complex<double> w1,
                     std::complex<double> w2, double* relative_mismatch = nullptr);

/// How far a map is from the identity: after `normalized`, min(max(|a - 1|, |b|),
/// max(|a + 1|, |b|)), the max-norm of M - I or of M + I. Rounding makes a product of maps of
/// operator norm N_1 ... N_k differ from the identity by about 1e-16 N_1 ... N_k.
double distance_to_identity(const Mobius& m);

/// Operator norm of the matrix (its largest singular value, |a| + |b| >= 1 for a valid map).
double operator_norm(const Mobius& m);

/// |trace| / 2 = |Re a| (normalised): > 1 hyperbolic, = 1 parabolic, < 1 elliptic.
double half_trace(const Mobius& m);

/// Translation length of a hyperbolic map, 2 acosh(|Re a|) after normalisation (0 when not
/// hyperbolic): how far it moves the points of its axis.
double translation_length(const Mobius& m);

}  // namespace ricci
