#pragma once
/// \file
/// Figures read back from a layout's texture coordinates, shared by the layout, atlas and
/// pipeline tests.

#include <cmath>

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci::testing {

/// How many triangles of `t` the layout `uv` draws flipped or degenerate (signed area not > 0).
inline int count_flipped(const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv, const Triangles& t) {
  int n = 0;
  for (int f = 0; f < t.rows(); ++f) {
    const Eigen::Vector2d a = uv.row(t(f, 0)).transpose();
    const Eigen::Vector2d b = uv.row(t(f, 1)).transpose() - a;
    const Eigen::Vector2d c = uv.row(t(f, 2)).transpose() - a;
    n += !(b.x() * c.y() - b.y() * c.x() > 0);
  }
  return n;
}

/// Sum of the layout's corner angles at every copy of vertex v: the cone angle 2 pi - K read back
/// from the texture coordinates.
inline double uv_angle_sum(const Parameterization& r, int v) {
  double sum = 0;
  for (int f = 0; f < r.mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (r.mesh.triangles(f, k) != v) continue;
      const Eigen::Vector2d p = r.uv.row(r.cut_mesh.triangles(f, k)).transpose();
      const Eigen::Vector2d a = r.uv.row(r.cut_mesh.triangles(f, (k + 1) % 3)).transpose() - p;
      const Eigen::Vector2d b = r.uv.row(r.cut_mesh.triangles(f, (k + 2) % 3)).transpose() - p;
      sum += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    }
  }
  return sum;
}

}  // namespace ricci::testing
