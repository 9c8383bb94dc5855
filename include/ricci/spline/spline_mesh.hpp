#pragma once
/// \file
/// A Powell-Sabin spline written as triangle meshes: the surface evaluated on a K x K lattice of
/// every quadratic piece, and the control net of Bezier ordinates (the K = 2 lattice with the
/// ordinates in place of the values). Lattice points are shared along piece and face edges (keyed
/// by the mesh vertices, edge split points and face split points they combine), so both meshes
/// are connected where the domain is.

#include <vector>

#include <Eigen/Core>

#include "ricci/spline/powell_sabin.hpp"

namespace ricci {

/// A lattice over the pieces of every face.
struct SplineTessellation {
  Eigen::MatrixXd values;  ///< #P by k: the spline (or the ordinates, for the control net)
  Triangles triangles;     ///< #T by 3 indices into the points, counter-clockwise in the charts
  std::vector<int> face;   ///< #P: a face holding the point (the first that produced it)
  Eigen::Matrix<double, Eigen::Dynamic, 3> barycentric;  ///< #P: its coordinates in that face
};

/// The spline evaluated on every piece subdivided `refine` x `refine` (refine^2 triangles per
/// piece, 6 refine^2 per face).
/// \throw InvalidInput when refine < 1 or the ordinates do not have 19 #F rows
SplineTessellation tessellate_spline(const SplineDomain& domain, const Eigen::MatrixXd& ordinates,
                                     int refine);

/// The control net: the ordinates as points (19 per face, those on mesh edges and vertices
/// shared), each piece's 6 ordinates joined as 4 triangles.
/// \throw InvalidInput when the ordinates do not have 19 #F rows
SplineTessellation spline_control_net(const SplineDomain& domain, const Eigen::MatrixXd& ordinates);

}  // namespace ricci
