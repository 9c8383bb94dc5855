#include "ricci/mesh/hard_cases.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci {
namespace {

Mesh from_lists(const std::vector<Eigen::Vector3d>& points,
                const std::vector<std::array<int, 3>>& faces) {
  Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    mesh.positions.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  }
  mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) mesh.triangles(static_cast<Eigen::Index>(f), k) = faces[f][k];
  }
  return mesh;
}

}  // namespace

Mesh make_cad_cylinder(int segments, double height) {
  if (segments < 3 || !std::isfinite(height) || height <= 0) {
    throw InvalidInput("make_cad_cylinder: need segments >= 3 and a finite height > 0, got " +
                       std::to_string(segments) + " and " + std::to_string(height));
  }
  const int n = segments;
  std::vector<Eigen::Vector3d> points;
  for (int level = 0; level < 2; ++level) {
    for (int i = 0; i < n; ++i) {
      const double t = 2 * std::numbers::pi * i / n;
      points.emplace_back(std::cos(t), std::sin(t), level * height);
    }
  }
  auto bottom = [&](int i) { return i % n; };
  auto top = [&](int i) { return n + i % n; };
  std::vector<std::array<int, 3>> faces;
  for (int i = 0; i < n; ++i) {  // the side: one strip, outward
    faces.push_back({bottom(i), bottom(i + 1), top(i + 1)});
    faces.push_back({bottom(i), top(i + 1), top(i)});
  }
  for (int i = 1; i + 1 < n; ++i) {  // the caps: fans from rim vertex 0
    faces.push_back({top(0), top(i), top(i + 1)});
    faces.push_back({bottom(0), bottom(i + 1), bottom(i)});
  }
  return from_lists(points, faces);
}

Mesh make_cad_ring(int segments) {
  if (segments < 3) {
    throw InvalidInput("make_cad_ring: need segments >= 3, got " + std::to_string(segments));
  }
  const int n = segments;
  // The square cross-section (radius from the axis, height), counter-clockwise seen along the
  // direction of increasing angle, so that the walls below face outward.
  const double section[4][2] = {{1.0, 0.0}, {1.5, 0.0}, {1.5, 0.5}, {1.0, 0.5}};
  std::vector<Eigen::Vector3d> points;
  for (int c = 0; c < 4; ++c) {
    for (int i = 0; i < n; ++i) {
      const double t = 2 * std::numbers::pi * i / n;
      points.emplace_back(section[c][0] * std::cos(t), section[c][0] * std::sin(t), section[c][1]);
    }
  }
  auto at = [&](int c, int i) { return (c % 4) * n + i % n; };
  std::vector<std::array<int, 3>> faces;
  for (int c = 0; c < 4; ++c) {
    for (int i = 0; i < n; ++i) {
      faces.push_back({at(c, i), at(c + 1, i), at(c + 1, i + 1)});
      faces.push_back({at(c, i), at(c + 1, i + 1), at(c, i + 1)});
    }
  }
  // Orient outward: the first wall (the bottom, z = 0) must face -z.
  const Eigen::Vector3d a = points[faces[0][0]], b = points[faces[0][1]], c = points[faces[0][2]];
  if ((b - a).cross(c - a).z() > 0) {
    for (auto& f : faces) std::swap(f[1], f[2]);
  }
  return from_lists(points, faces);
}

Mesh split_faces_near_corner(const Mesh& mesh, double weight, double lift, int stride) {
  if (!(weight > 0 && weight <= 1.0 / 3) || stride < 1 || !std::isfinite(lift)) {
    throw InvalidInput(
        "split_faces_near_corner: need weight in (0, 1/3], stride >= 1 and a "
        "finite lift");
  }
  std::vector<Eigen::Vector3d> points;
  points.reserve(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) points.emplace_back(mesh.positions.row(v));
  std::vector<std::array<int, 3>> faces;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int a = mesh.triangles(f, 0), b = mesh.triangles(f, 1), c = mesh.triangles(f, 2);
    if (f % stride != 0) {
      faces.push_back({a, b, c});
      continue;
    }
    const Eigen::Vector3d pa = points[a], pb = points[b], pc = points[c];
    const Eigen::Vector3d normal = (pb - pa).cross(pc - pa);
    const double area = 0.5 * normal.norm();
    Eigen::Vector3d p = (1 - 2 * weight) * pa + weight * (pb + pc);
    if (area > 0) p += lift * std::sqrt(area) * normal.normalized();
    const int m = static_cast<int>(points.size());
    points.push_back(p);
    faces.push_back({a, b, m});
    faces.push_back({b, c, m});
    faces.push_back({c, a, m});
  }
  return from_lists(points, faces);
}

Mesh pull_vertices_to_neighbours(const Mesh& mesh, double amount, std::uint32_t seed, int stride) {
  if (!(amount >= 0 && amount < 1) || stride < 1) {
    throw InvalidInput("pull_vertices_to_neighbours: need amount in [0, 1) and stride >= 1");
  }
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  std::vector<std::vector<int>> neighbours(t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    neighbours[t.edge_vertices(e, 0)].push_back(t.edge_vertices(e, 1));
    neighbours[t.edge_vertices(e, 1)].push_back(t.edge_vertices(e, 0));
  }
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Mesh out = mesh;
  std::vector<char> blocked(t.num_vertices, 0);
  for (int v = 0; v < t.num_vertices; v += stride) {
    if (blocked[v] || t.is_boundary_vertex[v] || neighbours[v].empty()) continue;
    const int w = neighbours[v][random() % neighbours[v].size()];
    const double fraction = amount * (0.5 + 0.5 * unit(random));
    out.positions.row(v) =
        mesh.positions.row(v) + fraction * (mesh.positions.row(w) - mesh.positions.row(v));
    // No two neighbours move: each moved vertex stays inside its own star.
    blocked[v] = 1;
    for (int u : neighbours[v]) blocked[u] = 1;
  }
  return out;
}

Mesh make_ball_with_fingers(int fingers, double aspect, int resolution) {
  if (fingers < 0 || fingers > 6 || resolution < 4 || resolution % 2 != 0 ||
      !std::isfinite(aspect) || !(aspect > 0)) {
    throw InvalidInput(
        "make_ball_with_fingers: need fingers in [0, 6], an even resolution >= 4 "
        "and a finite aspect > 0, got " +
        std::to_string(fingers) + ", " + std::to_string(resolution) + " and " +
        std::to_string(aspect));
  }
  const int n = resolution;
  // The cube's surface grid: integer points of [0, n]^3 with a coordinate at 0 or n, each once.
  std::vector<int> grid((n + 1) * (n + 1) * (n + 1), -1);
  std::vector<Eigen::Vector3d> points;
  auto vertex = [&](const std::array<int, 3>& c) {
    int& id = grid[(c[0] * (n + 1) + c[1]) * (n + 1) + c[2]];
    if (id < 0) {
      id = static_cast<int>(points.size());
      points.push_back(
          (Eigen::Vector3d(c[0], c[1], c[2]) * (2.0 / n) - Eigen::Vector3d::Ones()).normalized());
    }
    return id;
  };
  std::vector<std::array<int, 3>> faces;
  const int lo = n / 2 - 1, mid = n / 2, hi = n / 2 + 1;
  for (int side = 0; side < 6; ++side) {
    // Side `side`: axis a at n (the first three) or 0; (b, c) counter-clockwise seen from outside.
    const int a = side % 3, level = side < 3 ? n : 0;
    const int b = side < 3 ? (a + 1) % 3 : (a + 2) % 3, c = side < 3 ? (a + 2) % 3 : (a + 1) % 3;
    auto at = [&](int u, int v) {
      std::array<int, 3> p{};
      p[a] = level, p[b] = u, p[c] = v;
      return vertex(p);
    };
    const bool finger = side < fingers;
    std::vector<std::array<int, 3>> block;  // the finger's cells, which become its cap
    for (int u = 0; u < n; ++u) {
      for (int v = 0; v < n; ++v) {
        const std::array<int, 3> first{at(u, v), at(u + 1, v), at(u + 1, v + 1)};
        const std::array<int, 3> second{at(u, v), at(u + 1, v + 1), at(u, v + 1)};
        auto& to = finger && u >= lo && u < hi && v >= lo && v < hi ? block : faces;
        to.push_back(first);
        to.push_back(second);
      }
    }
    if (!finger) continue;
    // The block's boundary, counter-clockwise seen from outside, and its centre.
    const std::array<int, 8> ring{at(lo, lo), at(mid, lo), at(hi, lo), at(hi, mid),
                                  at(hi, hi), at(mid, hi), at(lo, hi), at(lo, mid)};
    const int centre = at(mid, mid);
    const Eigen::Vector3d axis = points[centre];
    std::array<Eigen::Vector3d, 8> across;  // unit directions from the axis to the ring
    double radius = 0;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d offset = points[ring[k]] - axis;
      across[k] = offset - offset.dot(axis) * axis;
      radius += across[k].norm() / 8;
      across[k].normalize();
    }
    const double step = 2 * std::numbers::pi * radius / 8;  // near-square cells
    const int rings = std::max(1, static_cast<int>(std::lround(8 * aspect)));
    std::array<int, 8> below = ring;
    for (int r = 1; r <= rings; ++r) {
      std::array<int, 8> above{};
      for (int k = 0; k < 8; ++k) {
        above[k] = static_cast<int>(points.size());
        points.emplace_back(axis + r * step * axis + radius * across[k]);
      }
      for (int k = 0; k < 8; ++k) {  // the wall, outward: edge below[k] -> below[k + 1] kept
        faces.push_back({below[k], below[(k + 1) % 8], above[(k + 1) % 8]});
        faces.push_back({below[k], above[(k + 1) % 8], above[k]});
      }
      below = above;
    }
    // The cap: the block's triangles on the last ring, the centre lifted into a low dome.
    points[centre] = axis + (rings * step + 0.5 * radius) * axis;
    for (std::array<int, 3> f : block) {
      for (int& w : f) {
        for (int k = 0; k < 8; ++k) {
          if (w == ring[k]) {
            w = below[k];
            break;
          }
        }
      }
      faces.push_back(f);
    }
  }
  return from_lists(points, faces);
}

}  // namespace ricci
