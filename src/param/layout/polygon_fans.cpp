#include "ricci/param/layout/polygon_fans.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace ricci {
namespace {

/// Twice the signed area of the uv triangle (a, b, c).
double twice_uv_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d u = b - a, w = c - a;
  return u.x() * w.y() - u.y() * w.x();
}

/// Whether the 3D triangle (a, b, c) has zero (or no finite) area, seen from any of its corners:
/// measure_distortion refuses a face whose area is zero from the corner it measures from.
bool flat_in_space(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  for (const auto& [o, p, q] : {std::tuple{a, b, c}, std::tuple{b, c, a}, std::tuple{c, a, b}}) {
    const double twice = (p - o).cross(q - o).norm();
    if (!(std::isfinite(twice) && twice > 0)) return true;
  }
  return false;
}

}  // namespace

Polygons start_fans_where_valid(const Polygons& polygons, const Mesh& mesh,
                                const Triangles& uv_triangles,
                                const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv) {
  if (polygons.empty()) return polygons;
  // The triangles of each polygon, for those no corner's fan is sound from.
  std::vector<std::vector<int>> triangles_of(polygons.num_polygons());
  for (std::size_t t = 0; t < polygons.triangle_polygon.size(); ++t) {
    triangles_of[polygons.triangle_polygon[t]].push_back(static_cast<int>(t));
  }
  Polygons out;
  out.triangle_polygon.assign(polygons.triangle_polygon.size(), -1);
  out.corner_start.push_back(0);
  out.corners.reserve(polygons.corners.size());
  std::vector<Eigen::Vector2d> q;
  std::vector<Eigen::Vector3d> x;
  auto add = [&](const std::vector<int>& triangles, const int* corner, int n, int first) {
    const int index = out.num_polygons();
    for (int t : triangles) out.triangle_polygon[t] = index;
    for (int i = 0; i < n; ++i) out.corners.push_back(corner[(first + i) % n]);
    out.corner_start.push_back(static_cast<int>(out.corners.size()));
  };
  for (int p = 0; p < polygons.num_polygons(); ++p) {
    const int n = polygons.size(p);
    const int* corner = polygons.corners.data() + polygons.corner_start[p];
    if (n == 3) {  // a triangle's one "fan" is itself from every corner
      add(triangles_of[p], corner, n, 0);
      continue;
    }
    q.resize(n);
    x.resize(n);
    for (int i = 0; i < n; ++i) {
      const int t = corner[i] / 3, k = corner[i] % 3;
      q[i] = uv.row(uv_triangles(t, k)).transpose();
      x[i] = mesh.positions.row(mesh.triangles(t, k)).transpose();
    }
    int best = 0, best_folded = n, best_flat = n;
    for (int s = 0; s < n && (best_folded > 0 || best_flat > 0); ++s) {
      int folded = 0, flat = 0;
      for (int i = 1; i + 1 < n; ++i) {
        const int b = (s + i) % n, c = (s + i + 1) % n;
        folded += !(twice_uv_area(q[s], q[b], q[c]) > 0);
        flat += flat_in_space(x[s], x[b], x[c]);
      }
      if (folded < best_folded || (folded == best_folded && flat < best_flat)) {
        best = s;
        best_folded = folded;
        best_flat = flat;
      }
    }
    if (best_folded == 0) {
      add(triangles_of[p], corner, n, best);
      continue;
    }
    // No corner sees the whole polygon in the layout (not star-shaped from a corner: any
    // reader's fan would fold): written as its own triangles, which the layout drew unfolded.
    for (int t : triangles_of[p]) {
      const std::array<int, 3> own{3 * t, 3 * t + 1, 3 * t + 2};
      add({t}, own.data(), 3, 0);
    }
  }
  return out;
}

Distortion measure_polygon_distortion(const Mesh& mesh, const Polygons& polygons,
                                      const Triangles& uv_triangles,
                                      const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv) {
  if (polygons.empty()) return measure_distortion(mesh, uv_triangles, uv);
  const Triangles fans = polygon_fans(polygons, mesh.triangles);
  const Triangles uv_fans = polygon_fans(polygons, uv_triangles);
  std::vector<Eigen::Index> measured;
  measured.reserve(static_cast<std::size_t>(fans.rows()));
  int flat_flipped = 0, flat_degenerate = 0;
  double flat_layout_area = 0;
  for (Eigen::Index f = 0; f < fans.rows(); ++f) {
    auto point = [&](int k) -> Eigen::Vector3d { return mesh.positions.row(fans(f, k)); };
    if (!flat_in_space(point(0), point(1), point(2))) {
      measured.push_back(f);
      continue;
    }
    auto at = [&](int k) -> Eigen::Vector2d { return uv.row(uv_fans(f, k)); };
    const double twice = twice_uv_area(at(0), at(1), at(2));
    if (!(std::isfinite(twice) && twice != 0)) {
      ++flat_degenerate;
    } else {
      flat_flipped += twice < 0;
      flat_layout_area += std::abs(twice) / 2;
    }
  }
  Distortion d;
  if (!measured.empty()) {
    Mesh fan_mesh;
    fan_mesh.positions = mesh.positions;
    fan_mesh.triangles.resize(static_cast<Eigen::Index>(measured.size()), 3);
    Triangles fan_uv(static_cast<Eigen::Index>(measured.size()), 3);
    for (std::size_t i = 0; i < measured.size(); ++i) {
      fan_mesh.triangles.row(static_cast<Eigen::Index>(i)) = fans.row(measured[i]);
      fan_uv.row(static_cast<Eigen::Index>(i)) = uv_fans.row(measured[i]);
    }
    d = measure_distortion(fan_mesh, fan_uv, uv);
  }
  d.flipped_faces += flat_flipped;
  d.degenerate_faces += flat_degenerate;
  d.layout_area += flat_layout_area;
  return d;
}

}  // namespace ricci
