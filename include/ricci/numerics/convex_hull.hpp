#pragma once
/// \file
/// The convex hull of points in the plane, and the turn that lays its minimal-area bounding
/// rectangle onto the axes.

#include <vector>

#include <Eigen/Core>

namespace ricci {

/// Convex hull of a set of points by Andrew's monotone chain with exact orientation tests
/// (orientation_sign): counter-clockwise from the lowest-leftmost point, no collinear points, no
/// repeats. Fewer than three distinct points come back as they are, sorted and deduplicated.
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> points);

/// Rotation angle (radians, in [-pi/4, pi/4]) that turns a convex hull's minimal-area bounding
/// rectangle onto the axes. That rectangle has a side along some hull edge, so each edge
/// direction is tried; of rectangles equal in area up to rounding the smallest turn wins. 0 for
/// fewer than three points.
/// \param hull counter-clockwise convex polygon (as convex_hull returns it)
double minimal_rectangle_rotation(const std::vector<Eigen::Vector2d>& hull);

}  // namespace ricci
