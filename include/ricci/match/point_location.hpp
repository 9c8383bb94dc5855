#pragma once
/// \file
/// Point location in a canonical domain (issue 29): which face of a triangulation holds a point,
/// and where in it. Two domains: triangles in the plane (the unit disk, a flat torus's layout)
/// and chordal triangles inscribed in the unit sphere, which hold the points of the sphere
/// radially above them (the central projection is the sphere map's own reading of a face).
///
/// Both locators bucket the faces in a uniform grid of about one face per cell, so a query costs
/// a few face tests. A point no face holds (outside a polygonal disk's boundary, in a crack
/// between faces rounded apart) gets the face that comes nearest, its negative weights clamped
/// to 0: `inside` is false then and `outside_by` says by how much it missed.

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// Where a point lies: a face and its barycentric weights (non-negative, summing to 1).
struct FaceLocation {
  int face = -1;
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();
  bool inside = false;    ///< the face holds the point (smallest raw weight >= -1e-9)
  double outside_by = 0;  ///< -(smallest raw weight) of the face kept when not inside; 0 inside
};

/// Faces of a planar triangulation in a grid. \pre faces counter-clockwise or not: weights are
/// ratios of signed areas, right for either orientation; degenerate faces are never chosen.
class PlanarLocator {
 public:
  /// \param points #P by 2; \param triangles #F by 3 indices into points
  /// \throw InvalidInput on an index out of range, a non-finite point or no faces
  PlanarLocator(const Eigen::Matrix<double, Eigen::Dynamic, 2>& points, const Triangles& triangles);
  FaceLocation locate(const Eigen::Vector2d& point) const;
  Eigen::Vector2d lower() const { return lower_; }  ///< the bounding box of the points
  Eigen::Vector2d upper() const { return upper_; }

 private:
  Eigen::Vector3d raw_weights(int face, const Eigen::Vector2d& point) const;
  int cell_index(int ix, int iy) const { return iy * nx_ + ix; }
  Eigen::Matrix<double, Eigen::Dynamic, 2> points_;
  Triangles triangles_;
  Eigen::Vector2d lower_, upper_;
  double cell_size_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<int> cell_start_,
      cell_faces_;  ///< faces of cell c: cell_faces_[start[c], start[c+1])
};

/// Chordal triangles with vertices on the unit sphere, in a grid over the cube [-1, 1]^3.
/// A point p of the sphere is in face (P_i, P_j, P_k) when p = c_i P_i + c_j P_j + c_k P_k with
/// every c >= 0 (the ray from the origin through p crosses the triangle); the weights are the
/// c normalised to sum 1 (the crossing point's barycentric coordinates).
class SphereLocator {
 public:
  /// \param points #P by 3 on the unit sphere; \param triangles #F by 3 indices into points
  /// \throw InvalidInput as PlanarLocator
  SphereLocator(const Positions& points, const Triangles& triangles);
  /// \param point any non-zero vector (its direction is located)
  FaceLocation locate(const Eigen::Vector3d& point) const;

 private:
  Eigen::Vector3d raw_weights(int face, const Eigen::Vector3d& point) const;
  Positions points_;
  Triangles triangles_;
  int n_ = 1;  ///< cells per axis
  std::vector<int> cell_start_, cell_faces_;
};

}  // namespace ricci
