#pragma once
/// \file
/// Spherical background geometry (curvature +1): the spherical law of cosines for a geodesic
/// triangle on the unit sphere. The sphere map (ricci/sphere/sphere.hpp) does not call it (it
/// takes a spherical triangle's area from the triple product of its corners); its tests check
/// those areas against the angle sums computed here.

namespace ricci {

/// Angle opposite side a of a geodesic triangle on the unit sphere with arc lengths a, b, c, by
/// the half-angle form of the spherical law of cosines,
///     tan(A / 2) = sqrt(sin(s - b) sin(s - c) / (sin s sin(s - a))),  s = (a + b + c) / 2,
/// accurate for tiny and near-pi angles (acos of (cos a - cos b cos c) / (sin b sin c) is not).
/// NaN when a side is not positive, a triangle inequality fails, or the perimeter reaches 2 pi.
double spherical_angle_from_lengths(double a, double b, double c);

}  // namespace ricci
