#pragma once
/// \file
/// Badly shaped meshes made from good ones, for the tests and the benchmarks of the flow with
/// intrinsic Delaunay flips (header-only, so that bench/ uses them without the test framework):
/// valence-3 spikes, 0.1-degree needles and scan-like tangential noise. Each keeps the surface's
/// topology, so its uniformization metric exists; what they break is the input triangulation.

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/topology.hpp"

namespace ricci::testing {

/// Outward unit normal of face f (zero for a degenerate face).
inline Eigen::RowVector3d face_normal(const Mesh& mesh, int f) {
  const Eigen::RowVector3d a = mesh.positions.row(mesh.triangles(f, 0));
  const Eigen::RowVector3d b = mesh.positions.row(mesh.triangles(f, 1));
  const Eigen::RowVector3d c = mesh.positions.row(mesh.triangles(f, 2));
  const Eigen::RowVector3d n = (b - a).cross(c - a);
  const double length = n.norm();
  return length > 0 ? Eigen::RowVector3d(n / length) : Eigen::RowVector3d::Zero();
}

/// `mesh`'s vertices followed by `added`, with `faces` as its triangles: the assembly step of
/// the edits below, which keep every old vertex at its index and append the new ones.
inline Mesh with_added_vertices(const Mesh& mesh, const std::vector<Eigen::RowVector3d>& added,
                                const std::vector<Eigen::Vector3i>& faces) {
  Mesh out;
  out.positions.resize(mesh.num_vertices() + static_cast<Eigen::Index>(added.size()), 3);
  out.positions.topRows(mesh.num_vertices()) = mesh.positions;
  for (std::size_t i = 0; i < added.size(); ++i) {
    out.positions.row(mesh.num_vertices() + static_cast<Eigen::Index>(i)) = added[i];
  }
  out.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    out.triangles.row(static_cast<Eigen::Index>(i)) = faces[i].transpose();
  }
  return out;
}

/// Splits every `stride`-th face 1-to-3 at a point near its first corner (barycentric weights
/// 0.8, 0.1, 0.1) and pushes the new vertex out along the face normal by `push` times the face's
/// longest edge: a valence-3 vertex whose three tall faces meet at a spike (an angle sum far
/// below 2 pi that vertex scaling cannot open without breaking a triangle), the shape a badly
/// decimated or a hand-edited mesh has.
inline Mesh with_valence3_spikes(const Mesh& mesh, int stride, double push) {
  std::vector<Eigen::RowVector3d> added;
  std::vector<Eigen::Vector3i> faces;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int a = mesh.triangles(f, 0), b = mesh.triangles(f, 1), c = mesh.triangles(f, 2);
    if (f % stride != 0) {
      faces.emplace_back(a, b, c);
      continue;
    }
    const Eigen::RowVector3d pa = mesh.positions.row(a), pb = mesh.positions.row(b),
                             pc = mesh.positions.row(c);
    const double longest = std::max({(pb - pa).norm(), (pc - pb).norm(), (pa - pc).norm()});
    const int p = mesh.num_vertices() + static_cast<int>(added.size());
    added.emplace_back(0.8 * pa + 0.1 * pb + 0.1 * pc + push * longest * face_normal(mesh, f));
    faces.emplace_back(a, b, p);
    faces.emplace_back(b, c, p);
    faces.emplace_back(c, a, p);
  }
  return with_added_vertices(mesh, added, faces);
}

/// Splits every `stride`-th interior edge (skipping those with a face already split) at the
/// point a fraction `t` of its length from its smaller vertex: the two new triangles on that side
/// are needles whose angle opposite the short piece is about t |ab| / |ac| radians
/// (t = 0.0017: about 0.1 degree on a regular mesh).
inline Mesh with_needles(const Mesh& mesh, int stride, double t) {
  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  std::vector<int> split_vertex(static_cast<std::size_t>(topology.num_edges), -1);
  std::vector<char> face_split(static_cast<std::size_t>(mesh.num_faces()), 0);
  std::vector<Eigen::RowVector3d> added;
  for (int e = 0; e < topology.num_edges; e += stride) {
    const int h0 = topology.edge_halfedges(e, 0), h1 = topology.edge_halfedges(e, 1);
    if (h1 < 0 || face_split[h0 / 3] || face_split[h1 / 3]) continue;
    face_split[h0 / 3] = face_split[h1 / 3] = 1;
    const int a = topology.edge_vertices(e, 0), b = topology.edge_vertices(e, 1);
    split_vertex[e] = mesh.num_vertices() + static_cast<int>(added.size());
    added.emplace_back((1 - t) * mesh.positions.row(a) + t * mesh.positions.row(b));
  }
  std::vector<Eigen::Vector3i> faces;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    int k = 0;
    while (k < 3 && split_vertex[topology.face_edges(f, k)] < 0) ++k;
    if (k == 3) {
      faces.emplace_back(mesh.triangles(f, 0), mesh.triangles(f, 1), mesh.triangles(f, 2));
      continue;
    }
    // The split edge is opposite corner k: (k + 1, k + 2) becomes (k + 1, p, k + 2).
    const int c = mesh.triangles(f, k), i = mesh.triangles(f, (k + 1) % 3),
              j = mesh.triangles(f, (k + 2) % 3), p = split_vertex[topology.face_edges(f, k)];
    faces.emplace_back(c, i, p);
    faces.emplace_back(c, p, j);
  }
  return with_added_vertices(mesh, added, faces);
}

/// Moves every vertex in its tangent plane (the plane normal to the area-weighted mean of its
/// faces' normals) by a random vector of length up to `amount` times its shortest edge, as a
/// scanner's noise and a remesher's irregular sampling do: the surface keeps its shape, its
/// triangulation becomes far from Delaunay.
inline Mesh jitter_tangentially(const Mesh& mesh, double amount, unsigned seed) {
  const int nv = mesh.num_vertices();
  Eigen::Matrix<double, Eigen::Dynamic, 3> normal =
      Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(nv, 3);
  Eigen::VectorXd shortest = Eigen::VectorXd::Constant(nv, std::numeric_limits<double>::infinity());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::RowVector3d a = mesh.positions.row(mesh.triangles(f, 0));
    const Eigen::RowVector3d b = mesh.positions.row(mesh.triangles(f, 1));
    const Eigen::RowVector3d c = mesh.positions.row(mesh.triangles(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a);  // twice the area times the unit normal
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k);
      normal.row(v) += n;
      const double edge =
          (mesh.positions.row(mesh.triangles(f, (k + 1) % 3)) - mesh.positions.row(v)).norm();
      shortest[v] = std::min(shortest[v], edge);
      shortest[mesh.triangles(f, (k + 1) % 3)] =
          std::min(shortest[mesh.triangles(f, (k + 1) % 3)], edge);
    }
  }
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> angle(0, 2 * 3.14159265358979323846), radius(0, 1);
  Mesh out = mesh;
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d n = normal.row(v).normalized();
    // Two unit vectors spanning the tangent plane.
    const Eigen::Vector3d helper =
        std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d t1 = n.cross(helper).normalized(), t2 = n.cross(t1);
    const double phi = angle(random), r = amount * shortest[v] * std::sqrt(radius(random));
    out.positions.row(v) += (r * (std::cos(phi) * t1 + std::sin(phi) * t2)).transpose();
  }
  return out;
}

/// A CAD-style strip: `n` segments along each long side of a 1 by `width` rectangle (slightly
/// bent), triangulated as two fans from opposite corners, as CAD tessellators do. Its triangles
/// have angles down to about width / n radians at the fan centres and are far from Delaunay.
inline Mesh cad_strip(int n, double width) {
  Mesh mesh;
  mesh.positions.resize(2 * (n + 1), 3);
  mesh.triangles.resize(2 * n, 3);
  for (int i = 0; i <= n; ++i) {
    const double x = static_cast<double>(i) / n, z = 0.02 * std::sin(3.0 * x);
    mesh.positions.row(i) << x, 0, z;              // bottom B_i
    mesh.positions.row(n + 1 + i) << x, width, z;  // top T_i
  }
  for (int i = 0; i < n; ++i) {
    mesh.triangles.row(i) << n + 1, i, i + 1;              // fan from T_0 over the bottom
    mesh.triangles.row(n + i) << n, n + 2 + i, n + 1 + i;  // fan from B_n over the top
  }
  return mesh;
}

/// An icosphere with every face split 1-to-3 at a point near its first corner (barycentric
/// weights 1 - 2 weight, weight, weight), lifted 1 % off the sphere: valence-3 vertices, needles.
inline Mesh icosphere_split_near_corners(int subdivisions, double weight) {
  const Mesh sphere = make_icosphere(subdivisions);
  const int nv = sphere.num_vertices(), nf = sphere.num_faces();
  Mesh mesh;
  mesh.positions.resize(nv + nf, 3);
  mesh.positions.topRows(nv) = sphere.positions;
  mesh.triangles.resize(3 * nf, 3);
  for (int f = 0; f < nf; ++f) {
    const int a = sphere.triangles(f, 0), b = sphere.triangles(f, 1), c = sphere.triangles(f, 2);
    mesh.positions.row(nv + f) =
        1.01 * ((1 - 2 * weight) * sphere.positions.row(a) +
                weight * (sphere.positions.row(b) + sphere.positions.row(c)));
    mesh.triangles.row(3 * f) << a, b, nv + f;
    mesh.triangles.row(3 * f + 1) << b, c, nv + f;
    mesh.triangles.row(3 * f + 2) << c, a, nv + f;
  }
  return mesh;
}

}  // namespace ricci::testing
