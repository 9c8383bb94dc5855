#pragma once
/// \file
/// The generated meshes every property test runs over: one per topology class the issue names.

#include <array>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include "ricci/flow/target.hpp"
#include "ricci/mesh/generate.hpp"

namespace ricci::testing {

struct NamedMesh {
  std::string name;
  Mesh mesh;
};

/// A mesh from literal positions and triangles, for hand-made test cases.
inline Mesh make_mesh(std::initializer_list<std::array<double, 3>> positions,
                      std::initializer_list<std::array<int, 3>> triangles) {
  Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(positions.size()), 3);
  mesh.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  Eigen::Index i = 0;
  for (const auto& p : positions) mesh.positions.row(i++) << p[0], p[1], p[2];
  i = 0;
  for (const auto& t : triangles) mesh.triangles.row(i++) << t[0], t[1], t[2];
  return mesh;
}

/// Regular tetrahedron with vertices at alternate cube corners, outward counter-clockwise faces.
inline Mesh tetrahedron() {
  return make_mesh({{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}},
                   {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}});
}

/// Torus of revolution (radii 1 and 0.4), n by m grid of quads split into triangles; vertex
/// (i, j) has index i m + j and quad a = i m + j gives faces 2a and 2a + 1.
inline Mesh torus(int n, int m) {
  Mesh mesh;
  mesh.positions.resize(n * m, 3);
  mesh.triangles.resize(2 * n * m, 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
      mesh.positions.row(i * m + j) << (1 + 0.4 * std::cos(v)) * std::cos(u),
          (1 + 0.4 * std::cos(v)) * std::sin(u), 0.4 * std::sin(v);
      const int a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m,
                d = i * m + (j + 1) % m;
      mesh.triangles.row(2 * a) << a, b, c;
      mesh.triangles.row(2 * a + 1) << a, c, d;
    }
  }
  return mesh;
}

/// A Moebius strip of 2n triangles: a band of n quads around the unit circle whose rungs turn
/// by half a turn, the last quad glued to the first with its ends swapped (non-orientable).
inline Mesh moebius_strip(int n) {
  Mesh mesh;
  mesh.positions.resize(2 * n, 3);
  mesh.triangles.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n;
    const Eigen::RowVector3d centre(std::cos(t), std::sin(t), 0);
    const Eigen::RowVector3d rung =
        0.3 * (std::cos(t / 2) * centre + std::sin(t / 2) * Eigen::RowVector3d::UnitZ());
    mesh.positions.row(2 * i) = centre + rung;
    mesh.positions.row(2 * i + 1) = centre - rung;
    const int a = 2 * i, b = 2 * i + 1;
    const int next_a = i + 1 < n ? a + 2 : 1, next_b = i + 1 < n ? b + 2 : 0;
    mesh.triangles.row(2 * i) << a, b, next_b;
    mesh.triangles.row(2 * i + 1) << a, next_b, next_a;
  }
  return mesh;
}

/// A disk fan around a saddle vertex: eight faces whose rim goes up and down, 787 degrees of
/// angle at the centre, so that its own shape cannot be laid out in one piece (a cone the flow
/// refuses; the components' path unfolds it in patches or lays it out as charts).
inline Mesh saddle_fan() {
  Mesh m;
  m.positions.resize(9, 3);
  m.triangles.resize(8, 3);
  m.positions.row(0) << 0, 0, 0;
  for (int i = 0; i < 8; ++i) {
    m.positions.row(1 + i) << std::cos(std::numbers::pi * i / 4),
        std::sin(std::numbers::pi * i / 4), i % 2 ? 1.0 : -1.0;
    m.triangles.row(i) << 0, 1 + i, 1 + (i + 1) % 8;
  }
  return m;
}

/// The vertex of a unit sphere mesh nearest a direction.
inline int nearest_vertex(const Mesh& sphere, const Eigen::Vector3d& direction) {
  int best = 0;
  (sphere.positions.rowwise() - direction.normalized().transpose())
      .rowwise()
      .squaredNorm()
      .minCoeff(&best);
  return best;
}

/// Four cones of pi at the vertices nearest a regular tetrahedron's corners.
inline std::vector<Cone> tetrahedron_cones(const Mesh& sphere) {
  return {{nearest_vertex(sphere, {1, 1, 1}), std::numbers::pi},
          {nearest_vertex(sphere, {1, -1, -1}), std::numbers::pi},
          {nearest_vertex(sphere, {-1, 1, -1}), std::numbers::pi},
          {nearest_vertex(sphere, {-1, -1, 1}), std::numbers::pi}};
}

/// Eight cones of pi/2 at the vertices nearest a cube's corners.
inline std::vector<Cone> cube_cones(const Mesh& sphere) {
  std::vector<Cone> cones;
  for (int sx : {-1, 1}) {
    for (int sy : {-1, 1}) {
      for (int sz : {-1, 1}) {
        cones.push_back(
            {nearest_vertex(sphere, {1.0 * sx, 1.0 * sy, 1.0 * sz}), std::numbers::pi / 2});
      }
    }
  }
  return cones;
}

/// Small generated meshes: tetrahedron, icosphere, flat and curved disks, torus, closed genus 2
/// and 3, a sphere with holes and a genus-1 surface with holes.
inline std::vector<NamedMesh> generated_meshes() {
  return {
      {"tetrahedron", make_tetrahedron(1.0)},
      {"icosphere", make_icosphere(2)},
      {"flat_disk", make_disk(5)},
      {"curved_disk", make_disk(5, 0.6)},
      {"torus", make_torus(24, 12)},
      {"genus2", make_closed_surface(2, 10)},
      {"genus3", make_closed_surface(3, 10)},
      {"sphere_with_3_holes", make_surface_with_holes(0, 3, 10)},
      {"torus_with_2_holes", make_surface_with_holes(1, 2, 10)},
  };
}

}  // namespace ricci::testing
