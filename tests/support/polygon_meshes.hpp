#pragma once
/// \file
/// Generated polygon meshes (quads and n-gons) as a file states them, for the tests of the
/// readers' polygon bookkeeping, the cut that never crosses a polygon and the polygon output.

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "ricci/mesh/io.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/mesh/topology.hpp"
#include "support/shared_meshes.hpp"

namespace ricci::testing {

/// Positions and faces of any number of corners (0-based, counter-clockwise seen from outside).
struct PolygonSoup {
  std::vector<std::array<double, 3>> positions;
  std::vector<std::vector<int>> faces;
};

/// The soup as OBJ text (`v x y z`, `f a b c d`, 1-based).
inline std::string obj_text(const PolygonSoup& soup) {
  std::string text;
  char line[128];
  for (const auto& p : soup.positions) {
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    text += line;
  }
  for (const auto& face : soup.faces) {
    text += "f";
    for (const int v : face) text += " " + std::to_string(v + 1);
    text += "\n";
  }
  return text;
}

/// Writes the soup as OBJ into the suite's scratch folder and reads it back with read_mesh.
inline ReadResult read_soup(const PolygonSoup& soup, const std::string& name,
                            const ReadOptions& options = {}) {
  const std::string path = write_text_file(suite_tmp_dir("polygons") / name, obj_text(soup));
  return read_mesh(path, options);
}

/// An n by m grid of quads on the torus of revolution (radii 1 and 0.4): vertex (i, j) is
/// i m + j, quad (i, j) is (i, j), (i+1, j), (i+1, j+1), (i, j+1).
inline PolygonSoup quad_torus(int n, int m) {
  PolygonSoup soup;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
      soup.positions.push_back({(1 + 0.4 * std::cos(v)) * std::cos(u),
                                (1 + 0.4 * std::cos(v)) * std::sin(u), 0.4 * std::sin(v)});
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const int i1 = (i + 1) % n, j1 = (j + 1) % m;
      soup.faces.push_back({i * m + j, i1 * m + j, i1 * m + j1, i * m + j1});
    }
  }
  return soup;
}

/// An n by m grid of unit quads over [0, n] x [0, m], lifted onto a gentle bump (a disk).
inline PolygonSoup quad_grid(int n, int m) {
  PolygonSoup soup;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= m; ++j) {
      const double x = i, y = j;
      soup.positions.push_back(
          {x, y, 0.3 * std::sin(x / n * std::numbers::pi) * std::sin(y / m * std::numbers::pi)});
    }
  }
  const int w = m + 1;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      soup.faces.push_back({i * w + j, (i + 1) * w + j, (i + 1) * w + j + 1, i * w + j + 1});
    }
  }
  return soup;
}

/// An open cylinder of n quads around and m along (radius 1, height 2): an annulus.
inline PolygonSoup quad_cylinder(int n, int m) {
  PolygonSoup soup;
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * i / n;
      soup.positions.push_back({std::cos(a), std::sin(a), 2.0 * j / m});
    }
  }
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      const int i1 = (i + 1) % n;
      soup.faces.push_back({j * n + i, j * n + i1, (j + 1) * n + i1, (j + 1) * n + i});
    }
  }
  return soup;
}

/// The cube [-1, 1]^3 with each side split into k by k quads, its vertices pushed onto the unit
/// sphere when `round`: a closed quad mesh of genus 0 whose eight corners have valence 3.
inline PolygonSoup quad_sphere(int k, bool round = true) {
  PolygonSoup soup;
  std::vector<std::array<long, 3>> keys;  // vertex positions times k, to share them
  auto vertex = [&](std::array<long, 3> key) {
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (keys[i] == key) return static_cast<int>(i);
    }
    keys.push_back(key);
    std::array<double, 3> p{double(key[0]) / k, double(key[1]) / k, double(key[2]) / k};
    if (round) {
      const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      for (double& x : p) x /= r;
    }
    soup.positions.push_back(p);
    return static_cast<int>(keys.size()) - 1;
  };
  // Each side: its outward axis and two tangent axes whose cross product points outward.
  for (int axis = 0; axis < 3; ++axis) {
    for (const int sign : {1, -1}) {
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      for (int i = 0; i < k; ++i) {
        for (int j = 0; j < k; ++j) {
          auto key = [&](int s, int t) {
            std::array<long, 3> p{};
            p[axis] = sign * k;
            // Swap the tangent order on the negative side to keep the faces outward.
            p[sign > 0 ? a : b] = 2 * s - k;
            p[sign > 0 ? b : a] = 2 * t - k;
            return p;
          };
          soup.faces.push_back({vertex(key(i, j)), vertex(key(i + 1, j)), vertex(key(i + 1, j + 1)),
                                vertex(key(i, j + 1))});
        }
      }
    }
  }
  return soup;
}

/// A 3 by 3 grid of unit quads whose lower-left L of three cells is one non-convex octagon with
/// three corners in a line on two of its sides ((0,0), (1,0), (2,0), (2,1), (1,1), (1,2), (0,2),
/// (0,1)): its fan from the first corner degenerates (the reader clips ears), and only the fan
/// from its reflex corner (1,1) is sound. Bent gently out of the plane when `bend`.
inline PolygonSoup l_octagon_grid(bool bend = false) {
  PolygonSoup soup;
  for (int y = 0; y <= 3; ++y) {
    for (int x = 0; x <= 3; ++x) {
      soup.positions.push_back({double(x), double(y), bend ? 0.1 * (x - 1.5) * (x - 1.5) : 0.0});
    }
  }
  auto v = [](int x, int y) { return 4 * y + x; };
  soup.faces.push_back({v(0, 0), v(1, 0), v(2, 0), v(2, 1), v(1, 1), v(1, 2), v(0, 2), v(0, 1)});
  for (const auto& [x, y] :
       std::vector<std::array<int, 2>>{{2, 0}, {1, 1}, {2, 1}, {0, 2}, {1, 2}, {2, 2}}) {
    soup.faces.push_back({v(x, y), v(x + 1, y), v(x + 1, y + 1), v(x, y + 1)});
  }
  return soup;
}

/// Quads over a triangle mesh: triangles 2 i and 2 i + 1 become one quad when they share an edge
/// (as the quads of the generated meshes are split), every other triangle stays a face of its
/// own.
inline Polygons pair_triangles(const Mesh& mesh) {
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  Polygons polygons;
  polygons.corner_start.push_back(0);
  auto close = [&] { polygons.corner_start.push_back(static_cast<int>(polygons.corners.size())); };
  for (int f = 0; f < t.num_faces; ++f) {
    const int p = polygons.num_polygons();
    polygons.triangle_polygon.push_back(p);
    int shared = -1;  // f's corner opposite the edge it shares with f + 1
    for (int k = 0; k < 3 && f % 2 == 0 && f + 1 < t.num_faces; ++k) {
      const int twin = t.halfedge_twin[3 * f + k];
      if (twin >= 0 && Topology::face_of(twin) == f + 1) shared = k;
    }
    if (shared < 0) {
      polygons.corners.insert(polygons.corners.end(), {3 * f, 3 * f + 1, 3 * f + 2});
      close();
      continue;
    }
    // f = (x0, x1, x2) with the shared edge x1 -> x2; f + 1 has x2 -> x1 and its apex d:
    // the quad x0, x1, d, x2.
    const int apex = 3 * (f + 1) + t.halfedge_twin[3 * f + shared] % 3;
    polygons.corners.insert(polygons.corners.end(), {3 * f + shared, 3 * f + (shared + 1) % 3, apex,
                                                     3 * f + (shared + 2) % 3});
    close();
    polygons.triangle_polygon.push_back(p);
    ++f;
  }
  return polygons;
}

}  // namespace ricci::testing
