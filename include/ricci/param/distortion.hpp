#pragma once
/// \file
/// How good a parameterization is (THEORY.md section 8): area and angle distortion of the map
/// from the 3D triangles to their layout, flipped faces, cones, seam length.

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// Distortion figures of a parameterization.
struct Distortion {
  /// Area distortion energy of the tutorial's eq. 9: sum over faces of (A/Abar - 1)^2 Abar with
  /// the layout area A and the 3D area Abar, both meshes scaled to total area 1.
  double area_distortion_energy = 0;
  double log_area_min = 0, log_area_max = 0, log_area_mean = 0, log_area_stddev = 0;
  /// sigma_max / sigma_min of the linear map from each 3D triangle to its layout (1: conformal).
  double angle_distortion_mean = 0, angle_distortion_max = 0;
  int flipped_faces = 0;     ///< layout signed area < 0
  int degenerate_faces = 0;  ///< layout signed area == 0 (or not finite)
};

/// Measures a layout against the 3D mesh.
/// \param mesh 3D positions and triangles (#F by 3)
/// \param uv_triangles #F by 3 indices into uv (per-corner texture coordinates)
/// \param uv #UV by 2 layout positions
Distortion measure_distortion(const Mesh& mesh, const Triangles& uv_triangles,
                              const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv);

}  // namespace ricci
