#include "ricci/mesh/polygons.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "ricci/errors.hpp"

namespace ricci {

void check_polygons(const Polygons& polygons, const Triangles& triangles,
                    const std::string& context) {
  if (polygons.empty() && polygons.triangle_polygon.empty() && polygons.corners.empty()) return;
  auto invalid = [&](const std::string& what) { throw InvalidInput(context + ": " + what); };
  const int nf = static_cast<int>(triangles.rows());
  const int np = polygons.num_polygons();
  if (static_cast<int>(polygons.triangle_polygon.size()) != nf) {
    invalid("polygons.triangle_polygon has " + std::to_string(polygons.triangle_polygon.size()) +
            " entries for " + std::to_string(nf) + " triangles");
  }
  if (polygons.corner_start.empty() || polygons.corner_start.front() != 0 ||
      polygons.corner_start.back() != static_cast<int>(polygons.corners.size())) {
    invalid("polygons.corner_start must run from 0 to the number of corners (" +
            std::to_string(polygons.corners.size()) + ")");
  }
  // The triangles of each polygon (compressed rows).
  std::vector<int> member_start(np + 1, 0);
  for (int t = 0; t < nf; ++t) {
    const int p = polygons.triangle_polygon[t];
    if (p < 0 || p >= np) {
      invalid("triangle " + std::to_string(t) + " belongs to polygon " + std::to_string(p) +
              ", out of range [0, " + std::to_string(np) + ")");
    }
    ++member_start[p + 1];
  }
  for (int p = 0; p < np; ++p) member_start[p + 1] += member_start[p];
  std::vector<int> members(nf);
  {
    std::vector<int> fill(member_start.begin(), member_start.end() - 1);
    for (int t = 0; t < nf; ++t) members[fill[polygons.triangle_polygon[t]]++] = t;
  }
  // Per polygon, its corner vertices, to check that its triangles use no other vertex.
  std::vector<int> mark(nf > 0 ? static_cast<std::size_t>(triangles.maxCoeff()) + 1 : 0, -1);
  for (int p = 0; p < np; ++p) {
    const int n = polygons.size(p), count = member_start[p + 1] - member_start[p];
    if (n < 3) {
      invalid("polygon " + std::to_string(p) + " has " + std::to_string(n) +
              " corners, need at least 3");
    }
    if (count != n - 2) {
      invalid("polygon " + std::to_string(p) + " has " + std::to_string(n) + " corners and " +
              std::to_string(count) + " triangles (a polygon of n corners has n - 2)");
    }
    for (int i = polygons.corner_start[p]; i < polygons.corner_start[p + 1]; ++i) {
      const int c = polygons.corners[i];
      if (c < 0 || c >= 3 * nf || polygons.triangle_polygon[c / 3] != p) {
        invalid("corner " + std::to_string(i - polygons.corner_start[p]) + " of polygon " +
                std::to_string(p) + " is triangle corner " + std::to_string(c) +
                ", not a corner of one of its triangles");
      }
      mark[triangles(c / 3, c % 3)] = p;
    }
    for (int i = member_start[p]; i < member_start[p + 1]; ++i) {
      const int t = members[i];
      for (int k = 0; k < 3; ++k) {
        if (mark[triangles(t, k)] == p) continue;
        invalid("triangle " + std::to_string(t) + " uses vertex " +
                std::to_string(triangles(t, k)) + ", which is no corner of its polygon " +
                std::to_string(p));
      }
    }
  }
}

Triangles polygon_fans(const Polygons& polygons, const Triangles& corner_values) {
  const int np = polygons.num_polygons();
  Triangles fans(static_cast<Eigen::Index>(polygons.corners.size()) - 2 * np, 3);
  auto value = [&](int corner) { return corner_values(corner / 3, corner % 3); };
  Eigen::Index row = 0;
  for (int p = 0; p < np; ++p) {
    const int* c = polygons.corners.data() + polygons.corner_start[p];
    for (int i = 1; i + 1 < polygons.size(p); ++i) {
      fans.row(row++) << value(c[0]), value(c[i]), value(c[i + 1]);
    }
  }
  return fans;
}

std::vector<char> polygon_diagonals(const Topology& topology, const Polygons& polygons) {
  std::vector<char> diagonal(topology.num_edges, 0);
  if (polygons.empty()) return diagonal;
  for (int e = 0; e < topology.num_edges; ++e) {
    const int h0 = topology.edge_halfedges(e, 0), h1 = topology.edge_halfedges(e, 1);
    if (h0 < 0 || h1 < 0) continue;
    diagonal[e] = polygons.triangle_polygon[Topology::face_of(h0)] ==
                  polygons.triangle_polygon[Topology::face_of(h1)];
  }
  return diagonal;
}

Polygons polygons_of_faces(const Polygons& polygons, const std::vector<int>& faces) {
  Polygons out;
  if (polygons.empty()) return out;
  const int np = polygons.num_polygons();
  // The subset's triangles of each polygon, and each triangle's index in the subset.
  std::vector<int> present(np, 0);
  std::vector<int> local(polygons.triangle_polygon.size(), -1);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    local[faces[i]] = static_cast<int>(i);
    ++present[polygons.triangle_polygon[faces[i]]];
  }
  std::vector<int> number(np, -1);  // the polygon's index in the subset (whole polygons)
  out.triangle_polygon.assign(faces.size(), -1);
  out.corner_start.push_back(0);
  bool any_polygon = false;
  auto add_triangle = [&](int i) {
    out.triangle_polygon[i] = static_cast<int>(out.corner_start.size()) - 1;
    out.corners.insert(out.corners.end(), {3 * i, 3 * i + 1, 3 * i + 2});
    out.corner_start.push_back(static_cast<int>(out.corners.size()));
  };
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const int p = polygons.triangle_polygon[faces[i]];
    if (present[p] != polygons.size(p) - 2) {
      add_triangle(static_cast<int>(i));
      continue;
    }
    if (number[p] >= 0) {
      out.triangle_polygon[i] = number[p];
      continue;
    }
    number[p] = static_cast<int>(out.corner_start.size()) - 1;
    out.triangle_polygon[i] = number[p];
    for (int j = polygons.corner_start[p]; j < polygons.corner_start[p + 1]; ++j) {
      const int c = polygons.corners[j];
      out.corners.push_back(3 * local[c / 3] + c % 3);
    }
    out.corner_start.push_back(static_cast<int>(out.corners.size()));
    any_polygon = any_polygon || polygons.size(p) > 3;
  }
  if (!any_polygon) return {};
  return out;
}

}  // namespace ricci
