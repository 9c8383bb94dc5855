#pragma once
/// \file
/// Exact geometric predicates in the plane: the orientation of three points, and whether two
/// triangles' interiors meet. Exact unless a product of two coordinates underflows (a
/// floating-point filter first, expansion arithmetic where the filter cannot decide).

#include <array>

#include <Eigen/Core>

namespace ricci {

/// Sign of the orientation of (a, b, c): +1 counter-clockwise, -1 clockwise, 0 collinear, exact
/// unless a product of two coordinates underflows (Shewchuk's filter, then expansion arithmetic).
int orientation_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c);

/// Whether the interiors of two triangles intersect (either orientation; a triangle of zero area
/// has no interior; triangles that only touch along an edge or at a point do not overlap).
bool triangles_overlap(const std::array<Eigen::Vector2d, 3>& a,
                       const std::array<Eigen::Vector2d, 3>& b);

/// triangles_overlap for triangles already known to be counter-clockwise with nonzero area (the
/// orientation test skipped): their interiors are disjoint if and only if an edge line of one has
/// all of the other on its closed outer side (the separating axes of two convex polygons are
/// among their edge normals).
/// \pre orientation_sign(a[0], a[1], a[2]) > 0 and orientation_sign(b[0], b[1], b[2]) > 0
bool ccw_triangles_overlap(const std::array<Eigen::Vector2d, 3>& a,
                           const std::array<Eigen::Vector2d, 3>& b);

}  // namespace ricci
