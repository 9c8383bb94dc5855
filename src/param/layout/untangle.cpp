#include "ricci/param/layout/untangle.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <deque>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
using Uv = Eigen::Matrix<double, Eigen::Dynamic, 2>;
using Vec4 = Eigen::Matrix<double, 4, 1>;
using Mat4 = Eigen::Matrix<double, 4, 4>;

[[noreturn]] void invalid(const std::string& what) {
  throw InvalidInput("untangle_layout: " + what);
}

/// Copies of one mesh vertex are related by rigid motions when the seams through it are
/// congruent: two sides' lengths agree to this (relative) ...
constexpr double kRigidLength = 1e-7;
/// ... and the motions reached around the vertex by different seams agree to this (a cone's
/// copies come back rotated).
constexpr double kConsistentMotion = 1e-8;

/// A vertex's angle in the result may differ from the one it must have by this (the checker's
/// tolerance for a cone).
constexpr double kAngleTolerance = 1e-6;

/// The smallest relative energy decrease the eps update assumes for a stage (the paper's sigma).
constexpr double kSigmaFloor = 0.5;

/// z -> rotation z + translation, |rotation| = 1.
struct Motion {
  Complex rotation{1, 0};
  Complex translation{0, 0};
  Complex operator()(Complex z) const { return rotation * z + translation; }
};

Motion compose(const Motion& outer, const Motion& inner) {
  return {outer.rotation * inner.rotation, outer.rotation * inner.translation + outer.translation};
}

/// The barrier chi(D, eps) = (D + sqrt(eps^2 + D^2)) / 2, written without cancellation for D < 0,
/// and its first two derivatives (chi' = chi / r, chi'' = eps^2 / (2 r^3), r = sqrt(eps^2 + D^2)).
struct Chi {
  double value, first, second;
};

Chi chi(double d, double eps) {
  const double r = std::sqrt(eps * eps + d * d);
  const double value = d >= 0 ? 0.5 * (d + r) : 0.5 * eps * eps / (r - d);
  return {value, value / r, 0.5 * eps * eps / (r * r * r)};
}

/// A face's reference: the 3D triangle in a frame of its plane, scaled to the layout's local
/// scale; J = sum_k u_k g_k^T with g the gradients of the barycentric coordinates.
struct Reference {
  Eigen::Vector2d g[3];
  bool valid = false;
};

/// The face energy of J = [[a, b], [c, d]] (vec order a, b, c, d), with gradient and a positive
/// semi-definite projection of its Hessian when asked.
double face_energy(const Vec4& j, double eps, double theta, Vec4* gradient, Mat4* hessian) {
  const double det = j[0] * j[3] - j[1] * j[2];
  const double frobenius = j.squaredNorm();
  const Chi c = chi(det, eps);
  const double h = 1 / c.value;
  const double energy = ((1 - theta) * frobenius + theta * (det * det + 1)) * h;
  if (gradient == nullptr) return energy;
  const double h1 = -c.first * h * h;
  const double h2 = 2 * c.first * c.first * h * h * h - c.second * h * h;
  const Vec4 q(j[3], -j[2], -j[1], j[0]);  // grad det
  // Shape: |J|^2 h(det).
  *gradient = (1 - theta) * (2 * h * j + frobenius * h1 * q);
  // Area: phi(det) = (det^2 + 1) h(det).
  const double phi1 = 2 * det * h + (det * det + 1) * h1;
  const double phi2 = 2 * h + 4 * det * h1 + (det * det + 1) * h2;
  *gradient += theta * phi1 * q;
  if (hessian == nullptr) return energy;
  Mat4 p = Mat4::Zero();  // Hessian of det
  p(0, 3) = p(3, 0) = 1;
  p(1, 2) = p(2, 1) = -1;
  Mat4 hs = 2 * h * Mat4::Identity() + 2 * h1 * (j * q.transpose() + q * j.transpose()) +
            frobenius * h2 * q * q.transpose() + frobenius * h1 * p;
  Mat4 ha = phi2 * q * q.transpose() + phi1 * p;
  const Mat4 full = (1 - theta) * hs + theta * ha;
  Eigen::SelfAdjointEigenSolver<Mat4> eig(full);
  const Vec4 lambda = eig.eigenvalues().cwiseMax(0.0);
  *hessian = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
  return energy;
}

double signed_area(const Uv& uv, const Triangles& t, int f) {
  const Eigen::Vector2d a = uv.row(t(f, 0)).transpose();
  const Eigen::Vector2d b = uv.row(t(f, 1)).transpose() - a;
  const Eigen::Vector2d c = uv.row(t(f, 2)).transpose() - a;
  return b.x() * c.y() - b.y() * c.x();
}

}  // namespace

UntangleResult untangle_layout(const Mesh& mesh, const Triangles& uv_triangles, const Uv& uv,
                               const UntangleOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int nf = mesh.num_faces(), nv = mesh.num_vertices();
  const int nuv = static_cast<int>(uv.rows());
  if (uv_triangles.rows() != nf) {
    invalid("uv_triangles has " + std::to_string(uv_triangles.rows()) + " rows but the mesh has " +
            std::to_string(nf) + " faces");
  }
  if (!options.angles.empty() && static_cast<int>(options.angles.size()) != nv) {
    invalid("angles has " + std::to_string(options.angles.size()) + " entries for " +
            std::to_string(nv) + " vertices");
  }
  if (!options.fixed.empty() && static_cast<int>(options.fixed.size()) != nv) {
    invalid("fixed has " + std::to_string(options.fixed.size()) + " entries for " +
            std::to_string(nv) + " vertices");
  }
  if (options.rings < 0 || options.max_rings < options.rings || options.newton_iterations < 1 ||
      options.max_stages < 1 || options.stall_stages < 1 || options.max_face_iterations < 0 ||
      !(options.area_weight >= 0 && options.area_weight < 1) || !(options.min_det > 0)) {
    invalid("an option is out of range");
  }
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      if (uv_triangles(f, k) < 0 || uv_triangles(f, k) >= nuv) {
        invalid("face " + std::to_string(f) + " has uv index " +
                std::to_string(uv_triangles(f, k)) + " out of range");
      }
    }
  }
  UntangleResult result;
  result.uv = uv;
  Uv& out = result.uv;
  // 3D shapes: a face of zero or non-finite area has no shape to untangle towards (and is not
  // counted as flipped).
  std::vector<double> area3(nf, 0);
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d p0 = mesh.positions.row(mesh.triangles(f, 0)).transpose();
    const Eigen::Vector3d e1 = mesh.positions.row(mesh.triangles(f, 1)).transpose() - p0;
    const Eigen::Vector3d e2 = mesh.positions.row(mesh.triangles(f, 2)).transpose() - p0;
    const double a = 0.5 * e1.cross(e2).norm();
    area3[f] = std::isfinite(a) ? a : 0;
  }
  auto is_flipped = [&](int f) { return area3[f] > 0 && !(signed_area(out, uv_triangles, f) > 0); };
  std::vector<int> flipped;
  for (int f = 0; f < nf; ++f) {
    if (is_flipped(f)) flipped.push_back(f);
  }
  result.flipped_before = static_cast<int>(flipped.size());
  result.flipped_after = result.flipped_before;
  auto finish = [&] {
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  };
  if (flipped.empty()) return finish();
  const Topology topology = build_topology(mesh.triangles, nv);

  // Faces around each mesh vertex.
  std::vector<int> face_offset(nv + 1, 0), vertex_faces(3 * static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) ++face_offset[mesh.triangles(f, k) + 1];
  }
  for (int v = 0; v < nv; ++v) face_offset[v + 1] += face_offset[v];
  {
    std::vector<int> next(face_offset.begin(), face_offset.end() - 1);
    for (int f = 0; f < nf; ++f) {
      for (int k = 0; k < 3; ++k) vertex_faces[next[mesh.triangles(f, k)]++] = f;
    }
  }
  auto corner_of = [&](int f, int v) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.triangles(f, k) == v) return k;
    }
    return -1;
  };

  // Each layout vertex as the image of its mesh vertex's reference copy (the copy of the vertex
  // in its first face) under a rigid motion, found across the seams through the vertex.
  std::vector<int> reference(nv, -1);
  std::vector<Motion> motion(nuv);
  std::vector<char> known(nuv, 0), movable(nv, 1);
  for (int v = 0; v < nv; ++v) {
    if (face_offset[v] == face_offset[v + 1]) {
      movable[v] = 0;
      continue;
    }
    reference[v] =
        uv_triangles(vertex_faces[face_offset[v]], corner_of(vertex_faces[face_offset[v]], v));
    known[reference[v]] = 1;
    if (!options.fixed.empty() && options.fixed[v]) movable[v] = 0;
    if (!options.move_boundary && topology.is_boundary_vertex[v]) movable[v] = 0;
  }
  // Seam edges: the motion from one side's copies to the other's, for each end whose copies
  // differ. Propagated until nothing changes (a vertex has few copies).
  struct Link {
    int vertex, from, to;
    Motion m;
  };
  std::vector<Link> links;
  for (int e = 0; e < topology.num_edges; ++e) {
    const int h0 = topology.edge_halfedges(e, 0), h1 = topology.edge_halfedges(e, 1);
    if (h0 < 0 || h1 < 0) continue;
    const int f0 = Topology::face_of(h0), f1 = Topology::face_of(h1);
    const int a = topology.tail(h0), b = topology.head(h0);
    const int a0 = uv_triangles(f0, corner_of(f0, a)), b0 = uv_triangles(f0, corner_of(f0, b));
    const int a1 = uv_triangles(f1, corner_of(f1, a)), b1 = uv_triangles(f1, corner_of(f1, b));
    if (a0 == a1 && b0 == b1) continue;
    const Complex pa0(out(a0, 0), out(a0, 1)), pb0(out(b0, 0), out(b0, 1));
    const Complex pa1(out(a1, 0), out(a1, 1)), pb1(out(b1, 0), out(b1, 1));
    const double l0 = std::abs(pb0 - pa0), l1 = std::abs(pb1 - pa1);
    if (a0 == a1 || b0 == b1 || !(l0 > 0) ||
        !(std::abs(l0 - l1) <= kRigidLength * std::max(l0, l1))) {
      // Not a rigid seam (a free-boundary chart's seams bend): its ends stay.
      movable[a] = movable[b] = 0;
      continue;
    }
    Motion m;
    m.rotation = (pb1 - pa1) / (pb0 - pa0);
    m.rotation /= std::abs(m.rotation);
    m.translation = pa1 - m.rotation * pa0;
    const Motion inverse{std::conj(m.rotation), -std::conj(m.rotation) * m.translation};
    links.push_back({a, a0, a1, m});
    links.push_back({a, a1, a0, inverse});
    links.push_back({b, b0, b1, m});
    links.push_back({b, b1, b0, inverse});
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (const Link& l : links) {
      if (!known[l.from]) continue;
      const Motion m = compose(l.m, motion[l.from]);
      if (!known[l.to]) {
        motion[l.to] = m;
        known[l.to] = 1;
        changed = true;
        continue;
      }
      const double scale = std::abs(Complex(out(l.to, 0), out(l.to, 1))) + 1;
      if (std::abs(m.rotation - motion[l.to].rotation) > kConsistentMotion ||
          std::abs(m.translation - motion[l.to].translation) > kConsistentMotion * scale) {
        movable[l.vertex] = 0;  // the copies come back moved: a cone (or an inconsistent seam)
      }
    }
  }
  // Every copy must have been reached from the reference, and must sit where its motion says.
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k), c = uv_triangles(f, k);
      if (!movable[v]) continue;
      const Complex p(out(c, 0), out(c, 1));
      const int r = reference[v];
      const Complex image = motion[c](Complex(out(r, 0), out(r, 1)));
      if (!known[c] || std::abs(image - p) > kConsistentMotion * (std::abs(p) + 1)) {
        movable[v] = 0;
      }
    }
  }
  std::vector<std::vector<int>> copies(nv);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      std::vector<int>& list = copies[mesh.triangles(f, k)];
      if (std::find(list.begin(), list.end(), uv_triangles(f, k)) == list.end()) {
        list.push_back(uv_triangles(f, k));
      }
    }
  }

  std::vector<char> stuck(nf, 0);
  for (int f : flipped) {
    bool any = false;
    for (int k = 0; k < 3; ++k) any = any || movable[mesh.triangles(f, k)];
    stuck[f] = !any;
  }
  if (options.give_up_when_stuck && std::count(stuck.begin(), stuck.end(), 1) > 0) {
    result.stuck_faces = static_cast<int>(std::count(stuck.begin(), stuck.end(), 1));
    return finish();
  }
  // The angle each interior vertex must have in the result: the options', else 2 pi where it
  // may move (a vertex that stays keeps whatever angle the layout gives it).
  std::vector<double> expected_angle(nv, std::numeric_limits<double>::quiet_NaN());
  for (int v = 0; v < nv; ++v) {
    if (topology.is_boundary_vertex[v]) continue;
    if (!options.angles.empty()) {
      expected_angle[v] = options.angles[v];
    } else if (movable[v]) {
      expected_angle[v] = 2 * std::numbers::pi;
    }
  }
  const double theta = options.area_weight;
  const long long budget =
      options.max_face_iterations > 0 ? options.max_face_iterations : 50LL * nf + 100000;
  long long work = 0;
  std::vector<int> variable(nv, -1), face_mark(nf, 0);

  // One cluster of variables (mesh vertices, each moving all its copies) with the faces around
  // them, untangled together; its moves are kept only when they leave none of its faces flipped
  // or degenerate that was not so before, and untangle at least one. Returns whether kept.
  auto solve_cluster = [&](std::vector<int> variables) {
    for (std::size_t i = 0; i < variables.size(); ++i) variable[variables[i]] = static_cast<int>(i);
    std::vector<int> faces;
    for (int v : variables) {
      for (int s = face_offset[v]; s < face_offset[v + 1]; ++s) {
        const int f = vertex_faces[s];
        if (!face_mark[f]) face_mark[f] = 1, faces.push_back(f);
      }
    }
    for (int f : faces) face_mark[f] = 0;
    std::sort(faces.begin(), faces.end());
    // A cluster whose every vertex may move (a whole small component) could shrink to a point,
    // where the energy is least for large eps: its largest positive face stays as an anchor.
    bool anchored = false;
    for (int f : faces) {
      for (int k = 0; k < 3; ++k) anchored = anchored || variable[mesh.triangles(f, k)] < 0;
    }
    if (!anchored) {
      int anchor = -1;
      for (int f : faces) {
        if (area3[f] > 0 && (anchor < 0 || signed_area(out, uv_triangles, f) >
                                               signed_area(out, uv_triangles, anchor))) {
          anchor = f;
        }
      }
      if (anchor < 0 || !(signed_area(out, uv_triangles, anchor) > 0)) {
        for (int v : variables) variable[v] = -1;
        return false;
      }
      for (int k = 0; k < 3; ++k) variable[mesh.triangles(anchor, k)] = -1;
      std::vector<int> kept;
      for (int v : variables) {
        if (variable[v] >= 0) kept.push_back(v);
      }
      variables = std::move(kept);
      for (std::size_t i = 0; i < variables.size(); ++i) {
        variable[variables[i]] = static_cast<int>(i);
      }
      if (variables.empty()) return false;
    }

    // References at the local scale: a face's scale is the mean of its vertices' (those with
    // positive faces); faces with none take the cluster's mean.
    auto vertex_scale = [&](int v) {
      double a2 = 0, a3 = 0;
      for (int s = face_offset[v]; s < face_offset[v + 1]; ++s) {
        const int f = vertex_faces[s];
        const double a = 0.5 * signed_area(out, uv_triangles, f);
        if (a > 0 && area3[f] > 0) a2 += a, a3 += area3[f];
      }
      return a3 > 0 ? a2 / a3 : 0.0;
    };
    std::vector<std::array<double, 3>> corner_scale(faces.size());
    double cluster_scale = 0;
    int counted = 0;
    for (std::size_t i = 0; i < faces.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        corner_scale[i][k] = vertex_scale(mesh.triangles(faces[i], k));
        if (corner_scale[i][k] > 0) cluster_scale += corner_scale[i][k], ++counted;
      }
    }
    cluster_scale = counted > 0 ? cluster_scale / counted : 1;
    std::vector<Reference> refs(faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i) {
      const int f = faces[i];
      double s = 0;
      int n = 0;
      for (int k = 0; k < 3; ++k) {
        if (corner_scale[i][k] > 0) s += corner_scale[i][k], ++n;
      }
      s = std::sqrt(n > 0 ? s / n : cluster_scale);
      const Eigen::Vector3d p0 = mesh.positions.row(mesh.triangles(f, 0)).transpose();
      const Eigen::Vector3d e1 = mesh.positions.row(mesh.triangles(f, 1)).transpose() - p0;
      const Eigen::Vector3d e2 = mesh.positions.row(mesh.triangles(f, 2)).transpose() - p0;
      const double l1 = e1.norm();
      if (!(area3[f] > 0) || !(l1 > 0) || !(s > 0) || !std::isfinite(s)) continue;
      const double x1 = s * l1, x2 = s * e1.dot(e2) / l1, y2 = s * 2 * area3[f] / l1;
      Reference& r = refs[i];
      r.g[1] = Eigen::Vector2d(1 / x1, -x2 / (x1 * y2));
      r.g[2] = Eigen::Vector2d(0, 1 / y2);
      r.g[0] = -(r.g[1] + r.g[2]);
      r.valid = true;
    }
    // The variables' positions (their reference copies) and a copy's position from them.
    const int n = static_cast<int>(variables.size());
    Eigen::VectorXd x(2 * n);
    for (int i = 0; i < n; ++i) {
      const int r = reference[variables[i]];
      x[2 * i] = out(r, 0), x[2 * i + 1] = out(r, 1);
    }
    const Eigen::VectorXd x_start = x;
    auto position = [&](const Eigen::VectorXd& at, int f, int k) {
      const int v = mesh.triangles(f, k), c = uv_triangles(f, k);
      if (variable[v] < 0) return Eigen::Vector2d(out(c, 0), out(c, 1));
      const Complex z = motion[c](Complex(at[2 * variable[v]], at[2 * variable[v] + 1]));
      return Eigen::Vector2d(z.real(), z.imag());
    };
    auto jacobian = [&](const Eigen::VectorXd& at, std::size_t i) {
      const int f = faces[i];
      Eigen::Matrix2d j = Eigen::Matrix2d::Zero();
      for (int k = 0; k < 3; ++k) j += position(at, f, k) * refs[i].g[k].transpose();
      return Vec4(j(0, 0), j(0, 1), j(1, 0), j(1, 1));
    };
    auto det_of = [](const Vec4& j) { return j[0] * j[3] - j[1] * j[2]; };
    auto min_det = [&](const Eigen::VectorXd& at) {
      double m = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < faces.size(); ++i) {
        if (refs[i].valid) m = std::min(m, det_of(jacobian(at, i)));
      }
      return m;
    };
    auto total = [&](const Eigen::VectorXd& at, double eps) {
      double e = 0;
      for (std::size_t i = 0; i < faces.size(); ++i) {
        if (refs[i].valid) e += face_energy(jacobian(at, i), eps, theta, nullptr, nullptr);
      }
      return e;
    };
    // One eps stage: Newton with projected face Hessians, backtracking on the energy.
    std::vector<Eigen::Triplet<double>> triplets;
    SparseCholesky solver;
    bool analysed = false;
    auto minimise = [&](double eps) {
      for (int it = 0; it < options.newton_iterations && work < budget; ++it) {
        ++result.newton_iterations;
        work += static_cast<long long>(faces.size());
        Eigen::VectorXd g = Eigen::VectorXd::Zero(2 * n);
        triplets.clear();
        double e = 0;
        for (int i = 0; i < 2 * n; ++i) triplets.emplace_back(i, i, 0.0);
        for (std::size_t i = 0; i < faces.size(); ++i) {
          if (!refs[i].valid) continue;
          const int f = faces[i];
          Vec4 gj;
          Mat4 hj;
          e += face_energy(jacobian(x, i), eps, theta, &gj, &hj);
          // d vec(J) / d w for each corner whose vertex is a variable: B_k R (R: the copy's
          // rotation), B_k = [[g0 g1 0 0], [0 0 g0 g1]]^T per corner.
          Eigen::Matrix<double, 4, 6> b = Eigen::Matrix<double, 4, 6>::Zero();
          int slot[3];
          for (int k = 0; k < 3; ++k) {
            slot[k] = variable[mesh.triangles(f, k)];
            if (slot[k] < 0) continue;
            const Complex r = motion[uv_triangles(f, k)].rotation;
            Eigen::Matrix<double, 4, 2> bk = Eigen::Matrix<double, 4, 2>::Zero();
            bk(0, 0) = refs[i].g[k].x(), bk(1, 0) = refs[i].g[k].y();
            bk(2, 1) = refs[i].g[k].x(), bk(3, 1) = refs[i].g[k].y();
            Eigen::Matrix2d rot;
            rot << r.real(), -r.imag(), r.imag(), r.real();
            b.middleCols<2>(2 * k) = bk * rot;
          }
          const Eigen::Matrix<double, 6, 1> gf = b.transpose() * gj;
          const Eigen::Matrix<double, 6, 6> hf = b.transpose() * hj * b;
          for (int k = 0; k < 3; ++k) {
            if (slot[k] < 0) continue;
            g.segment<2>(2 * slot[k]) += gf.segment<2>(2 * k);
            for (int l = 0; l < 3; ++l) {
              if (slot[l] < 0) continue;
              for (int a = 0; a < 2; ++a) {
                for (int c = 0; c < 2; ++c) {
                  triplets.emplace_back(2 * slot[k] + a, 2 * slot[l] + c, hf(2 * k + a, 2 * l + c));
                }
              }
            }
          }
        }
        Eigen::SparseMatrix<double> h(2 * n, 2 * n);
        h.setFromTriplets(triplets.begin(), triplets.end());
        double diagonal = 0;
        for (int i = 0; i < 2 * n; ++i) diagonal = std::max(diagonal, h.coeff(i, i));
        if (!(diagonal > 0) || !std::isfinite(diagonal) || !g.allFinite()) return;
        // A small shift keeps the system definite where a variable's faces are all conformal
        // (their projected Hessians may be singular in a direction).
        for (int i = 0; i < 2 * n; ++i) h.coeffRef(i, i) += 1e-9 * diagonal;
        Eigen::VectorXd d;
        try {
          if (!analysed) solver.analyze(h), analysed = true;  // one pattern per cluster
          solver.factorize(h);
          d = -solver.solve(g);
        } catch (const SolverError&) {
          d = -g / diagonal;
        }
        const double slope = g.dot(d);
        if (!(slope < 0) || !d.allFinite()) return;
        bool accepted = false;
        for (double t = 1; t > 1e-12; t *= 0.5) {
          const Eigen::VectorXd trial = x + t * d;
          const double et = total(trial, eps);
          if (et <= e + 1e-4 * t * slope) {
            x = trial;
            accepted = true;
            if (e - et < 1e-9 * e) return;  // this stage has converged
            break;
          }
        }
        if (!accepted) return;
      }
    };
    double worst = min_det(x);
    double eps = std::sqrt(1e-12 + 0.04 * std::min(worst, 0.0) * std::min(worst, 0.0));
    // Stages until the faces are positive and, after that, until the energy settles (a face
    // just past det = 0 is a sliver: the barrier, eps -> 0, pulls it back into shape).
    double stalled_at = worst;
    int stalled = 0;
    for (int stage = 0; stage < options.max_stages && work < budget; ++stage) {
      const double before = total(x, eps);
      minimise(eps);
      const double after = total(x, eps);
      if (worst > options.min_det && !(before - after > 1e-3 * after)) break;
      worst = min_det(x);
      // No progress towards positive faces for a while: a face no move of these vertices can
      // open (a cone whose angle its faces cannot hold), or one that needs a larger region.
      if (worst > stalled_at + 0.1 * (options.min_det - stalled_at)) {
        stalled_at = worst;
        stalled = 0;
      } else if (!(worst > options.min_det) && ++stalled >= options.stall_stages) {
        break;
      }
      // The paper's floor for sigma is 0.1 (eps shrinks by about 5 % a stage once the energy
      // settles); 0.5 shrinks it by about 30 %: CAD parts with 70-80 flipped needles untangled in
      // one region with 100-200 Newton iterations instead of failing after 1700, distortion
      // the same to 3 digits.
      const double sigma = std::max(1 - after / before, kSigmaFloor);
      const double mu = (1 - sigma) * chi(worst, eps).value;
      eps = worst < mu ? 2 * std::sqrt(mu * (mu - worst)) : 1e-10;
    }
    int bad_before = 0, bad_after = 0;
    bool new_bad = false;
    for (std::size_t i = 0; i < faces.size(); ++i) {
      if (!refs[i].valid) continue;
      const bool was_bad = !(det_of(jacobian(x_start, i)) > options.min_det);
      const bool is_bad = !(det_of(jacobian(x, i)) > options.min_det);
      bad_before += was_bad;
      bad_after += is_bad;
      new_bad = new_bad || (is_bad && !was_bad);
    }
    // The positions as written must agree: no face of the cluster newly flipped in the layout's
    // own arithmetic either.
    std::vector<std::pair<int, Eigen::RowVector2d>> saved;
    for (int i = 0; i < n; ++i) {
      for (int c : copies[variables[i]]) saved.emplace_back(c, out.row(c));
    }
    std::vector<char> flipped_before(faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i) flipped_before[i] = is_flipped(faces[i]);
    for (int i = 0; i < n; ++i) {
      for (int c : copies[variables[i]]) {
        const Complex z = motion[c](Complex(x[2 * i], x[2 * i + 1]));
        out(c, 0) = z.real(), out(c, 1) = z.imag();
      }
    }
    int fixed_faces = 0;
    for (std::size_t i = 0; i < faces.size(); ++i) {
      const bool now = is_flipped(faces[i]);
      new_bad = new_bad || (now && !flipped_before[i]);
      fixed_faces += flipped_before[i] && !now;
    }
    // Every face positive does not make a map: a vertex's faces can wrap around it twice, or a
    // cone's once less. Each interior vertex of the cluster's faces whose faces are all positive
    // must have its angle (a cone its own).
    bool wrapped = false;
    for (int f : faces) {
      for (int k = 0; k < 3 && !wrapped; ++k) {
        const int v = mesh.triangles(f, k);
        const double expected = expected_angle[v];
        if (!std::isfinite(expected)) continue;
        double sum = 0;
        bool positive = true;
        for (int s2 = face_offset[v]; s2 < face_offset[v + 1] && positive; ++s2) {
          const int g = vertex_faces[s2];
          positive = !is_flipped(g);
          const int j = corner_of(g, v);
          const Eigen::Vector2d a = out.row(uv_triangles(g, j)).transpose();
          const Eigen::Vector2d b = out.row(uv_triangles(g, (j + 1) % 3)).transpose() - a;
          const Eigen::Vector2d c = out.row(uv_triangles(g, (j + 2) % 3)).transpose() - a;
          sum += std::atan2(b.x() * c.y() - b.y() * c.x(), b.dot(c));
        }
        wrapped = positive && std::abs(sum - expected) > kAngleTolerance;
      }
    }
    const bool keep = !new_bad && !wrapped && bad_after < bad_before && fixed_faces > 0;
    if (!keep) {
      for (const auto& [c, p] : saved) out.row(c) = p;
    } else {
      result.region_faces += static_cast<int>(faces.size());
    }
    for (int v : variables) variable[v] = -1;
    return keep;
  };

  std::vector<int> depth(nv, -1), parent(nv);
  for (int rings = std::max(options.rings, 1); rings <= options.max_rings && work < budget;
       rings *= 2) {
    std::vector<int> seeds;
    for (int f = 0; f < nf; ++f) {
      if (is_flipped(f) && !stuck[f]) seeds.push_back(f);
    }
    if (seeds.empty()) break;
    ++result.rounds;
    // The region: vertices within `rings` of the flipped faces; the movable ones are variables,
    // in clusters joined by the faces between them.
    std::fill(depth.begin(), depth.end(), -1);
    std::deque<int> queue;
    for (int f : seeds) {
      for (int k = 0; k < 3; ++k) {
        const int v = mesh.triangles(f, k);
        if (depth[v] < 0) depth[v] = 0, queue.push_back(v);
      }
    }
    std::vector<int> variables;
    while (!queue.empty()) {
      const int v = queue.front();
      queue.pop_front();
      if (movable[v]) variables.push_back(v);
      if (depth[v] == rings) continue;
      for (int s = face_offset[v]; s < face_offset[v + 1]; ++s) {
        const int f = vertex_faces[s];
        for (int k = 0; k < 3; ++k) {
          const int w = mesh.triangles(f, k);
          if (depth[w] < 0) depth[w] = depth[v] + 1, queue.push_back(w);
        }
      }
    }
    std::sort(variables.begin(), variables.end());
    for (int v : variables) parent[v] = v;
    auto find = [&](int v) {
      while (parent[v] != v) v = parent[v] = parent[parent[v]];
      return v;
    };
    for (int v : variables) variable[v] = 0;  // marks the region's variables
    for (int v : variables) {
      for (int s = face_offset[v]; s < face_offset[v + 1]; ++s) {
        const int f = vertex_faces[s];
        for (int k = 0; k < 3; ++k) {
          const int w = mesh.triangles(f, k);
          if (variable[w] < 0) continue;
          const int a = find(v), b = find(w);
          if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
      }
    }
    for (int v : variables) variable[v] = -1;
    std::vector<std::vector<int>> clusters;
    std::vector<int> cluster_of(nv, -1);
    for (int v : variables) {
      int& c = cluster_of[find(v)];
      if (c < 0) c = static_cast<int>(clusters.size()), clusters.emplace_back();
      clusters[c].push_back(v);
    }
    for (const std::vector<int>& cluster : clusters) solve_cluster(cluster);
  }
  result.flipped_after = 0;
  for (int f = 0; f < nf; ++f) {
    result.flipped_after += is_flipped(f);
    result.stuck_faces += is_flipped(f) && stuck[f];
  }
  for (int v = 0; v < nv; ++v) {
    bool moved = false;
    for (int c : copies[v]) moved = moved || out(c, 0) != uv(c, 0) || out(c, 1) != uv(c, 1);
    result.moved_vertices += moved;
  }
  return finish();
}

}  // namespace ricci
