#include "ricci/param/layout/untangle.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <deque>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

#include "param/layout/detail/untangle_energy.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/numerics/disjoint_sets.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;
using Uv = Eigen::Matrix<double, Eigen::Dynamic, 2>;
using untangle_energy::chi;
using untangle_energy::face_energy;
using untangle_energy::Mat4;
using untangle_energy::Vec4;

[[noreturn]] void invalid_untangle_input(const std::string& what) {
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

/// A face's reference: the 3D triangle in a frame of its plane, scaled to the layout's local
/// scale; J = sum_k u_k g_k^T with g the gradients of the barycentric coordinates.
struct Reference {
  Eigen::Vector2d g[3];
  bool valid = false;
};

double signed_area(const Uv& uv, const Triangles& t, int f) {
  const Eigen::Vector2d a = uv.row(t(f, 0)).transpose();
  const Eigen::Vector2d b = uv.row(t(f, 1)).transpose() - a;
  const Eigen::Vector2d c = uv.row(t(f, 2)).transpose() - a;
  return b.x() * c.y() - b.y() * c.x();
}

void check_untangle_inputs(const Mesh& mesh, const Triangles& uv_triangles, const Uv& uv,
                           const UntangleOptions& options) {
  const int nf = mesh.num_faces(), nv = mesh.num_vertices();
  const int nuv = static_cast<int>(uv.rows());
  if (uv_triangles.rows() != nf) {
    invalid_untangle_input("uv_triangles has " + std::to_string(uv_triangles.rows()) +
                           " rows but the mesh has " + std::to_string(nf) + " faces");
  }
  if (!options.angles.empty() && static_cast<int>(options.angles.size()) != nv) {
    invalid_untangle_input("angles has " + std::to_string(options.angles.size()) + " entries for " +
                           std::to_string(nv) + " vertices");
  }
  if (!options.fixed.empty() && static_cast<int>(options.fixed.size()) != nv) {
    invalid_untangle_input("fixed has " + std::to_string(options.fixed.size()) + " entries for " +
                           std::to_string(nv) + " vertices");
  }
  if (options.rings < 0 || options.max_rings < options.rings || options.newton_iterations < 1 ||
      options.max_stages < 1 || options.stall_stages < 1 || options.max_face_iterations < 0 ||
      !(options.area_weight >= 0 && options.area_weight < 1) || !(options.min_det > 0)) {
    invalid_untangle_input("an option is out of range");
  }
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      if (uv_triangles(f, k) < 0 || uv_triangles(f, k) >= nuv) {
        invalid_untangle_input("face " + std::to_string(f) + " has uv index " +
                               std::to_string(uv_triangles(f, k)) + " out of range");
      }
    }
  }
}

/// The 3D area of each face: 0 where it is zero or not finite (such a face has no shape to
/// untangle towards, and is not counted as flipped).
std::vector<double> face_areas(const Mesh& mesh) {
  const int nf = mesh.num_faces();
  std::vector<double> area3(nf, 0);
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d p0 = mesh.positions.row(mesh.triangles(f, 0)).transpose();
    const Eigen::Vector3d e1 = mesh.positions.row(mesh.triangles(f, 1)).transpose() - p0;
    const Eigen::Vector3d e2 = mesh.positions.row(mesh.triangles(f, 2)).transpose() - p0;
    const double a = 0.5 * e1.cross(e2).norm();
    area3[f] = std::isfinite(a) ? a : 0;
  }
  return area3;
}

/// The faces around each mesh vertex, in compressed rows: those of v are
/// faces[offset[v]] .. faces[offset[v + 1] - 1], in increasing order.
struct Stars {
  std::vector<int> offset, faces;
};

Stars vertex_stars(const Triangles& triangles, int nv) {
  const int nf = static_cast<int>(triangles.rows());
  Stars stars{std::vector<int>(nv + 1, 0), std::vector<int>(3 * static_cast<std::size_t>(nf))};
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) ++stars.offset[triangles(f, k) + 1];
  }
  for (int v = 0; v < nv; ++v) stars.offset[v + 1] += stars.offset[v];
  std::vector<int> next(stars.offset.begin(), stars.offset.end() - 1);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) stars.faces[next[triangles(f, k)]++] = f;
  }
  return stars;
}

/// The corner of face f at vertex v (-1 when v is not on f).
int corner_of(const Triangles& triangles, int f, int v) {
  for (int k = 0; k < 3; ++k) {
    if (triangles(f, k) == v) return k;
  }
  return -1;
}

/// Each layout vertex as the image of its mesh vertex's reference copy (the copy of the vertex
/// in its first face) under a rigid motion, found across the seams through the vertex; the
/// vertices whose copies are not so related (or that the options hold) may not move.
struct SeamMotions {
  std::vector<int> reference;  ///< per mesh vertex: its reference copy (-1: on no face)
  std::vector<Motion> motion;  ///< per layout vertex: from its reference copy to it
  std::vector<char> known;     ///< per layout vertex: motion found
  std::vector<char> movable;   ///< per mesh vertex
};

/// A seam edge's motion from one side's copy of an end to the other side's.
struct Link {
  int vertex, from, to;
  Motion m;
};

/// The links of the seam edges whose copies differ, each way, for each end; the ends of a seam
/// whose two sides are not congruent stay (a free-boundary chart's seams bend).
std::vector<Link> seam_links(const Mesh& mesh, const Topology& topology,
                             const Triangles& uv_triangles, const Uv& out,
                             std::vector<char>& movable) {
  std::vector<Link> links;
  for (int e = 0; e < topology.num_edges; ++e) {
    const int h0 = topology.edge_halfedges(e, 0), h1 = topology.edge_halfedges(e, 1);
    if (h0 < 0 || h1 < 0) continue;
    const int f0 = Topology::face_of(h0), f1 = Topology::face_of(h1);
    const int a = topology.tail(h0), b = topology.head(h0);
    const int a0 = uv_triangles(f0, corner_of(mesh.triangles, f0, a));
    const int b0 = uv_triangles(f0, corner_of(mesh.triangles, f0, b));
    const int a1 = uv_triangles(f1, corner_of(mesh.triangles, f1, a));
    const int b1 = uv_triangles(f1, corner_of(mesh.triangles, f1, b));
    if (a0 == a1 && b0 == b1) continue;
    const Complex pa0(out(a0, 0), out(a0, 1)), pb0(out(b0, 0), out(b0, 1));
    const Complex pa1(out(a1, 0), out(a1, 1)), pb1(out(b1, 0), out(b1, 1));
    const double l0 = std::abs(pb0 - pa0), l1 = std::abs(pb1 - pa1);
    if (a0 == a1 || b0 == b1 || !(l0 > 0) ||
        !(std::abs(l0 - l1) <= kRigidLength * std::max(l0, l1))) {
      movable[a] = movable[b] = 0;  // not a rigid seam: its ends stay
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
  return links;
}

SeamMotions seam_motions(const Mesh& mesh, const Topology& topology, const Stars& stars,
                         const Triangles& uv_triangles, const Uv& out,
                         const UntangleOptions& options) {
  const int nf = mesh.num_faces(), nv = mesh.num_vertices();
  const int nuv = static_cast<int>(out.rows());
  SeamMotions s{std::vector<int>(nv, -1), std::vector<Motion>(nuv), std::vector<char>(nuv, 0),
                std::vector<char>(nv, 1)};
  for (int v = 0; v < nv; ++v) {
    if (stars.offset[v] == stars.offset[v + 1]) {
      s.movable[v] = 0;
      continue;
    }
    const int first = stars.faces[stars.offset[v]];
    s.reference[v] = uv_triangles(first, corner_of(mesh.triangles, first, v));
    s.known[s.reference[v]] = 1;
    if (!options.fixed.empty() && options.fixed[v]) s.movable[v] = 0;
    if (!options.move_boundary && topology.is_boundary_vertex[v]) s.movable[v] = 0;
  }
  // Propagated until nothing changes (a vertex has few copies).
  const std::vector<Link> links = seam_links(mesh, topology, uv_triangles, out, s.movable);
  for (bool changed = true; changed;) {
    changed = false;
    for (const Link& l : links) {
      if (!s.known[l.from]) continue;
      const Motion m = compose(l.m, s.motion[l.from]);
      if (!s.known[l.to]) {
        s.motion[l.to] = m;
        s.known[l.to] = 1;
        changed = true;
        continue;
      }
      const double scale = std::abs(Complex(out(l.to, 0), out(l.to, 1))) + 1;
      if (std::abs(m.rotation - s.motion[l.to].rotation) > kConsistentMotion ||
          std::abs(m.translation - s.motion[l.to].translation) > kConsistentMotion * scale) {
        s.movable[l.vertex] = 0;  // the copies come back moved: a cone (or an inconsistent seam)
      }
    }
  }
  // Every copy must have been reached from the reference, and must sit where its motion says.
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k), c = uv_triangles(f, k);
      if (!s.movable[v]) continue;
      const Complex p(out(c, 0), out(c, 1));
      const int r = s.reference[v];
      const Complex image = s.motion[c](Complex(out(r, 0), out(r, 1)));
      if (!s.known[c] || std::abs(image - p) > kConsistentMotion * (std::abs(p) + 1)) {
        s.movable[v] = 0;
      }
    }
  }
  return s;
}

/// The layout vertices of each mesh vertex, in the order of their first corners.
std::vector<std::vector<int>> vertex_copies(const Mesh& mesh, const Triangles& uv_triangles) {
  std::vector<std::vector<int>> copies(mesh.num_vertices());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      std::vector<int>& list = copies[mesh.triangles(f, k)];
      if (std::find(list.begin(), list.end(), uv_triangles(f, k)) == list.end()) {
        list.push_back(uv_triangles(f, k));
      }
    }
  }
  return copies;
}

/// The angle each interior vertex must have in the result: the options', else 2 pi where it
/// may move (a vertex that stays keeps whatever angle the layout gives it: NaN, unchecked).
std::vector<double> expected_angles(const Topology& topology, const std::vector<char>& movable,
                                    const UntangleOptions& options) {
  const int nv = static_cast<int>(movable.size());
  std::vector<double> expected_angle(nv, std::numeric_limits<double>::quiet_NaN());
  for (int v = 0; v < nv; ++v) {
    if (topology.is_boundary_vertex[v]) continue;
    if (!options.angles.empty()) {
      expected_angle[v] = options.angles[v];
    } else if (movable[v]) {
      expected_angle[v] = 2 * std::numbers::pi;
    }
  }
  return expected_angle;
}

/// What every cluster reads, and the state the clusters share (the layout, the work done).
struct Untangler {
  const Mesh& mesh;
  const Triangles& uv_triangles;
  const UntangleOptions& options;
  UntangleResult& result;
  Uv& out;  ///< result.uv
  std::vector<double> area3;
  Stars stars{};
  SeamMotions seams{};
  std::vector<std::vector<int>> copies{};
  std::vector<double> expected_angle{};
  long long budget = 0, work = 0;
  /// Per mesh vertex: its index among the current cluster's variables, else -1.
  std::vector<int> variable{};

  bool is_flipped(int f) const { return area3[f] > 0 && !(signed_area(out, uv_triangles, f) > 0); }
};

/// Newton's shift of the Hessian's diagonal, relative to its largest entry: it keeps the system
/// definite where a variable's faces are all conformal (their projected Hessians may be
/// singular in a direction).
constexpr double kDiagonalShift = 1e-9;
/// Backtracking: the Armijo constant, and the smallest step tried.
constexpr double kArmijo = 1e-4;
constexpr double kSmallestUntangleStep = 1e-12;
/// A Newton step that lowers the energy by less than this fraction ends the stage: converged.
constexpr double kStageConverged = 1e-9;
/// The first eps: sqrt(kEpsFloor^2 + (kEpsScale * min(det, 0))^2) (the paper's choice), and
/// the eps once the smallest det exceeds the target mu.
constexpr double kEpsFloorSquared = 1e-12;
constexpr double kEpsScaleSquared = 0.04;
constexpr double kFinalEps = 1e-10;
/// Once every face is positive, stages stop when one lowers the energy by less than this
/// fraction.
constexpr double kEnergySettled = 1e-3;
/// A stage makes progress when it raises the smallest det by this fraction of its distance to
/// min_det.
constexpr double kStallProgress = 0.1;

/// One cluster's problem: its variables (mesh vertices, each moving all its copies), the faces
/// around them, and each face's reference.
struct Cluster {
  const Untangler& u;
  std::vector<int> variables, faces;
  std::vector<Reference> refs;

  int size() const { return static_cast<int>(variables.size()); }
  /// Corner k of face f at the variables' positions `at` (their reference copies).
  Eigen::Vector2d position(const Eigen::VectorXd& at, int f, int k) const {
    const int v = u.mesh.triangles(f, k), c = u.uv_triangles(f, k);
    const int i = u.variable[v];
    if (i < 0) return Eigen::Vector2d(u.out(c, 0), u.out(c, 1));
    const Complex z = u.seams.motion[c](Complex(at[2 * i], at[2 * i + 1]));
    return Eigen::Vector2d(z.real(), z.imag());
  }
  Vec4 jacobian(const Eigen::VectorXd& at, std::size_t i) const {
    const int f = faces[i];
    Eigen::Matrix2d j = Eigen::Matrix2d::Zero();
    for (int k = 0; k < 3; ++k) j += position(at, f, k) * refs[i].g[k].transpose();
    return Vec4(j(0, 0), j(0, 1), j(1, 0), j(1, 1));
  }
  static double det_of(const Vec4& j) { return j[0] * j[3] - j[1] * j[2]; }
  double min_det(const Eigen::VectorXd& at) const {
    double m = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < faces.size(); ++i) {
      if (refs[i].valid) m = std::min(m, det_of(jacobian(at, i)));
    }
    return m;
  }
  double total(const Eigen::VectorXd& at, double eps) const {
    double e = 0;
    for (std::size_t i = 0; i < faces.size(); ++i) {
      if (refs[i].valid) {
        e += face_energy(jacobian(at, i), eps, u.options.area_weight, nullptr, nullptr);
      }
    }
    return e;
  }
};

/// Numbers the variables (u.variable) and returns the faces around them, sorted.
std::vector<int> number_variables(Untangler& u, const std::vector<int>& variables,
                                  std::vector<char>& face_mark) {
  for (std::size_t i = 0; i < variables.size(); ++i) u.variable[variables[i]] = static_cast<int>(i);
  std::vector<int> faces;
  for (int v : variables) {
    for (int s = u.stars.offset[v]; s < u.stars.offset[v + 1]; ++s) {
      const int f = u.stars.faces[s];
      if (!face_mark[f]) face_mark[f] = 1, faces.push_back(f);
    }
  }
  for (int f : faces) face_mark[f] = 0;
  std::sort(faces.begin(), faces.end());
  return faces;
}

/// A cluster whose every vertex may move (a whole small component) could shrink to a point,
/// where the energy is least for large eps: its largest positive face stays as an anchor (its
/// vertices leave the variables, which are numbered again). False when there is no positive
/// face, or no variable is left.
bool anchor(Untangler& u, const std::vector<int>& faces, std::vector<int>& variables) {
  bool anchored = false;
  for (int f : faces) {
    for (int k = 0; k < 3; ++k) anchored = anchored || u.variable[u.mesh.triangles(f, k)] < 0;
  }
  if (anchored) return true;
  int anchor = -1;
  for (int f : faces) {
    if (u.area3[f] > 0 && (anchor < 0 || signed_area(u.out, u.uv_triangles, f) >
                                             signed_area(u.out, u.uv_triangles, anchor))) {
      anchor = f;
    }
  }
  if (anchor < 0 || !(signed_area(u.out, u.uv_triangles, anchor) > 0)) {
    for (int v : variables) u.variable[v] = -1;
    return false;
  }
  for (int k = 0; k < 3; ++k) u.variable[u.mesh.triangles(anchor, k)] = -1;
  std::vector<int> kept;
  for (int v : variables) {
    if (u.variable[v] >= 0) kept.push_back(v);
  }
  variables = std::move(kept);
  for (std::size_t i = 0; i < variables.size(); ++i) {
    u.variable[variables[i]] = static_cast<int>(i);
  }
  return !variables.empty();
}

/// The layout's local scale at v: its positive faces' layout area over their 3D area (0 when it
/// has none).
double vertex_scale(const Untangler& u, int v) {
  double a2 = 0, a3 = 0;
  for (int s = u.stars.offset[v]; s < u.stars.offset[v + 1]; ++s) {
    const int f = u.stars.faces[s];
    const double a = 0.5 * signed_area(u.out, u.uv_triangles, f);
    if (a > 0 && u.area3[f] > 0) a2 += a, a3 += u.area3[f];
  }
  return a3 > 0 ? a2 / a3 : 0.0;
}

/// References at the local scale: a face's scale is the mean of its vertices' (those with
/// positive faces); faces with none take the cluster's mean.
std::vector<Reference> face_references(const Untangler& u, const std::vector<int>& faces) {
  std::vector<std::array<double, 3>> corner_scale(faces.size());
  double cluster_scale = 0;
  int counted = 0;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      corner_scale[i][k] = vertex_scale(u, u.mesh.triangles(faces[i], k));
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
    const Eigen::Vector3d p0 = u.mesh.positions.row(u.mesh.triangles(f, 0)).transpose();
    const Eigen::Vector3d e1 = u.mesh.positions.row(u.mesh.triangles(f, 1)).transpose() - p0;
    const Eigen::Vector3d e2 = u.mesh.positions.row(u.mesh.triangles(f, 2)).transpose() - p0;
    const double l1 = e1.norm();
    if (!(u.area3[f] > 0) || !(l1 > 0) || !(s > 0) || !std::isfinite(s)) continue;
    const double x1 = s * l1, x2 = s * e1.dot(e2) / l1, y2 = s * 2 * u.area3[f] / l1;
    Reference& r = refs[i];
    r.g[1] = Eigen::Vector2d(1 / x1, -x2 / (x1 * y2));
    r.g[2] = Eigen::Vector2d(0, 1 / y2);
    r.g[0] = -(r.g[1] + r.g[2]);
    r.valid = true;
  }
  return refs;
}

/// The Newton system's storage, kept over a cluster's stages (one symbolic analysis).
struct NewtonSystem {
  std::vector<Eigen::Triplet<double>> triplets;
  SparseCholesky solver;
  bool analysed = false;
};

/// The energy at x with its gradient g and the projected Hessian's triplets (a zero diagonal
/// first, so that every variable has its entry).
double assemble(const Cluster& c, const Eigen::VectorXd& x, double eps, Eigen::VectorXd& g,
                std::vector<Eigen::Triplet<double>>& triplets) {
  const Untangler& u = c.u;
  const int n = c.size();
  g = Eigen::VectorXd::Zero(2 * n);
  triplets.clear();
  double e = 0;
  for (int i = 0; i < 2 * n; ++i) triplets.emplace_back(i, i, 0.0);
  for (std::size_t i = 0; i < c.faces.size(); ++i) {
    if (!c.refs[i].valid) continue;
    const int f = c.faces[i];
    Vec4 gj;
    Mat4 hj;
    e += face_energy(c.jacobian(x, i), eps, u.options.area_weight, &gj, &hj);
    // d vec(J) / d w for each corner whose vertex is a variable: B_k R (R: the copy's
    // rotation), B_k = [[g0 g1 0 0], [0 0 g0 g1]]^T per corner.
    Eigen::Matrix<double, 4, 6> b = Eigen::Matrix<double, 4, 6>::Zero();
    int slot[3];
    for (int k = 0; k < 3; ++k) {
      slot[k] = u.variable[u.mesh.triangles(f, k)];
      if (slot[k] < 0) continue;
      const Complex r = u.seams.motion[u.uv_triangles(f, k)].rotation;
      Eigen::Matrix<double, 4, 2> bk = Eigen::Matrix<double, 4, 2>::Zero();
      bk(0, 0) = c.refs[i].g[k].x(), bk(1, 0) = c.refs[i].g[k].y();
      bk(2, 1) = c.refs[i].g[k].x(), bk(3, 1) = c.refs[i].g[k].y();
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
          for (int d = 0; d < 2; ++d) {
            triplets.emplace_back(2 * slot[k] + a, 2 * slot[l] + d, hf(2 * k + a, 2 * l + d));
          }
        }
      }
    }
  }
  return e;
}

/// One eps stage: Newton with projected face Hessians, backtracking on the energy.
void minimise_stage(Untangler& u, const Cluster& c, double eps, NewtonSystem& system,
                    Eigen::VectorXd& x) {
  const int n = c.size();
  for (int it = 0; it < u.options.newton_iterations && u.work < u.budget; ++it) {
    ++u.result.newton_iterations;
    u.work += static_cast<long long>(c.faces.size());
    Eigen::VectorXd g;
    const double e = assemble(c, x, eps, g, system.triplets);
    Eigen::SparseMatrix<double> h(2 * n, 2 * n);
    h.setFromTriplets(system.triplets.begin(), system.triplets.end());
    double diagonal = 0;
    for (int i = 0; i < 2 * n; ++i) diagonal = std::max(diagonal, h.coeff(i, i));
    if (!(diagonal > 0) || !std::isfinite(diagonal) || !g.allFinite()) return;
    for (int i = 0; i < 2 * n; ++i) h.coeffRef(i, i) += kDiagonalShift * diagonal;
    Eigen::VectorXd d;
    try {
      // One pattern per cluster.
      if (!system.analysed) system.solver.analyze(h), system.analysed = true;
      system.solver.factorize(h);
      d = -system.solver.solve(g);
    } catch (const SolverError&) {
      d = -g / diagonal;
    }
    const double slope = g.dot(d);
    if (!(slope < 0) || !d.allFinite()) return;
    bool accepted = false;
    for (double t = 1; t > kSmallestUntangleStep; t *= 0.5) {
      const Eigen::VectorXd trial = x + t * d;
      const double et = c.total(trial, eps);
      if (et <= e + kArmijo * t * slope) {
        x = trial;
        accepted = true;
        if (e - et < kStageConverged * e) return;  // this stage has converged
        break;
      }
    }
    if (!accepted) return;
  }
}

/// The eps stages: until the faces are positive and, after that, until the energy settles (a
/// face just past det = 0 is a sliver: the barrier, eps -> 0, pulls it back into shape).
void run_stages(Untangler& u, const Cluster& c, Eigen::VectorXd& x) {
  const UntangleOptions& options = u.options;
  NewtonSystem system;
  double worst = c.min_det(x);
  double eps =
      std::sqrt(kEpsFloorSquared + kEpsScaleSquared * std::min(worst, 0.0) * std::min(worst, 0.0));
  double stalled_at = worst;
  int stalled = 0;
  for (int stage = 0; stage < options.max_stages && u.work < u.budget; ++stage) {
    const double before = c.total(x, eps);
    minimise_stage(u, c, eps, system, x);
    const double after = c.total(x, eps);
    if (worst > options.min_det && !(before - after > kEnergySettled * after)) break;
    worst = c.min_det(x);
    // No progress towards positive faces for a while: a face no move of these vertices can
    // open (a cone whose angle its faces cannot hold), or one that needs a larger region.
    if (worst > stalled_at + kStallProgress * (options.min_det - stalled_at)) {
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
    eps = worst < mu ? 2 * std::sqrt(mu * (mu - worst)) : kFinalEps;
  }
}

/// Every face positive does not make a map: a vertex's faces can wrap around it twice, or a
/// cone's once less. True when an interior vertex of `faces` whose faces are all positive has
/// an angle other than its expected one (a cone its own).
bool wraps_a_vertex(const Untangler& u, const std::vector<int>& faces) {
  bool wrapped = false;
  for (int f : faces) {
    for (int k = 0; k < 3 && !wrapped; ++k) {
      const int v = u.mesh.triangles(f, k);
      const double expected = u.expected_angle[v];
      if (!std::isfinite(expected)) continue;
      double sum = 0;
      bool positive = true;
      for (int s2 = u.stars.offset[v]; s2 < u.stars.offset[v + 1] && positive; ++s2) {
        const int g = u.stars.faces[s2];
        positive = !u.is_flipped(g);
        const int j = corner_of(u.mesh.triangles, g, v);
        const Eigen::Vector2d a = u.out.row(u.uv_triangles(g, j)).transpose();
        const Eigen::Vector2d b = u.out.row(u.uv_triangles(g, (j + 1) % 3)).transpose() - a;
        const Eigen::Vector2d c = u.out.row(u.uv_triangles(g, (j + 2) % 3)).transpose() - a;
        sum += std::atan2(b.x() * c.y() - b.y() * c.x(), b.dot(c));
      }
      wrapped = positive && std::abs(sum - expected) > kAngleTolerance;
    }
  }
  return wrapped;
}

/// Writes the cluster's positions x into the layout and keeps them only when they leave none of
/// its faces flipped or degenerate that was not so before (in J and in the layout's own
/// arithmetic), wrap no vertex, and untangle at least one face; else the layout is restored.
bool keep_if_better(Untangler& u, const Cluster& c, const Eigen::VectorXd& x_start,
                    const Eigen::VectorXd& x) {
  const double min_det = u.options.min_det;
  int bad_before = 0, bad_after = 0;
  bool new_bad = false;
  for (std::size_t i = 0; i < c.faces.size(); ++i) {
    if (!c.refs[i].valid) continue;
    const bool was_bad = !(Cluster::det_of(c.jacobian(x_start, i)) > min_det);
    const bool is_bad = !(Cluster::det_of(c.jacobian(x, i)) > min_det);
    bad_before += was_bad;
    bad_after += is_bad;
    new_bad = new_bad || (is_bad && !was_bad);
  }
  // The positions as written must agree: no face of the cluster newly flipped in the layout's
  // own arithmetic either.
  std::vector<std::pair<int, Eigen::RowVector2d>> saved;
  for (int i = 0; i < c.size(); ++i) {
    for (int copy : u.copies[c.variables[i]]) saved.emplace_back(copy, u.out.row(copy));
  }
  std::vector<char> flipped_before(c.faces.size());
  for (std::size_t i = 0; i < c.faces.size(); ++i) flipped_before[i] = u.is_flipped(c.faces[i]);
  for (int i = 0; i < c.size(); ++i) {
    for (int copy : u.copies[c.variables[i]]) {
      const Complex z = u.seams.motion[copy](Complex(x[2 * i], x[2 * i + 1]));
      u.out(copy, 0) = z.real(), u.out(copy, 1) = z.imag();
    }
  }
  int fixed_faces = 0;
  for (std::size_t i = 0; i < c.faces.size(); ++i) {
    const bool now = u.is_flipped(c.faces[i]);
    new_bad = new_bad || (now && !flipped_before[i]);
    fixed_faces += flipped_before[i] && !now;
  }
  const bool keep =
      !new_bad && !wraps_a_vertex(u, c.faces) && bad_after < bad_before && fixed_faces > 0;
  if (!keep) {
    for (const auto& [copy, p] : saved) u.out.row(copy) = p;
  }
  return keep;
}

/// One cluster of variables with the faces around them, untangled together (see
/// keep_if_better for when its moves are kept). Returns whether kept.
bool solve_cluster(Untangler& u, std::vector<int> variables, std::vector<char>& face_mark) {
  Cluster c{u, {}, {}, {}};
  c.faces = number_variables(u, variables, face_mark);
  if (!anchor(u, c.faces, variables)) return false;
  c.variables = std::move(variables);
  c.refs = face_references(u, c.faces);
  // The variables' positions (their reference copies).
  const int n = c.size();
  Eigen::VectorXd x(2 * n);
  for (int i = 0; i < n; ++i) {
    const int r = u.seams.reference[c.variables[i]];
    x[2 * i] = u.out(r, 0), x[2 * i + 1] = u.out(r, 1);
  }
  const Eigen::VectorXd x_start = x;
  run_stages(u, c, x);
  const bool keep = keep_if_better(u, c, x_start, x);
  if (keep) u.result.region_faces += static_cast<int>(c.faces.size());
  for (int v : c.variables) u.variable[v] = -1;
  return keep;
}

/// The region of a round: the movable vertices within `rings` of the seed faces' vertices,
/// sorted.
std::vector<int> region_variables(const Untangler& u, const std::vector<int>& seeds, int rings,
                                  std::vector<int>& depth) {
  std::fill(depth.begin(), depth.end(), -1);
  std::deque<int> queue;
  for (int f : seeds) {
    for (int k = 0; k < 3; ++k) {
      const int v = u.mesh.triangles(f, k);
      if (depth[v] < 0) depth[v] = 0, queue.push_back(v);
    }
  }
  std::vector<int> variables;
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop_front();
    if (u.seams.movable[v]) variables.push_back(v);
    if (depth[v] == rings) continue;
    for (int s = u.stars.offset[v]; s < u.stars.offset[v + 1]; ++s) {
      const int f = u.stars.faces[s];
      for (int k = 0; k < 3; ++k) {
        const int w = u.mesh.triangles(f, k);
        if (depth[w] < 0) depth[w] = depth[v] + 1, queue.push_back(w);
      }
    }
  }
  std::sort(variables.begin(), variables.end());
  return variables;
}

/// The sorted variables in clusters joined by the faces between them, each cluster sorted, the
/// clusters in the order of their smallest vertices.
std::vector<std::vector<int>> clusters_of(Untangler& u, const std::vector<int>& variables) {
  const int nv = u.mesh.num_vertices();
  DisjointSets sets(nv);
  for (int v : variables) u.variable[v] = 0;  // marks the region's variables
  for (int v : variables) {
    for (int s = u.stars.offset[v]; s < u.stars.offset[v + 1]; ++s) {
      const int f = u.stars.faces[s];
      for (int k = 0; k < 3; ++k) {
        const int w = u.mesh.triangles(f, k);
        if (u.variable[w] >= 0) sets.unite(v, w);
      }
    }
  }
  for (int v : variables) u.variable[v] = -1;
  std::vector<std::vector<int>> clusters;
  std::vector<int> cluster_of(nv, -1);
  for (int v : variables) {
    int& c = cluster_of[sets.find(v)];
    if (c < 0) c = static_cast<int>(clusters.size()), clusters.emplace_back();
    clusters[c].push_back(v);
  }
  return clusters;
}

}  // namespace

UntangleResult untangle_layout(const Mesh& mesh, const Triangles& uv_triangles, const Uv& uv,
                               const UntangleOptions& options) {
  const auto start = Clock::now();
  check_untangle_inputs(mesh, uv_triangles, uv, options);
  const int nf = mesh.num_faces(), nv = mesh.num_vertices();
  UntangleResult result;
  result.uv = uv;
  Untangler u{mesh, uv_triangles, options, result, result.uv, face_areas(mesh)};
  std::vector<int> flipped;
  for (int f = 0; f < nf; ++f) {
    if (u.is_flipped(f)) flipped.push_back(f);
  }
  result.flipped_before = static_cast<int>(flipped.size());
  result.flipped_after = result.flipped_before;
  if (flipped.empty()) {
    result.seconds = seconds_since(start);
    return result;
  }
  const Topology topology = build_topology(mesh.triangles, nv);
  u.stars = vertex_stars(mesh.triangles, nv);
  u.seams = seam_motions(mesh, topology, u.stars, uv_triangles, u.out, options);
  u.copies = vertex_copies(mesh, uv_triangles);
  std::vector<char> stuck(nf, 0);
  for (int f : flipped) {
    bool any = false;
    for (int k = 0; k < 3; ++k) any = any || u.seams.movable[mesh.triangles(f, k)];
    stuck[f] = !any;
  }
  if (options.give_up_when_stuck && std::count(stuck.begin(), stuck.end(), 1) > 0) {
    result.stuck_faces = static_cast<int>(std::count(stuck.begin(), stuck.end(), 1));
    result.seconds = seconds_since(start);
    return result;
  }
  u.expected_angle = expected_angles(topology, u.seams.movable, options);
  u.budget = options.max_face_iterations > 0 ? options.max_face_iterations : 50LL * nf + 100000;
  u.variable.assign(nv, -1);
  std::vector<int> depth(nv, -1);
  std::vector<char> face_mark(nf, 0);
  // Rounds over the flipped faces that are not stuck, the region doubling its rings each time.
  for (int rings = std::max(options.rings, 1); rings <= options.max_rings && u.work < u.budget;
       rings *= 2) {
    std::vector<int> seeds;
    for (int f = 0; f < nf; ++f) {
      if (u.is_flipped(f) && !stuck[f]) seeds.push_back(f);
    }
    if (seeds.empty()) break;
    ++result.rounds;
    for (const std::vector<int>& cluster :
         clusters_of(u, region_variables(u, seeds, rings, depth))) {
      solve_cluster(u, cluster, face_mark);
    }
  }
  result.flipped_after = 0;
  for (int f = 0; f < nf; ++f) {
    result.flipped_after += u.is_flipped(f);
    result.stuck_faces += u.is_flipped(f) && stuck[f];
  }
  for (int v = 0; v < nv; ++v) {
    bool moved = false;
    for (int c : u.copies[v]) moved = moved || u.out(c, 0) != uv(c, 0) || u.out(c, 1) != uv(c, 1);
    result.moved_vertices += moved;
  }
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace ricci
