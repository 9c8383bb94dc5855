#pragma once
// Private to the mesh module: the zero-area test that find_defects reports and repair_mesh's
// sliver removal answers, in one place so that the two always agree on which faces it holds for.

#include <algorithm>

#include <Eigen/Geometry>

#include "ricci/mesh/mesh.hpp"

namespace ricci::mesh_detail {

/// Twice the area of triangle (a, b, c) and its longest edge squared.
struct AreaMeasure {
  double twice_area = 0;
  double longest_squared = 0;
};

inline AreaMeasure area_measure(const Positions& P, int a, int b, int c) {
  const Eigen::Vector3d pa = P.row(a).transpose(), pb = P.row(b).transpose(),
                        pc = P.row(c).transpose();
  return {(pb - pa).cross(pc - pa).norm(),
          std::max({(pb - pa).squaredNorm(), (pc - pb).squaredNorm(), (pa - pc).squaredNorm()})};
}

/// Zero area: twice the area at most `tolerance` times the longest edge squared (the sine of the
/// largest angle below `tolerance`), so that the test does not depend on the mesh's scale.
inline bool is_zero_area(const AreaMeasure& m, double tolerance) {
  return !(m.twice_area > tolerance * m.longest_squared);
}

inline bool is_zero_area(const Positions& P, int a, int b, int c, double tolerance) {
  return is_zero_area(area_measure(P, a, b, c), tolerance);
}

}  // namespace ricci::mesh_detail
