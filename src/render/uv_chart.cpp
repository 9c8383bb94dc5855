#include "ricci/render/uv_chart.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include "ricci/errors.hpp"

namespace ricci {

void check_uv_layout(const char* function, const Mesh& mesh, const Triangles& uv_triangles,
                     const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv) {
  const std::string name(function);
  if (uv_triangles.rows() != mesh.num_faces()) {
    throw InvalidInput(name + ": uv_triangles has " + std::to_string(uv_triangles.rows()) +
                       " rows but the mesh has " + std::to_string(mesh.num_faces()) + " faces");
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.triangles(f, c), t = uv_triangles(f, c);
      if (v < 0 || v >= mesh.num_vertices()) {
        throw InvalidInput(name + ": face " + std::to_string(f) + " corner " + std::to_string(c) +
                           ": vertex index " + std::to_string(v) + " is out of range [0, " +
                           std::to_string(mesh.num_vertices()) + ")");
      }
      if (t < 0 || t >= uv.rows()) {
        throw InvalidInput(name + ": face " + std::to_string(f) + " corner " + std::to_string(c) +
                           ": uv index " + std::to_string(t) + " is out of range [0, " +
                           std::to_string(uv.rows()) + ")");
      }
    }
  }
}

UvChart analyse_uv_chart(const Mesh& mesh, const Triangles& uv_triangles,
                         const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                         double cone_tolerance) {
  check_uv_layout("analyse_uv_chart", mesh, uv_triangles, uv);
  const int nf = mesh.num_faces(), nv = mesh.num_vertices();
  const auto& T = mesh.triangles;

  // Halfedges sorted by their undirected edge; an edge is interior when exactly two halfedges of
  // opposite directions share it.
  struct Entry {
    std::int64_t key;
    int halfedge;
  };
  std::vector<Entry> entries(static_cast<std::size_t>(nf) * 3);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = T(f, (k + 1) % 3), b = T(f, (k + 2) % 3);
      entries[3 * f + k] = {static_cast<std::int64_t>(std::min(a, b)) * nv + std::max(a, b),
                            3 * f + k};
    }
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return x.key != y.key ? x.key < y.key : x.halfedge < y.halfedge;
  });

  // Texture coordinates divided out of homogeneous ones (TexturedMesh::uv_weights) agree only up
  // to rounding where the file repeats a corner per face: equal within kSameUv of the layout's
  // extent counts as the same (a few thousand ulps; distinct corners of a layout are far apart).
  // An all-zero layout keeps a tiny positive extent, so that only equal coordinates match.
  constexpr double kSameUv = 1e-12, kTinyExtent = 1e-300;
  const double extent = uv.rows() > 0 ? std::max(uv.cwiseAbs().maxCoeff(), kTinyExtent) : 1.0;
  auto same_uv = [&](int t0, int t1) {
    return t0 == t1 || (uv.row(t0) - uv.row(t1)).cwiseAbs().maxCoeff() <= kSameUv * extent;
  };
  UvChart chart;
  std::vector<char> on_boundary(nv, 0), on_seam(nv, 0);
  for (std::size_t i = 0; i < entries.size();) {
    std::size_t j = i;
    while (j < entries.size() && entries[j].key == entries[i].key) ++j;
    bool seam = true;
    if (j - i == 2) {
      const int h0 = entries[i].halfedge, h1 = entries[i + 1].halfedge;
      const int f0 = h0 / 3, k0 = h0 % 3, f1 = h1 / 3, k1 = h1 % 3;
      const int a0 = (k0 + 1) % 3, b0 = (k0 + 2) % 3, a1 = (k1 + 1) % 3, b1 = (k1 + 2) % 3;
      if (T(f0, a0) == T(f1, b1) && T(f0, b0) == T(f1, a1)) {
        seam = !(same_uv(uv_triangles(f0, a0), uv_triangles(f1, b1)) &&
                 same_uv(uv_triangles(f0, b0), uv_triangles(f1, a1)));
      } else {
        // Two faces of the same orientation on one edge: the surface is not oriented here.
        for (std::size_t m = i; m < j; ++m) {
          const int h = entries[m].halfedge;
          on_boundary[T(h / 3, (h % 3 + 1) % 3)] = on_boundary[T(h / 3, (h % 3 + 2) % 3)] = 1;
        }
      }
    } else {
      for (std::size_t m = i; m < j; ++m) {
        const int h = entries[m].halfedge;
        on_boundary[T(h / 3, (h % 3 + 1) % 3)] = on_boundary[T(h / 3, (h % 3 + 2) % 3)] = 1;
      }
    }
    if (seam) {
      ++chart.seam_edges;
      for (std::size_t m = i; m < j; ++m) {
        const int h = entries[m].halfedge;
        chart.seam_halfedges.push_back(h);
        on_seam[T(h / 3, (h % 3 + 1) % 3)] = on_seam[T(h / 3, (h % 3 + 2) % 3)] = 1;
      }
    }
    i = j;
  }
  std::sort(chart.seam_halfedges.begin(), chart.seam_halfedges.end());

  // Total texture angle at every interior seam vertex.
  std::vector<double> angle_sum(nv, 0.0);
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = T(f, c);
      if (!on_seam[v] || on_boundary[v]) continue;
      const Eigen::Vector2d p = uv.row(uv_triangles(f, c));
      const Eigen::Vector2d e1 = Eigen::Vector2d(uv.row(uv_triangles(f, (c + 1) % 3))) - p;
      const Eigen::Vector2d e2 = Eigen::Vector2d(uv.row(uv_triangles(f, (c + 2) % 3))) - p;
      angle_sum[v] += std::atan2(std::abs(e1.x() * e2.y() - e1.y() * e2.x()), e1.dot(e2));
    }
  }
  for (int v = 0; v < nv; ++v) {
    if (!on_seam[v] || on_boundary[v]) continue;
    if (std::abs(angle_sum[v] - 2 * std::numbers::pi) > cone_tolerance) {
      chart.cones.push_back(v);
      chart.cone_angles.push_back(angle_sum[v]);
    }
  }
  return chart;
}

}  // namespace ricci
