#pragma once
/// \file
/// How good a parameterization is (THEORY.md section 8): area and angle distortion of the map
/// from the 3D triangles to their layout, flipped faces, cones, seam length.

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// Distortion figures of a parameterization.
///
/// Areas: Abar_f is the area of face f in R^3 and A_f its *signed* layout area (positive when the
/// layout keeps the triangle counter-clockwise). Both are normalised to total area 1: Abar_f by
/// the total 3D area, A_f by the sum of |A_f| over the faces with a finite layout area (for a
/// layout without flips this is the layout's total area). Degenerate faces (A_f == 0 or not
/// finite) enter the energy with A_f = 0; they and the flipped faces are left out of the log and
/// angle statistics. Means and standard deviations are weighted by the normalised 3D area Abar_f
/// of the faces they include (so that they do not depend on how finely the mesh is meshed); when
/// no face qualifies, these statistics are NaN.
struct Distortion {
  /// Area distortion energy of the tutorial's eq. 9: sum over faces of (A/Abar - 1)^2 Abar with
  /// the layout area A and the 3D area Abar, both meshes scaled to total area 1. A is signed, so a
  /// flipped face costs more than any unflipped one (at least Abar). 0 when the layout scales
  /// every face by the same factor.
  double area_distortion_energy = 0;
  /// ln(A/Abar) per face over the faces with A > 0: min, max, Abar-weighted mean and standard
  /// deviation (the population one: sqrt of the weighted mean of squared deviations).
  double log_area_min = 0, log_area_max = 0, log_area_mean = 0, log_area_stddev = 0;
  /// sigma_max / sigma_min of the linear map from each 3D triangle (in its own plane) to its
  /// layout (1: conformal, also for a mirror image): Abar-weighted mean and max over the faces
  /// with A != 0 (flipped faces included: their ratio is well defined).
  double angle_distortion_mean = 0, angle_distortion_max = 0;
  int flipped_faces = 0;     ///< layout signed area < 0
  int degenerate_faces = 0;  ///< layout signed area == 0 (or not finite)
  double surface_area = 0;   ///< total 3D area, before normalisation
  double layout_area = 0;    ///< sum of |A_f| over the faces with finite A_f, before normalisation
};

/// Measures a layout against the 3D mesh (THEORY.md section 8). The figures do not change when
/// the layout is scaled, rotated, translated or mirrored (the mirror flips every face, though).
/// \param mesh 3D positions (#V by 3) and triangles (#F by 3)
/// \param uv_triangles #F by 3 indices into uv (per-corner texture coordinates): corner c of
///        face f of the mesh lies at uv.row(uv_triangles(f, c)) in the layout
/// \param uv #UV by 2 layout positions (non-finite rows make their faces degenerate)
/// \pre every 3D face has a finite, non-zero area
/// \throw InvalidInput naming the mismatch when uv_triangles has not #F rows, the mesh has no
///        faces, an index is out of range, or a 3D face has zero or non-finite area
Distortion measure_distortion(const Mesh& mesh, const Triangles& uv_triangles,
                              const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv);

/// The per-face figures behind Distortion, for pictures and viewers that colour faces by them.
struct FaceDistortion {
  /// #F values ln(|A_f| / Abar_f), both areas normalised as in Distortion (flipped faces by the
  /// size of their layout area); NaN where the layout area is zero or not finite, or where the 3D
  /// area is.
  Eigen::VectorXd log_area;
  /// #F values sigma_max / sigma_min (>= 1) of the linear map from the 3D triangle to its layout,
  /// as in Distortion; NaN where log_area is.
  Eigen::VectorXd angle;
  /// #F flags: 1 where the layout triangle is flipped (signed area < 0), else 0.
  std::vector<char> flipped;
};

/// Measures every face of a layout: the values whose statistics measure_distortion reports.
/// Unlike measure_distortion it accepts faces of zero 3D area (their values are NaN).
/// \param mesh, uv_triangles, uv as measure_distortion
/// \throw InvalidInput naming the mismatch when uv_triangles has not #F rows, the mesh has no
///        faces, an index is out of range, or the total 3D area is zero or not finite
FaceDistortion measure_face_distortion(const Mesh& mesh, const Triangles& uv_triangles,
                                       const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv);

}  // namespace ricci
