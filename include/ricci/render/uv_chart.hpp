#pragma once
/// \file
/// Where a texture layout is cut and where it is not flat: the seams (edges along which the two
/// faces disagree on their texture coordinates, and boundary edges) and the cones (interior
/// vertices on seams around which the texture angles do not add up to 2 pi).

#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// Seams and cones of a texture layout.
struct UvChart {
  /// Halfedges h = 3 f + k (the side of face f opposite its corner k, from corner k + 1 to
  /// corner k + 2) on the boundary of the texture chart: the edge has no face on the other side,
  /// more than two faces, or a neighbour whose texture coordinates at the two shared vertices
  /// differ (by index, and by value beyond 1e-12 of the largest |uv|). An interior seam edge
  /// appears once per side.
  std::vector<int> seam_halfedges;
  std::vector<int> cones;  ///< interior vertices on seams whose total texture angle is not 2 pi
  std::vector<double> cone_angles;  ///< per cone: the sum of its texture corner angles (radians)
  int seam_edges = 0;               ///< mesh edges with at least one seam halfedge
};

/// Finds the seams and cones of a texture layout.
/// \param uv_triangles #F by 3 indices into uv (per-corner texture coordinates)
/// \param uv #UV by 2 texture coordinates
/// \param cone_tolerance a vertex is a cone when |sum of its texture angles - 2 pi| exceeds this
/// \throw InvalidInput when uv_triangles has not #F rows or an index is out of range
UvChart analyse_uv_chart(const Mesh& mesh, const Triangles& uv_triangles,
                         const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                         double cone_tolerance = 1e-6);

/// Checks that uv_triangles has one row per face and that every index (mesh and texture) is in
/// range. \throw InvalidInput naming `function`, the face and the corner otherwise
void check_uv_layout(const char* function, const Mesh& mesh, const Triangles& uv_triangles,
                     const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv);

}  // namespace ricci
