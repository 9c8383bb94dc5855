/// A linear baseline for `ricci sphere`, in the style of boundary-first-flattening's sphere mode
/// (docs/sphere.md, "Compared with boundary-first-flattening").
///
///   ricci_sphere_baseline MESH...
///
/// This is our own re-implementation of the *linear approach*, not BFF: BFF's interior is a
/// cotangent-Laplacian (harmonic) extension, and its sphere mode punctures the mesh at a vertex,
/// flattens the disk with its boundary on a circle, projects stereographically and centres. Here,
/// for each mesh:
///   1. the pole is the one `ricci sphere` takes (choose_pole_vertex); it is removed with its star;
///   2. the boundary (the pole's link) goes onto the unit circle, counter-clockwise, at angles
///      proportional to cumulative 3D edge length (BFF instead solves for a conformal boundary
///      length distribution; this baseline does not);
///   3. the interior uv solve the cotangent-Laplacian Dirichlet problem, weights
///      (cot alpha + cot beta) / 2 on each interior edge (negative on non-Delaunay edges);
///   4. the same mirrored inverse stereographic projection and 5. the same Moebius centring as
///      sphere_map (docs/sphere.md steps 4-5; the few lines are re-implemented here because
///      sphere.cpp keeps them private).
/// It prints, for the baseline and for sphere_map (the library: default options, i.e. Thurston,
/// line ricci-sphere, and vertex scaling with flips, line ricci-sphere-vs) on the same mesh:
/// disk faces with planar signed area <= 0, spherical faces with det(P_i, P_j, P_k) <= 0 (the test
/// of SphereResult::inverted_faces), the spherical area sum, the angle distortion
/// sigma_max / sigma_min of each 3D triangle -> chordal triangle (3D-area-weighted mean, max) and
/// the time; for the baseline also the number of negative cotangent weights.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "ricci/mesh/io.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"
#include "ricci/sphere/sphere.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using ricci::Mesh;
using ricci::Positions;
using Plane = Eigen::Matrix<double, Eigen::Dynamic, 2>;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Eigen::Vector3d vertex(const Positions& P, int v) {
  return P.row(v).transpose();
}

/// det(a, b, c) from differences, as in sphere.cpp.
double det3(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return a.dot((b - a).cross(c - a));
}

/// docs/sphere.md step 4: (x, y) -> (2x, -2y, |p|^2 - 1) / (1 + |p|^2).
Eigen::Vector3d lift(double x, double y) {
  const double r2 = x * x + y * y;
  return Eigen::Vector3d(2 * x, -2 * y, r2 - 1) / (1 + r2);
}

/// docs/sphere.md step 5: centre of mass c = sum_f w_f n_f of the input's area and M.
void centre_of_mass(const Positions& P, const ricci::Triangles& F, const Eigen::VectorXd& w,
                    Eigen::Vector3d& c, Eigen::Matrix3d& M) {
  c.setZero();
  M.setZero();
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d s = vertex(P, F(f, 0)) + vertex(P, F(f, 1)) + vertex(P, F(f, 2));
    if (!(s.norm() > 0)) continue;
    const Eigen::Vector3d n = s.normalized();
    c += w[f] * n;
    M += w[f] * (Eigen::Matrix3d::Identity() - n * n.transpose());
  }
}

/// docs/sphere.md step 5: damped Newton on the boost phi_a(x) = (1-|a|^2)(x-a)/|x-a|^2 - a
/// (2 M a = c, |a| <= 0.5, halved until |c| decreases), until |c| <= 1e-12 or 100 steps.
/// Returns the final |c|.
double centre(Positions& P, const std::vector<int>& referenced, const Mesh& mesh,
              const Eigen::VectorXd& w, int& steps) {
  Eigen::Vector3d c;
  Eigen::Matrix3d M;
  centre_of_mass(P, mesh.triangles, w, c, M);
  Positions trial;
  for (steps = 0; c.norm() > 1e-12 && steps < 100; ++steps) {
    Eigen::Vector3d a = (2 * M).ldlt().solve(c);
    if (!a.allFinite()) a = c / 2;
    if (a.norm() > 0.5) a *= 0.5 / a.norm();
    bool accepted = false;
    for (int halving = 0; halving < 40 && !accepted; ++halving, a /= 2) {
      trial = P;
      for (int v : referenced) {
        const Eigen::Vector3d d = vertex(P, v) - a;
        const Eigen::Vector3d y = (1 - a.squaredNorm()) / d.squaredNorm() * d - a;
        trial.row(v) = y.normalized().transpose();
      }
      Eigen::Vector3d c2;
      Eigen::Matrix3d M2;
      centre_of_mass(trial, mesh.triangles, w, c2, M2);
      if (c2.norm() < c.norm()) {
        P.swap(trial);
        c = c2;
        M = M2;
        accepted = true;
      }
    }
    if (!accepted) break;
  }
  return c.norm();
}

/// sigma_max / sigma_min of the linear map from triangle p to triangle q (each in its own plane):
/// with J the 2 by 2 matrix in orthonormal frames, s1^2 + s2^2 = |J|_F^2 and s1 s2 = |det J|, so
/// s1 / s2 = (F + sqrt(F^2 - 4 D^2)) / (2 D). Infinite for a degenerate image.
double distortion(const Eigen::Vector3d (&p)[3], const Eigen::Vector3d (&q)[3]) {
  auto local = [](const Eigen::Vector3d(&t)[3]) {
    const Eigen::Vector3d e1 = t[1] - t[0], e2 = t[2] - t[0];
    const double l1 = e1.norm();
    Eigen::Matrix2d E;
    E << l1, e1.dot(e2) / l1, 0, e1.cross(e2).norm() / l1;
    return E;
  };
  const Eigen::Matrix2d P = local(p), Q = local(q);
  if (!(P.determinant() > 0) || !(std::abs(Q.determinant()) > 0)) {
    return std::numeric_limits<double>::infinity();
  }
  const Eigen::Matrix2d J = Q * P.inverse();
  const double F = J.squaredNorm(), D = std::abs(J.determinant());
  return (F + std::sqrt(std::max(F * F - 4 * D * D, 0.0))) / (2 * D);
}

struct Figures {
  int planar_flipped = 0;    ///< disk faces with signed area <= 0 in the plane
  int inverted = 0;          ///< faces with det(P_i, P_j, P_k) <= 0
  double area_sum = 0;       ///< sum of signed spherical areas (4 pi for a single cover)
  double mean = 0, max = 0;  ///< angle distortion: 3D-area-weighted mean, max
  double seconds = 0;
  double centre = 0;         ///< |centre of mass| after the normalisation
  int negative_weights = 0;  ///< interior edges with a negative cotangent weight (baseline)
  int interior_edges = 0;
};

/// Face weights: share of the 3D area.
Eigen::VectorXd area_weights(const Mesh& mesh) {
  Eigen::VectorXd w(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = vertex(mesh.positions, mesh.triangles(f, 0));
    w[f] = (vertex(mesh.positions, mesh.triangles(f, 1)) - a)
               .cross(vertex(mesh.positions, mesh.triangles(f, 2)) - a)
               .norm();
  }
  return w / w.sum();
}

/// Planar flips over the faces that do not touch the pole; spherical figures over all faces.
void measure(const Mesh& mesh, int pole, const Plane& plane, const Positions& P,
             const Eigen::VectorXd& w, Figures& out) {
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int i = mesh.triangles(f, 0), j = mesh.triangles(f, 1), k = mesh.triangles(f, 2);
    if (i != pole && j != pole && k != pole) {
      const Eigen::Vector2d a = plane.row(i), b = plane.row(j), c = plane.row(k);
      const Eigen::Vector2d u = b - a, v = c - a;
      if (!(u.x() * v.y() - u.y() * v.x() > 0)) ++out.planar_flipped;
    }
    Eigen::Vector3d p[3], q[3];
    for (int m = 0; m < 3; ++m) {
      p[m] = vertex(mesh.positions, mesh.triangles(f, m));
      q[m] = vertex(P, mesh.triangles(f, m));
    }
    const double det = det3(q[0], q[1], q[2]);
    if (!(det > 0)) ++out.inverted;
    out.area_sum += 2 * std::atan2(det, 1 + q[0].dot(q[1]) + q[1].dot(q[2]) + q[2].dot(q[0]));
    const double r = distortion(p, q);
    out.mean += w[f] * r;
    out.max = std::max(out.max, r);
  }
}

/// The linear baseline (see the file comment).
Figures baseline(const Mesh& mesh) {
  const auto start = Clock::now();
  Figures out;
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  const int pole = ricci::choose_pole_vertex(mesh);
  const ricci::Topology topology = ricci::build_topology(mesh.triangles, nv);

  // 1. The disk: faces not touching the pole; its boundary loop (disk on the left).
  ricci::Triangles disk_faces(nf, 3);
  int nd = 0;
  for (int f = 0; f < nf; ++f) {
    if ((mesh.triangles.row(f).array() != pole).all()) disk_faces.row(nd++) = mesh.triangles.row(f);
  }
  disk_faces.conservativeResize(nd, 3);
  const ricci::Topology disk = ricci::build_topology(disk_faces, nv);
  if (disk.boundary_loops.size() != 1) throw std::runtime_error("the pole's star left no disk");
  const std::vector<int>& loop = disk.boundary_loops[0];

  // 2. Boundary on the unit circle by cumulative 3D length, counter-clockwise.
  Plane plane = Plane::Constant(nv, 2, std::numeric_limits<double>::quiet_NaN());
  std::vector<double> cumulative(loop.size() + 1, 0.0);
  for (std::size_t k = 0; k < loop.size(); ++k) {
    cumulative[k + 1] = cumulative[k] + (vertex(mesh.positions, loop[(k + 1) % loop.size()]) -
                                         vertex(mesh.positions, loop[k]))
                                            .norm();
  }
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const double theta = 2 * std::numbers::pi * cumulative[k] / cumulative.back();
    plane.row(loop[k]) << std::cos(theta), std::sin(theta);
  }

  // 3. Interior: cotangent Laplacian, Dirichlet boundary. Weight of edge (i, j):
  // sum over its faces of cot(angle opposite) / 2.
  std::vector<int> index(nv, -1);
  int ni = 0;
  for (int v = 0; v < nv; ++v) {
    if (v != pole && disk.vertex_component[v] >= 0 && !disk.is_boundary_vertex[v]) index[v] = ni++;
  }
  Eigen::VectorXd edge_weight = Eigen::VectorXd::Zero(disk.num_edges);
  for (int f = 0; f < nd; ++f) {
    for (int m = 0; m < 3; ++m) {
      const Eigen::Vector3d a = vertex(mesh.positions, disk_faces(f, m));
      const Eigen::Vector3d u = vertex(mesh.positions, disk_faces(f, (m + 1) % 3)) - a;
      const Eigen::Vector3d v = vertex(mesh.positions, disk_faces(f, (m + 2) % 3)) - a;
      edge_weight[disk.face_edges(f, m)] += 0.5 * u.dot(v) / u.cross(v).norm();
    }
  }
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(ni, 2);
  for (int e = 0; e < disk.num_edges; ++e) {
    if (disk.is_boundary_edge[e]) continue;
    ++out.interior_edges;
    const double we = edge_weight[e];
    if (we < 0) ++out.negative_weights;
    const int a = disk.edge_vertices(e, 0), b = disk.edge_vertices(e, 1);
    for (auto [s, t] : {std::pair{a, b}, std::pair{b, a}}) {
      if (index[s] < 0) continue;
      triplets.emplace_back(index[s], index[s], we);
      if (index[t] >= 0) {
        triplets.emplace_back(index[s], index[t], -we);
      } else {
        rhs.row(index[s]) += we * plane.row(t);
      }
    }
  }
  Eigen::SparseMatrix<double> L(ni, ni);
  L.setFromTriplets(triplets.begin(), triplets.end());
  ricci::SparseCholesky solver;
  solver.analyze(L);
  solver.factorize(L);
  for (int c = 0; c < 2; ++c) {
    const Eigen::VectorXd x = solver.solve(rhs.col(c));
    for (int v = 0; v < nv; ++v) {
      if (index[v] >= 0) plane(v, c) = x[index[v]];
    }
  }

  // 4. Mirrored inverse stereographic projection, the pole at (0, 0, 1).
  Positions P = Positions::Zero(nv, 3);
  std::vector<int> referenced;
  for (int v = 0; v < nv; ++v) {
    if (topology.vertex_component[v] < 0) continue;
    referenced.push_back(v);
    P.row(v) = v == pole ? Eigen::RowVector3d(0, 0, 1) : lift(plane(v, 0), plane(v, 1)).transpose();
  }

  // 5. Moebius centring.
  const Eigen::VectorXd w = area_weights(mesh);
  int steps = 0;
  out.centre = centre(P, referenced, mesh, w, steps);
  out.seconds = seconds_since(start);
  measure(mesh, pole, plane, P, w, out);
  return out;
}

Figures library(const Mesh& mesh, ricci::Scheme scheme) {
  ricci::SphereOptions options;
  options.structure.scheme = scheme;
  const ricci::SphereResult r = ricci::sphere_map(mesh, options);
  Figures out;
  measure(mesh, r.pole, r.plane, r.positions, area_weights(mesh), out);
  // The same figures as the library's own (its counts are authoritative; ours must agree).
  if (out.inverted != r.inverted_faces) std::fprintf(stderr, "warning: inverted count differs\n");
  out.seconds = r.seconds;
  out.centre = r.centre_of_mass;
  return out;
}

void print(const char* mesh, const char* method, int nv, int nf, const Figures& f) {
  std::printf("%s\t%s\t%d\t%d\t%d\t%d\t%.2g\t%.4f\t%.4g\t%.2g\t%.3f", mesh, method, nv, nf,
              f.planar_flipped, f.inverted, f.area_sum - 4 * std::numbers::pi, f.mean, f.max,
              f.centre, f.seconds);
  if (f.interior_edges > 0) std::printf("\t%d/%d", f.negative_weights, f.interior_edges);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: ricci_sphere_baseline MESH...\n");
    return 2;
  }
  std::printf(
      "mesh\tmethod\tV\tF\tplanar_flipped\tinverted\tarea-4pi\tdistortion_mean\tdistortion_max"
      "\tcentre\tseconds\tnegative_cot_weights\n");
  int status = 0;
  for (int a = 1; a < argc; ++a) {
    const std::string name = std::filesystem::path(argv[a]).stem().string();
    try {
      const Mesh mesh = ricci::read_mesh(argv[a]).mesh;
      print(name.c_str(), "linear-cotan", mesh.num_vertices(), mesh.num_faces(), baseline(mesh));
      print(name.c_str(), "ricci-sphere", mesh.num_vertices(), mesh.num_faces(),
            library(mesh, ricci::Scheme::Thurston));
      print(name.c_str(), "ricci-sphere-vs", mesh.num_vertices(), mesh.num_faces(),
            library(mesh, ricci::Scheme::VertexScaling));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", argv[a], e.what());
      status = 1;
    }
  }
  return status;
}
