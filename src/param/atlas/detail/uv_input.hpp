#pragma once
/// \file
/// The checks and reads of a uv layout (positions and faces indexing them) that the packer and
/// the overlap test share (internal).

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/errors.hpp"
#include "ricci/mesh/mesh.hpp"

namespace ricci::atlas_detail {

using Points = Eigen::Matrix<double, Eigen::Dynamic, 2>;

/// Refuses a non-finite position, a face index out of range, or a per-face vector (named
/// per_face_name in the message) of the wrong size; `who` names the caller.
/// \throw InvalidInput
inline void check_uv_input(const char* who, const Points& uv, const Triangles& triangles,
                           const std::vector<int>& per_face, const char* per_face_name) {
  for (Eigen::Index v = 0; v < uv.rows(); ++v) {
    if (!std::isfinite(uv(v, 0)) || !std::isfinite(uv(v, 1))) {
      throw InvalidInput(std::string(who) + ": position " + std::to_string(v) + " is not finite");
    }
  }
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (triangles(f, k) < 0 || triangles(f, k) >= uv.rows()) {
        throw InvalidInput(std::string(who) + ": face " + std::to_string(f) + " uses position " +
                           std::to_string(triangles(f, k)) + " of " + std::to_string(uv.rows()));
      }
    }
  }
  if (!per_face.empty() && static_cast<Eigen::Index>(per_face.size()) != triangles.rows()) {
    throw InvalidInput(std::string(who) + ": " + per_face_name + " has " +
                       std::to_string(per_face.size()) + " entries for " +
                       std::to_string(triangles.rows()) + " faces");
  }
}

/// Position v as a column vector.
inline Eigen::Vector2d uv_point(const Points& uv, int v) {
  return uv.row(v).transpose();
}

}  // namespace ricci::atlas_detail
