#pragma once
/// \file
/// The background geometry a discrete metric lives in: the flat plane (the tutorial's setting) or
/// the hyperbolic plane of constant curvature -1 (THEORY.md section 9). Lengths, angles, the
/// Hessian and Gauss-Bonnet all depend on it; ricci/metric/background.hpp dispatches them.

#include <array>
#include <string>

#include "ricci/enum_names.hpp"

namespace ricci {

enum class Geometry {
  Euclidean,   ///< triangles are flat: K sums to 2 pi chi
  Hyperbolic,  ///< triangles have curvature -1: K minus the total area sums to 2 pi chi
};

/// What the flow and the admissibility checks need to know about a background.
struct GeometryTraits {
  Geometry geometry;
  const char* name;  ///< printed and parsed
  /// K is invariant under u += c: the flow fixes that gauge on closed components (the
  /// hyperbolic energy is strictly convex and has none).
  bool scale_gauge;
  /// Gauss-Bonnet reads sum K - area = 2 pi chi (area > 0) instead of sum K = 2 pi chi.
  bool area_in_gauss_bonnet;
};

/// One row per geometry, in the order of the enum.
inline constexpr std::array<GeometryTraits, 2> kGeometryTraits{{
    {Geometry::Euclidean, "euclidean", true, false},
    {Geometry::Hyperbolic, "hyperbolic", false, true},
}};

/// The row of a geometry. \throw InvalidInput for a value outside the enum
const GeometryTraits& geometry_traits(Geometry geometry);

template <>
struct EnumNames<Geometry> {
  static constexpr const char* noun = "geometry";
  static constexpr std::array<EnumName<Geometry>, 2> names{{
      {kGeometryTraits[0].geometry, kGeometryTraits[0].name},
      {kGeometryTraits[1].geometry, kGeometryTraits[1].name},
  }};
};

/// "euclidean" or "hyperbolic".
const char* geometry_name(Geometry geometry);
/// Inverse of geometry_name. \throw InvalidInput naming the string and the valid names
Geometry parse_geometry(const std::string& name);

}  // namespace ricci
