#pragma once
/// \file
/// The background geometry a discrete metric lives in: the flat plane (the tutorial's setting) or
/// the hyperbolic plane of constant curvature -1 (THEORY.md section 9). Lengths, angles, the
/// Hessian and Gauss-Bonnet all depend on it.

#include <string>

namespace ricci {

enum class Geometry {
  Euclidean,   ///< triangles are flat: K sums to 2 pi chi
  Hyperbolic,  ///< triangles have curvature -1: K minus the total area sums to 2 pi chi
};

/// "euclidean" or "hyperbolic".
const char* geometry_name(Geometry geometry);
/// Inverse of geometry_name. \throw InvalidInput naming the string and the valid names
Geometry parse_geometry(const std::string& name);

}  // namespace ricci
