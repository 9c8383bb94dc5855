#include "mesh/io/detail/file_polygons.hpp"

#include <algorithm>

namespace ricci::io_detail {

Polygons file_polygons(const std::vector<int>& polygon_start,
                       const std::vector<int>& polygon_of_triangle,
                       const std::vector<int>& triangle_corners, const Triangles& triangles,
                       const std::vector<int>& face_map, const std::vector<char>& face_flipped) {
  const int nf = static_cast<int>(triangles.rows());
  auto source = [&](int r) { return face_map.empty() ? r : face_map[r]; };
  auto flipped = [&](int r) { return !face_flipped.empty() && face_flipped[r] != 0; };

  Polygons out;
  out.triangle_polygon.assign(nf, -1);
  out.corner_start.push_back(0);
  bool any_polygon = false;
  auto single_triangle = [&](int r) {
    out.triangle_polygon[r] = out.num_polygons();
    out.corners.insert(out.corners.end(), {3 * r, 3 * r + 1, 3 * r + 2});
    out.corner_start.push_back(static_cast<int>(out.corners.size()));
  };
  // The triangles of a file face are consecutive in the triangulation, and repair keeps the
  // order of the triangles it keeps: each face's returned triangles are a run.
  std::vector<int> vertex_at, output_corner;
  for (int begin = 0; begin < nf;) {
    const int p = polygon_of_triangle[source(begin)];
    int end = begin + 1;
    while (end < nf && polygon_of_triangle[source(end)] == p) ++end;
    const int first = polygon_start[p], n = polygon_start[p + 1] - first;
    bool whole = end - begin == n - 2;
    vertex_at.assign(n, -1);
    output_corner.assign(n, -1);
    for (int r = begin; r < end && whole; ++r) {
      whole = flipped(r) == flipped(begin);
      for (int k = 0; k < 3 && whole; ++k) {
        // Reversing a triangle exchanged its corners 1 and 2.
        const int from = flipped(r) && k > 0 ? 3 - k : k;
        const int i = triangle_corners[3 * source(r) + from] - first;
        if (vertex_at[i] < 0) {
          vertex_at[i] = triangles(r, k);
          output_corner[i] = 3 * r + k;
        }
        whole = vertex_at[i] == triangles(r, k);
      }
    }
    whole =
        whole && std::find(output_corner.begin(), output_corner.end(), -1) == output_corner.end();
    if (!whole) {
      for (int r = begin; r < end; ++r) single_triangle(r);
      begin = end;
      continue;
    }
    for (int r = begin; r < end; ++r) out.triangle_polygon[r] = out.num_polygons();
    out.corners.push_back(output_corner[0]);
    for (int j = 1; j < n; ++j) out.corners.push_back(output_corner[flipped(begin) ? n - j : j]);
    out.corner_start.push_back(static_cast<int>(out.corners.size()));
    any_polygon = any_polygon || n > 3;
    begin = end;
  }
  if (!any_polygon) return {};
  return out;
}

}  // namespace ricci::io_detail
