#include "ricci/param/cones/cones.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <numbers>

#include "ricci/errors.hpp"
#include "ricci/mesh/build_counts.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace ricci {
namespace {

/// Whether L plus a large penalty on vertex 0 (the gauge) factorises: a connected component's
/// Laplacian with non-negative enough weights does.
bool positive_definite_with_one_pin(const Eigen::SparseMatrix<double>& L) {
  Eigen::SparseMatrix<double> A = L;
  A.coeffRef(0, 0) += 1e10 * std::max(1.0, L.diagonal().cwiseAbs().maxCoeff());
  SparseCholesky cholesky;
  try {
    cholesky.factorize(A);
  } catch (const SolverError&) {
    return false;
  }
  return true;
}

/// The cotangent Laplacian of the input metric's intrinsic Delaunay triangulation (#V by #V).
/// \param s the input lengths' vertex-scaling structure
Eigen::SparseMatrix<double> intrinsic_delaunay_laplacian(const Topology& t,
                                                         const Eigen::VectorXd& input_lengths,
                                                         ConformalStructure s) {
  Eigen::VectorXd lengths = input_lengths;
  const Eigen::VectorXd u = s.initial_u;
  // (t is copied only when some edge is not Delaunay.)
  IntrinsicTriangulation intrinsic(t, std::move(s));
  DelaunayFlipOptions isometric;
  isometric.isometric = true;
  intrinsic.flip_to_delaunay(u, lengths, isometric);
  const Topology& flipped = intrinsic.topology();
  CornerAngles angles;
  corner_angles(flipped, lengths, angles);
  Eigen::VectorXd hw, ew;
  halfedge_weights(flipped, intrinsic.structure(), u, lengths, angles, hw);
  edge_weights(flipped, hw, ew);
  return curvature_hessian(flipped, ew);
}

/// Lowers hops[v] to the number of edges from `source` to v, for every v within max_rings edges
/// of it (breadth-first over the vertex neighbour lists).
void grow_rings(const std::vector<std::vector<int>>& neighbours, int source, int max_rings,
                std::vector<int>& hops) {
  std::vector<int> frontier = {source};
  hops[source] = 0;
  for (int r = 1; r <= max_rings && !frontier.empty(); ++r) {
    std::vector<int> next;
    for (int a : frontier) {
      for (int b : neighbours[a]) {
        if (hops[b] > r) {
          hops[b] = r;
          next.push_back(b);
        }
      }
    }
    frontier = std::move(next);
  }
}

/// grow_rings, but a ring is only taken while the area the source's rings cover (area: per
/// vertex, normalised to a total of 1) stays within max_area: on a CAD mesh one ring of a fan
/// centre covers a whole face of the part, and three rings the whole part.
void grow_rings_within(const std::vector<std::vector<int>>& neighbours, int source, int max_rings,
                       const Eigen::VectorXd& area, double max_area, std::vector<int>& hops) {
  std::vector<int> frontier = {source};
  hops[source] = 0;
  double covered = area[source];
  for (int r = 1; r <= max_rings && !frontier.empty(); ++r) {
    std::vector<int> next;
    std::vector<int> before;  // their hops before this ring, to undo it
    double added = 0;
    for (int a : frontier) {
      for (int b : neighbours[a]) {
        if (hops[b] > r) {
          before.push_back(hops[b]);
          hops[b] = r;
          next.push_back(b);
          added += area[b];
        }
      }
    }
    if (covered + added > max_area) {
      for (std::size_t i = next.size(); i-- > 0;) hops[next[i]] = before[i];
      return;
    }
    covered += added;
    frontier = std::move(next);
  }
}

/// A cone set of at most this many cones is improved by exchanges (each cone taken out and
/// the best candidate put in): two passes over the cones up to kExchangeTwice of them, one pass
/// above (an exchange costs two fits of #V x #S each; kitten with 32 cones: 6.1 s for two passes
/// against 1.4 s for the greedy alone).
constexpr int kExchangeCones = 64;
constexpr int kExchangeTwice = 8;

/// Most doubles the selection keeps as columns of A^-1 (#V per cone): 320 MB.
constexpr double kColumnValues = 4e7;

/// Rings around a cone left out of the measure and of the candidates for the next cone. (Capping
/// them by area in the selection let cones crowd on small high-genus meshes: 2 flipped faces on
/// a generated genus-20 surface of 748 faces.)
constexpr int kSeparationRings = 3;
/// log_scale_spread leaves out at most this fraction of the area around each cone: with three
/// whole rings, a CAD cylinder's fan centres hid every vertex and the spread read 0.
constexpr double kRingArea = 0.02;

/// A third of the 3D area of the faces around each vertex, normalised to a total of 1.
/// Each face's share of the 3D area (summing to 1).
Eigen::VectorXd face_areas(const Mesh& mesh, const Topology& t) {
  Eigen::VectorXd area(t.num_faces);
  for (int f = 0; f < t.num_faces; ++f) {
    const Eigen::Vector3d a = mesh.positions.row(t.triangles(f, 0));
    const Eigen::Vector3d b = mesh.positions.row(t.triangles(f, 1));
    const Eigen::Vector3d c = mesh.positions.row(t.triangles(f, 2));
    area[f] = (b - a).cross(c - a).norm();
  }
  return area / area.sum();
}

/// A third of each vertex's faces' share of the 3D area (summing to 1).
Eigen::VectorXd vertex_areas(const Topology& t, const Eigen::VectorXd& face_area) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(t.num_vertices);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) area[t.triangles(f, k)] += face_area[f] / 3;
  }
  return area;
}

std::vector<std::vector<int>> vertex_neighbours(const Topology& t) {
  std::vector<std::vector<int>> neighbours(t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    neighbours[t.edge_vertices(e, 0)].push_back(t.edge_vertices(e, 1));
    neighbours[t.edge_vertices(e, 1)].push_back(t.edge_vertices(e, 0));
  }
  return neighbours;
}

}  // namespace

namespace {

/// Quadratic programmes of more cones than this activate violated bounds in batches.
constexpr int kBatchedActiveSet = 64;

/// min 1/2 k^T M k + r^T k subject to lo <= k <= hi and, with `sum_constraint`, sum k = total:
/// a small dense quadratic programme, solved by an active-set method (the KKT system of the free
/// variables, bounds fixed one violation at a time and released when their multiplier turns).
/// Returns whether the bounds could all be met; when they cannot, the equality-constrained
/// minimiser without bounds is returned.
bool bounded_least_squares(const Eigen::MatrixXd& M, const Eigen::VectorXd& r,
                           const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                           bool sum_constraint, double total, Eigen::VectorXd& k,
                           double& multiplier) {
  const int m = static_cast<int>(r.size());
  const double ridge = 1e-12 * std::max(1e-300, M.diagonal().cwiseAbs().maxCoeff());
  // state: 0 free, -1 at lo, +1 at hi
  std::vector<int> state(m, 0);
  auto solve_free = [&](Eigen::VectorXd& x, double& lambda) -> bool {
    std::vector<int> free;
    for (int i = 0; i < m; ++i) {
      if (state[i] == 0) free.push_back(i);
    }
    x.resize(m);
    for (int i = 0; i < m; ++i) {
      if (state[i] < 0) x[i] = lo[i];
      if (state[i] > 0) x[i] = hi[i];
    }
    const int nf = static_cast<int>(free.size());
    const int rows = nf + (sum_constraint ? 1 : 0);
    lambda = 0;
    if (nf == 0)
      return !sum_constraint || std::abs(x.sum() - total) <= 1e-9 * (1 + std::abs(total));
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(rows, rows);
    Eigen::VectorXd b(rows);
    for (int a = 0; a < nf; ++a) {
      double fixed_part = 0;
      for (int j = 0; j < m; ++j) {
        if (state[j] != 0) fixed_part += M(free[a], j) * x[j];
      }
      b[a] = -r[free[a]] - fixed_part;
      for (int c = 0; c < nf; ++c) K(a, c) = M(free[a], free[c]);
      K(a, a) += ridge;
    }
    if (sum_constraint) {
      double fixed_sum = 0;
      for (int j = 0; j < m; ++j) {
        if (state[j] != 0) fixed_sum += x[j];
      }
      for (int a = 0; a < nf; ++a) K(a, nf) = K(nf, a) = 1.0;
      b[nf] = total - fixed_sum;
    }
    // M restricted to the free variables is positive definite (M is, plus the ridge): one
    // Cholesky factorisation, and the sum constraint by its Schur complement. (A full-pivoting
    // LU of the whole KKT system took 95 % of a genus-150 selection of 912 cones: 149 s.)
    const Eigen::LLT<Eigen::MatrixXd> llt(K.topLeftCorner(nf, nf));
    Eigen::VectorXd y(rows);
    if (llt.info() == Eigen::Success) {
      const Eigen::VectorXd yb = llt.solve(b.head(nf));
      if (sum_constraint) {
        const Eigen::VectorXd y1 = llt.solve(Eigen::VectorXd::Ones(nf));
        const double mu = (yb.sum() - b[nf]) / y1.sum();
        y.head(nf) = yb - mu * y1;
        y[nf] = mu;
      } else {
        y = yb;
      }
    } else {
      y = K.fullPivLu().solve(b);
    }
    for (int a = 0; a < nf; ++a) x[free[a]] = y[a];
    if (sum_constraint) lambda = y[nf];
    return y.allFinite();
  };

  if (sum_constraint && (lo.sum() > total || hi.sum() < total)) {
    std::fill(state.begin(), state.end(), 0);
    solve_free(k, multiplier);
    return false;
  }
  // The active-set iterations; `batched`: violated bounds among the free variables become
  // active all at once (one at a time, a genus-150 surface whose 900 cones sit at their lower
  // bounds took 900 factorisations per programme: 149 s for its selection). The optimum is
  // unique (M is positive definite), so the path does not change it, but a batch can leave the
  // sum constraint a single free variable it cannot meet; then the one-at-a-time path runs.
  auto run = [&](bool batched) -> bool {
    std::fill(state.begin(), state.end(), 0);
    Eigen::VectorXd x;
    double lambda = 0;
    for (int iteration = 0; iteration < 4 * m + 8; ++iteration) {
      if (!solve_free(x, lambda)) break;
      int worst = -1;
      double worst_violation = 1e-12;
      std::vector<int> violated;
      for (int i = 0; i < m; ++i) {
        if (state[i] != 0) continue;
        const double v = std::max(lo[i] - x[i], x[i] - hi[i]);
        if (v > 1e-12) violated.push_back(i);
        if (v > worst_violation) {
          worst_violation = v;
          worst = i;
        }
      }
      if (worst >= 0) {
        int free_count = 0;
        for (int st : state) free_count += st == 0;
        if (sum_constraint && free_count == 1) break;  // the sum needs one free variable
        if (!batched || (sum_constraint && static_cast<int>(violated.size()) >= free_count)) {
          violated = {worst};  // the worst violated bound becomes active
        }
        for (int i : violated) state[i] = x[i] < lo[i] ? -1 : 1;
        continue;
      }
      // Feasible: release the active bound whose multiplier has the wrong sign, if any. The
      // gradient of the Lagrangian at a bound at lo must be >= 0 (at hi <= 0).
      const Eigen::VectorXd gradient = M * x + r + Eigen::VectorXd::Constant(m, lambda);
      int release = -1;
      double most = 1e-12 * (1 + gradient.cwiseAbs().maxCoeff());
      for (int i = 0; i < m; ++i) {
        const double wrong = state[i] < 0 ? -gradient[i] : state[i] > 0 ? gradient[i] : 0.0;
        if (wrong > most) {
          most = wrong;
          release = i;
        }
      }
      if (release < 0) {
        k = x;
        multiplier = lambda;
        return true;
      }
      state[release] = 0;
    }
    return false;
  };
  if (m > kBatchedActiveSet && run(true)) return true;
  if (run(false)) return true;
  std::fill(state.begin(), state.end(), 0);
  solve_free(k, multiplier);
  return false;
}

/// The area distortion of the tutorial's eq. 9 as the linearised model sees it, in log form:
///     F(u) = log sum_f a_f e^{4 u_f} - 2 log sum_f a_f e^{2 u_f}  =  log(1 + E),
/// E = sum_f a_f (e^{2 u_f} / Z - 1)^2 with Z = sum_f a_f e^{2 u_f}, u_f the mean of u over the
/// corners of face f (its area scales by e^{2 u_f} when u is linear over it) and a_f its share
/// of the 3D area: the checker's E. Unlike the L2 norm of u it charges expansion exponentially:
/// a strong positive cone (u ~ -(k / 2 pi) log r next to it, so area grows like r^(-k / pi))
/// costs what it costs in the texture, and shrinking costs little. (Per face rather than per
/// vertex: a cone's own u counts once per vertex but touches deg faces; on spot with 4 cones
/// the per-vertex form gave the checker's E 1.01, this one 0.92.)
/// Returns F; `gradient` (optional) gets dF/du.
double area_energy(const Topology& t, const Eigen::VectorXd& face_area, const Eigen::VectorXd& u,
                   Eigen::VectorXd* gradient) {
  const int nf = t.num_faces;
  Eigen::ArrayXd uf(nf);
  for (int f = 0; f < nf; ++f) {
    uf[f] = (u[t.triangles(f, 0)] + u[t.triangles(f, 1)] + u[t.triangles(f, 2)]) / 3;
  }
  const double top = uf.maxCoeff();  // e^{4 (u - top)} cannot overflow
  const Eigen::ArrayXd scale = (2 * (uf - top)).exp();
  const Eigen::ArrayXd e2 = scale * face_area.array();
  const Eigen::ArrayXd e4 = scale * e2;
  const double s2 = e2.sum(), s4 = e4.sum();
  if (gradient) {
    const Eigen::ArrayXd per_face = (4.0 / 3) * (e4 / s4 - e2 / s2);
    *gradient = Eigen::VectorXd::Zero(u.size());
    for (int f = 0; f < nf; ++f) {
      for (int c = 0; c < 3; ++c) (*gradient)[t.triangles(f, c)] += per_face[f];
    }
  }
  return std::log(s4) - 2 * std::log(s2);
}

/// The objective the cone curvatures minimise: log(1 + E) of the linearised flat metric plus
/// `smooth` times its Dirichlet energy D = sum over edges of w_ij (u_i - u_j)^2 = u^T L u. The
/// second term stands for the angle distortion: a discrete conformal map distorts each face's
/// angles by about |grad u| h, so the mean over faces of the squared distortion is about D / #F
/// (h^2 / area is about constant on a fair mesh); it also charges each cone k^2 G_ss, the log
/// singularity its ring of faces pays. Strong cones of both signs side by side flatten the area
/// and steepen u between them: E alone chose them on spot (angle distortion 1.077 against BFF's
/// 1.058 at 32 cones, its excess far from the cones).
/// With u = A^-1 rhs, rhs = rhs0 + sum_i k_i e_{S_i}: D = u . rhs (held vertices have u = 0), so
/// dD/dk_i = 2 u_{S_i} and its Hessian is 2 A^-1 restricted to S (`green`).
struct ConeObjective {
  const SparseCholesky& cholesky;
  const Eigen::VectorXd& rhs0;
  const Eigen::VectorXd& u0;  ///< A^-1 rhs0
  const Topology& t;
  const Eigen::VectorXd& face_area;
  const std::vector<int>& S;
  /// A^-1 e_s for the cones, when kept (then u and the cones' gradient take no solve); empty
  /// when they would take too much memory.
  const std::vector<Eigen::VectorXd>& columns;
  double smooth = 0;

  bool has_columns() const { return !S.empty() && columns.size() == S.size(); }
  Eigen::VectorXd solve_u(const Eigen::VectorXd& k) const {
    if (has_columns()) {
      Eigen::VectorXd u = u0;
      for (std::size_t i = 0; i < S.size(); ++i) u += k[static_cast<int>(i)] * columns[i];
      return u;
    }
    Eigen::VectorXd rhs = rhs0;
    for (std::size_t i = 0; i < S.size(); ++i) rhs[S[i]] += k[static_cast<int>(i)];
    return cholesky.solve(rhs);
  }
  double value(const Eigen::VectorXd& u, const Eigen::VectorXd& k) const {
    double dirichlet = u.dot(rhs0);
    for (std::size_t i = 0; i < S.size(); ++i) dirichlet += u[S[i]] * k[static_cast<int>(i)];
    return area_energy(t, face_area, u, nullptr) + smooth * dirichlet;
  }
  /// d/dk_i for the cones: G_S^T dF/du + 2 smooth u_S.
  Eigen::VectorXd gradient(const Eigen::VectorXd& u) const {
    Eigen::VectorXd w;
    area_energy(t, face_area, u, &w);
    const int m = static_cast<int>(S.size());
    Eigen::VectorXd g(m);
    if (has_columns()) {
      for (int i = 0; i < m; ++i) g[i] = columns[i].dot(w) + 2 * smooth * u[S[i]];
    } else {
      const Eigen::VectorXd all = cholesky.solve(w);
      for (int i = 0; i < m; ++i) g[i] = all[S[i]] + 2 * smooth * u[S[i]];
    }
    return g;
  }
  /// d/dk at every vertex (a cone of curvature 0 there included): A^-1 dF/du + 2 smooth u.
  Eigen::VectorXd gradient_everywhere(const Eigen::VectorXd& u) const {
    Eigen::VectorXd w;
    area_energy(t, face_area, u, &w);
    return cholesky.solve(w) + 2 * smooth * u;
  }
};

/// Curvatures k of the cones S minimising the ConeObjective subject to lo <= k <= hi and, on a
/// closed surface, sum k = total: a quasi-Newton method (BFGS started from the objective's
/// Hessian at u = 0: 8 M for log(1 + E), M = G_S^T P G_S the Hessian of J, plus 2 smooth green)
/// whose steps are the bounded quadratic programmes of bounded_least_squares, with a backtracking
/// line search. With the cones' columns of A^-1 kept an iterate takes no solve (dense products
/// of #V x #S); without them two. `k` enters feasible (the J minimiser) and leaves at the
/// minimiser; returns u there, `gradient_all` (when given) gets the objective's gradient at
/// every vertex (for the next cone: the one solve of the call with columns). B: in, an estimate
/// of the Hessian for the first B.rows() cones (from an earlier call); out, the final one.
Eigen::VectorXd minimise_cone_objective(const ConeObjective& objective, const Eigen::MatrixXd& M,
                                        const Eigen::MatrixXd& green, const Eigen::VectorXd& lo,
                                        const Eigen::VectorXd& hi, bool closed, double total,
                                        Eigen::VectorXd& k, Eigen::MatrixXd& B,
                                        Eigen::VectorXd* gradient_all, double& value) {
  const int m = static_cast<int>(objective.S.size());
  Eigen::VectorXd u = objective.solve_u(k);
  value = objective.value(u, k);
  if (m == 0) {
    if (gradient_all) *gradient_all = objective.gradient_everywhere(u);
    return u;
  }
  Eigen::VectorXd g = objective.gradient(u);
  // The previous greedy step's estimate for the cones it had (B enters with those rows), the
  // model's Hessian at u = 0 for the new ones; the model's alone if that is not positive definite.
  Eigen::MatrixXd model_hessian = 8 * M + 2 * objective.smooth * green;
  model_hessian.diagonal().array() +=
      1e-9 * std::max(1e-300, model_hessian.diagonal().cwiseAbs().maxCoeff());
  Eigen::MatrixXd start = model_hessian;
  const int kept = static_cast<int>(std::min<Eigen::Index>(B.rows(), m));
  if (kept > 0 && B.cols() == B.rows()) {
    start.topLeftCorner(kept, kept) = B.topLeftCorner(kept, kept);
    if (start.llt().info() != Eigen::Success) start = model_hessian;
  }
  B = std::move(start);
  for (int iteration = 0; iteration < 60; ++iteration) {
    Eigen::VectorXd target;
    double multiplier = 0;
    const Eigen::VectorXd linear = g - B * k;
    if (!bounded_least_squares(B, linear, lo, hi, closed, total, target, multiplier)) break;
    const Eigen::VectorXd direction = target - k;
    if (direction.cwiseAbs().maxCoeff() < 1e-12) break;
    const double slope = g.dot(direction);
    if (!(slope < 0)) break;
    double step = 1;
    Eigen::VectorXd k_new, u_new;
    double value_new = INFINITY;
    for (int tries = 0; tries < 30; ++tries, step *= 0.5) {
      k_new = k + step * direction;
      u_new = objective.solve_u(k_new);
      value_new = objective.value(u_new, k_new);
      if (value_new <= value + 1e-4 * step * slope) break;
    }
    if (!(value_new < value)) break;
    const Eigen::VectorXd g_new = objective.gradient(u_new);
    const Eigen::VectorXd s = k_new - k, y = g_new - g;
    const double sy = s.dot(y);
    if (sy > 1e-12 * s.norm() * y.norm()) {
      const Eigen::VectorXd Bs = B * s;
      B += y * y.transpose() / sy - Bs * Bs.transpose() / s.dot(Bs);
    }
    const double decrease = value - value_new;
    k = k_new;
    u = u_new;
    g = g_new;
    value = value_new;
    if (decrease <= 1e-8 * (1 + std::abs(value))) break;
  }
  if (gradient_all) *gradient_all = objective.gradient_everywhere(u);
  return u;
}

/// The flow linearised at the input metric, factorised once: what the selection and the
/// refinement of cone curvatures share.
struct ConeModelData {
  const Topology* topology = nullptr;  ///< the problem's
  int nv = 0;
  bool closed = false;
  int chi = 0;
  int gauge = -1;          ///< closed surfaces: the vertex held at u = 0
  std::vector<char> held;  ///< boundary vertices and the gauge, held at u = 0
  Eigen::VectorXd curvature, area, angle_sum, largest_corner;
  Eigen::VectorXd face_area;  ///< each face's share of the 3D area
  CornerAngles angles;
  Eigen::SparseMatrix<double> A;  ///< L plus the penalty on the held vertices
  SparseCholesky cholesky;
  Eigen::VectorXd rhs0;  ///< -K off the held vertices: u0 = A^-1 rhs0

  /// P x = a (x - mean_a x): J = u^T P u.
  Eigen::VectorXd spread(const Eigen::VectorXd& x) const {
    const double mean = area.dot(x);
    return (area.array() * (x.array() - mean)).matrix();
  }
};

void check_cone_options(const ConeSelectionOptions& options) {
  if (options.count < 0 || options.max_cones < 0 || !(options.max_log_scale > 0) ||
      !(options.max_face_angle > 0) || !(options.max_corner_angle > 0) ||
      !(options.max_curvature < 2 * std::numbers::pi) || !(options.smoothness >= 0)) {
    throw InvalidInput(
        "select_cones: count and max_cones must be >= 0, max_log_scale, max_face_angle and "
        "max_corner_angle > 0, max_curvature < 2 pi, smoothness >= 0");
  }
}

}  // namespace

struct ConeModel::Data : ConeModelData {};

ConeModel::ConeModel(std::unique_ptr<Data> data) : data_(std::move(data)) {}
ConeModel::ConeModel(ConeModel&&) noexcept = default;
ConeModel& ConeModel::operator=(ConeModel&&) noexcept = default;
ConeModel::~ConeModel() = default;

ConeModel build_cone_model(const FlowProblem& problem) {
  const build_counting::Scope counted(build_counting::Kind::ConeModel);
  auto data = std::make_unique<ConeModel::Data>();
  ConeModelData& model = *data;
  const Mesh& mesh = *problem.mesh;
  model.topology = &problem.topology;
  const Topology& t = problem.topology;
  if (t.components.size() != 1) {
    throw InvalidInput("select_cones: the mesh has " + std::to_string(t.components.size()) +
                       " connected components; choose cones for each on its own");
  }
  const int nv = model.nv = t.num_vertices;
  const ConformalStructure& s = problem.structure.structure;
  // The input lengths' vertex-scaling structure, for the intrinsic Delaunay Laplacian: the
  // problem's own when that is its scheme.
  auto vertex_scaling = [&] {
    if (s.scheme == Scheme::VertexScaling && s.geometry == Geometry::Euclidean) return s;
    StructureOptions vs;
    vs.scheme = Scheme::VertexScaling;
    return make_conformal_structure(t, problem.input_lengths, vs).structure;
  };
  Eigen::VectorXd lengths, hw, ew;
  edge_lengths(t, s, s.initial_u, lengths);
  if (!corner_angles(t, lengths, model.angles).ok()) {
    throw InvalidInput("select_cones: the initial metric breaks a triangle inequality");
  }
  vertex_curvature(t, model.angles, model.curvature);
  Eigen::SparseMatrix<double> L;
  if (scheme_traits(s.scheme).ptolemy_flips) {
    // The flow with flips linearises to the Laplacian of the intrinsic Delaunay triangulation.
    L = intrinsic_delaunay_laplacian(t, problem.input_lengths, vertex_scaling());
  } else {
    halfedge_weights(t, s, s.initial_u, lengths, model.angles, hw);
    edge_weights(t, hw, ew);
    L = curvature_hessian(t, ew);
    if (!positive_definite_with_one_pin(L)) {
      // Obtuse needles make some weights negative enough that L is indefinite (the repaired
      // Stanford dragon): the intrinsic Delaunay Laplacian has non-negative weights.
      L = intrinsic_delaunay_laplacian(t, problem.input_lengths, vertex_scaling());
    }
  }

  // Area weights: a third of the 3D area of the faces around each vertex, normalised.
  model.face_area = face_areas(mesh, t);
  model.area = vertex_areas(t, model.face_area);
  const bool has_boundary = t.num_boundary_loops() > 0;
  model.chi = t.euler_characteristic();
  model.closed = !has_boundary;
  // Dirichlet vertices (the boundary) and the gauge of a closed surface are held at u = 0 by a
  // penalty on the diagonal; the cones are sources on the right-hand side, so one factorisation
  // serves every cone set.
  model.held.assign(nv, 0);
  for (int v = 0; v < nv; ++v) model.held[v] = has_boundary && t.is_boundary_vertex[v];
  if (model.closed) {
    model.gauge = 0;
    model.held[0] = 1;
  }
  const double penalty = 1e10 * std::max(1.0, L.diagonal().cwiseAbs().maxCoeff());
  model.A = L;
  for (int v = 0; v < nv; ++v) {
    if (model.held[v]) model.A.coeffRef(v, v) += penalty;
  }
  model.cholesky.analyze(model.A);
  model.cholesky.factorize(model.A);
  model.rhs0 = -model.curvature;
  for (int v = 0; v < nv; ++v) {
    if (model.held[v] && v != model.gauge) model.rhs0[v] = 0;
  }
  model.angle_sum = Eigen::VectorXd::Zero(nv);
  model.largest_corner = Eigen::VectorXd::Zero(nv);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = t.triangles(f, c);
      model.angle_sum[v] += model.angles(f, c);
      model.largest_corner[v] = std::max(model.largest_corner[v], model.angles(f, c));
    }
  }
  return ConeModel(std::move(data));
}

namespace {

/// Cone bounds: drawable on the input's faces, and a positive angle. Near a cone the map scales
/// the angles at the vertex by about (its cone angle) / (its angle sum in the input), so the
/// largest input corner there, scaled, must stay below max_corner_angle; and the average below
/// max_face_angle.
double cone_lower_bound(const ConeModelData& model, const ConeSelectionOptions& options, int v) {
  const double by_average = options.max_face_angle * model.topology->vertex_degree[v];
  const double by_largest = options.max_corner_angle * model.angle_sum[v] / model.largest_corner[v];
  return 2 * std::numbers::pi - std::min(by_average, by_largest);
}

}  // namespace

ConeSelection select_cones(const Mesh& mesh, const ConeSelectionOptions& options) {
  check_cone_options(options);
  const FlowProblem problem = make_flow_problem(mesh, options.structure);
  return select_cones(build_cone_model(problem), options);
}

ConeSelection select_cones(const ConeModel& handle, const ConeSelectionOptions& options) {
  check_cone_options(options);
  const ConeModelData& model = handle.data();
  const Topology& t = *model.topology;
  const int nv = model.nv;
  constexpr double kPi = std::numbers::pi;
  const Eigen::VectorXd& curvature = model.curvature;
  const Eigen::VectorXd& area = model.area;
  auto spread = [&](const Eigen::VectorXd& x) { return model.spread(x); };
  const bool closed = model.closed;
  const int chi = model.chi;
  const std::vector<char>& held = model.held;
  const int gauge = model.gauge;
  const SparseCholesky& cholesky = model.cholesky;
  const Eigen::VectorXd& rhs0 = model.rhs0;
  const Eigen::VectorXd u0 = cholesky.solve(rhs0);
  const Eigen::VectorXd Pu0 = spread(u0);
  auto lower_bound = [&](int v) { return cone_lower_bound(model, options, v); };
  const double upper = options.max_curvature;

  const std::vector<std::vector<int>> neighbours = vertex_neighbours(t);
  // A cone of curvature k makes u behave like -(k / 2 pi) log r next to it: the cone itself,
  // not distortion more cones could remove. Vertices within `separation` rings of a cone are
  // left out of the measure and of the candidates (else cones pile up next to each other).
  int separation = kSeparationRings;
  std::vector<int> ring(nv, std::numeric_limits<int>::max() / 2);

  ConeSelection result;
  std::vector<int>& S = result.vertices;
  Eigen::MatrixXd M(0, 0), green(0, 0);
  // Weight of the Dirichlet energy per face (see ConeObjective).
  const double smooth = options.smoothness / t.num_faces;
  Eigen::VectorXd r(0);
  std::vector<char> is_cone(nv, 0);
  // The cones' columns of A^-1, kept while they fit in kColumnValues doubles (the objective's
  // iterations then take no solve, and M comes from dot products).
  std::vector<Eigen::VectorXd> columns;
  auto add_cone = [&](int v) {
    const int m = static_cast<int>(S.size());
    Eigen::VectorXd e = Eigen::VectorXd::Zero(nv);
    e[v] = 1;
    Eigen::VectorXd g = cholesky.solve(e);
    const Eigen::VectorXd Pg = spread(g);
    const bool keep = static_cast<double>(nv) * (m + 1) <= kColumnValues &&
                      columns.size() == static_cast<std::size_t>(m);
    M.conservativeResize(m + 1, m + 1);
    green.conservativeResize(m + 1, m + 1);
    r.conservativeResize(m + 1);
    if (keep) {
      // M_im = g_i^T P g_m (= (A^-1 P g_m)_{S_i}: A is symmetric).
      for (int i = 0; i < m; ++i) M(i, m) = M(m, i) = columns[i].dot(Pg);
      M(m, m) = g.dot(Pg);
    } else {
      columns.clear();
      const Eigen::VectorXd h = cholesky.solve(Pg);
      for (int i = 0; i < m; ++i) M(i, m) = M(m, i) = h[S[i]];
      M(m, m) = h[v];
    }
    S.push_back(v);
    is_cone[v] = 1;
    for (int i = 0; i <= m; ++i) green(i, m) = green(m, i) = g[S[i]];
    r[m] = g.dot(Pu0);
    if (keep) columns.push_back(std::move(g));
    grow_rings(neighbours, v, separation, ring);
  };
  auto reset_rings = [&]() {
    std::fill(ring.begin(), ring.end(), std::numeric_limits<int>::max() / 2);
    for (int v : S) grow_rings(neighbours, v, separation, ring);
  };

  int max_cones = options.max_cones;
  if (max_cones == 0) {
    max_cones = 64;
    // Each cone can take at most about pi of negative curvature on a valence-6 vertex.
    if (closed && chi < 0) max_cones = std::max(max_cones, 6 * -chi);
  }
  const int wanted = options.count > 0 ? std::min(options.count, std::max(max_cones, 1)) : -1;
  const double total = 2 * kPi * chi;

  if (closed && chi != 0) {
    // The first cone makes the problem solvable: among well-spread candidates (farthest-point
    // samples in edge hops, from the vertex of most extreme curvature), the one whose single
    // cone of 2 pi chi spreads u least.
    int first = 1 % nv;
    for (int v = 0; v < nv; ++v) {
      if (v == gauge) continue;
      if ((chi > 0 && curvature[v] > curvature[first]) ||
          (chi < 0 && curvature[v] < curvature[first])) {
        first = v;
      }
    }
    std::vector<int> candidates = {first};
    std::vector<int> hops(nv, std::numeric_limits<int>::max());
    grow_rings(neighbours, first, std::numeric_limits<int>::max(), hops);
    while (static_cast<int>(candidates.size()) < std::max(1, options.try_first_cone_candidates)) {
      int far = -1;
      for (int v = 0; v < nv; ++v) {
        if (v != gauge && (far < 0 || hops[v] > hops[far])) far = v;
      }
      if (far < 0 || hops[far] == 0) break;
      candidates.push_back(far);
      grow_rings(neighbours, far, std::numeric_limits<int>::max(), hops);
    }
    int best = first;
    double best_energy = INFINITY;
    for (int c : candidates) {
      Eigen::VectorXd rhs = rhs0;
      rhs[c] += total;
      const Eigen::VectorXd u = cholesky.solve(rhs);
      const double energy = u.dot(spread(u));
      if (energy < best_energy) {
        best_energy = energy;
        best = c;
      }
    }
    add_cone(best);
  }

  Eigen::VectorXd k;
  // The objective's quasi-Newton Hessian at the previous fit.
  Eigen::MatrixXd hessian;
  // The last cone set whose curvatures met their bounds: when automatic selection ends out of
  // bounds (the cap, or cones so close together on a needle mesh that the bounded problem had
  // no solution and its unbounded fallback gave curvatures of +-36), it returns that one.
  struct Good {
    int m = 0;
    Eigen::VectorXd k;
    double rms = 0;
  } last_good;
  // The curvatures of the current cone set: the J minimiser (a bounded quadratic programme),
  // then the objective's (warm-started from the previous greedy step when `warm`).
  struct SetFit {
    bool within = true;  ///< the bounds could be met
    double value = INFINITY, lambda = 0;
    Eigen::VectorXd k, u, q;  ///< q: the gradient at every vertex (J's when out of bounds)
  };
  auto fit_set = [&](const Eigen::VectorXd* start, bool need_q) {
    const int m = static_cast<int>(S.size());
    SetFit fit;
    Eigen::VectorXd lo(m), hi(m);
    for (int i = 0; i < m; ++i) {
      lo[i] = lower_bound(S[i]);
      hi[i] = upper;
    }
    if (m > 0) {
      fit.within = bounded_least_squares(M, r, lo, hi, closed, total, fit.k, fit.lambda);
    }
    if (m > 0 && fit.within) {
      // From the L2 minimiser to the area distortion's: the gradient of F at it chooses the next
      // cone, so the greedy measures what the texture shows. A start within the bounds (the
      // previous step's minimiser) saves most iterations; `hessian` holds the previous estimate.
      const ConeObjective objective{cholesky, rhs0, u0, t, model.face_area, S, columns, smooth};
      if (start && start->size() == m) {
        bool inside = std::abs(start->sum() - fit.k.sum()) <= 1e-9 * (1 + std::abs(total));
        for (int i = 0; i < m; ++i) {
          inside = inside && (*start)[i] >= lo[i] && (*start)[i] <= hi[i];
        }
        if (inside) fit.k = *start;
      }
      fit.u = minimise_cone_objective(objective, M, green, lo, hi, closed, total, fit.k, hessian,
                                      need_q ? &fit.q : nullptr, fit.value);
      fit.lambda = 0;
      if (closed && need_q) {
        int free = 0;
        for (int i = 0; i < m; ++i) {
          if (fit.k[i] > lo[i] + 1e-9 && fit.k[i] < hi[i] - 1e-9) {
            fit.lambda -= fit.q[S[i]];
            ++free;
          }
        }
        fit.lambda /= std::max(free, 1);
      }
    } else {
      Eigen::VectorXd rhs = rhs0;
      for (int i = 0; i < m; ++i) rhs[S[i]] += fit.k[i];
      fit.u = cholesky.solve(rhs);
      fit.q = cholesky.solve(spread(fit.u));
    }
    return fit;
  };
  // Vertices of a face with a corner above max_corner_angle: a cone there steepens u across
  // that face, whose angle distortion (the checker's face mean) then explodes or whose corner
  // images cross (a CAD cylinder's fan: one 178.5-degree face next to an exchanged cone took
  // sigma ratio 2836 and the mean from 1.79 to 4.15; lifted valence-3 spikes, 141-degree
  // corners: 6 flipped faces, 2 with this). They are candidates only when no other vertex is.
  std::vector<char> on_sliver(nv, 0);
  for (int f = 0; f < t.num_faces; ++f) {
    if (model.angles.row(f).maxCoeff() <= options.max_corner_angle) continue;
    for (int c = 0; c < 3; ++c) on_sliver[t.triangles(f, c)] = 1;
  }
  // The best candidate for a new cone by the gradient q (not held, not a cone, outside the
  // rings of the cones, and on a closed surface with a lower bound the total can still pay);
  // -1 when there is none.
  auto best_candidate = [&](const SetFit& fit) {
    double lower_sum = 0;
    for (int c : S) lower_sum += lower_bound(c);
    int best = -1;
    for (int pass = 0; pass < 2 && best < 0; ++pass) {
      double best_gain = -1;
      for (int v = 0; v < nv; ++v) {
        if (held[v] || is_cone[v] || t.vertex_component[v] < 0 || ring[v] <= separation) continue;
        if (pass == 0 && on_sliver[v]) continue;
        const double gain = std::abs(fit.q[v] + fit.lambda);
        if (gain <= best_gain) continue;
        const double lo_v = lower_bound(v);
        if (closed && lo_v > 0 && lower_sum + lo_v > total + 1e-9) continue;
        best = v;
        best_gain = gain;
      }
    }
    return best;
  };
  // Curvatures in quarter turns for the cones S: rounded (the sum kept, as quantize_cones does),
  // then a quarter turn moved from one cone to another while the objective falls; the moves
  // tried first are those its gradient predicts to gain most. A cone that ends at 0 is none.
  auto quantize_in_model = [&](const std::vector<int>& cones, const Eigen::VectorXd& k_real) {
    const int m = static_cast<int>(cones.size());
    const double quarter = kPi / 2;
    std::vector<Cone> real(m);
    double sum = 0;
    for (int i = 0; i < m; ++i) {
      real[i] = {i, k_real[i]};
      sum += k_real[i];
    }
    const double units_total = std::round((closed ? total : sum) / quarter) * quarter;
    Eigen::VectorXd kq = Eigen::VectorXd::Zero(m);
    for (const Cone& c : quantize_cones(real, units_total)) kq[c.vertex] = c.curvature;
    auto allowed = [&](int i, double value) {
      return value <= options.max_curvature + 1e-12 && value >= lower_bound(cones[i]) - 1e-12;
    };
    const ConeObjective objective{cholesky, rhs0, u0, t, model.face_area, cones, columns, smooth};
    Eigen::VectorXd u = objective.solve_u(kq);
    double value = objective.value(u, kq);
    for (int move = 0; move < 4 * m + 8; ++move) {
      const Eigen::VectorXd g = objective.gradient(u);
      std::vector<std::pair<double, std::pair<int, int>>> moves;  // predicted change, (to, from)
      for (int i = 0; i < m; ++i) {
        for (int j = 0; j < m; ++j) {
          if (i == j || !allowed(i, kq[i] + quarter) || !allowed(j, kq[j] - quarter)) continue;
          moves.push_back({quarter * (g[i] - g[j]), {i, j}});
        }
      }
      std::sort(moves.begin(), moves.end());
      bool improved = false;
      for (std::size_t a = 0; a < std::min<std::size_t>(moves.size(), 8) && !improved; ++a) {
        const auto [i, j] = moves[a].second;
        Eigen::VectorXd trial = kq;
        trial[i] += quarter;
        trial[j] -= quarter;
        const Eigen::VectorXd u_trial = objective.solve_u(trial);
        const double v = objective.value(u_trial, trial);
        if (v < value - 1e-12 * (1 + std::abs(value))) {
          kq = trial;
          u = u_trial;
          value = v;
          improved = true;
        }
      }
      if (!improved) break;
    }
    return kq;
  };
  SetFit fit;
  for (;;) {
    const int m = static_cast<int>(S.size());
    Eigen::VectorXd warm;
    if (fit.k.size() > 0 && fit.k.size() < m && fit.within) {
      warm = Eigen::VectorXd::Zero(m);  // the new cones at 0
      warm.head(fit.k.size()) = fit.k;
    }
    fit = fit_set(&warm, true);
    result.within_bounds = fit.within;
    k = fit.k;
    const Eigen::VectorXd& u = fit.u;
    const Eigen::VectorXd& q = fit.q;
    const double lambda = fit.lambda;
    if (m > 0 && fit.within)
      result.area_energy = std::expm1(area_energy(t, model.face_area, u, nullptr));
    const Eigen::VectorXd Pu = spread(u);
    const double mean = area.dot(u);
    double largest = 0;
    for (int v = 0; v < nv; ++v) {
      if (ring[v] > separation) largest = std::max(largest, std::abs(u[v] - mean));
    }
    result.max_log_scale.push_back(largest);
    result.log_scale_rms = std::sqrt(std::max(0.0, u.dot(Pu)));
    if (result.within_bounds && m > 0) {
      last_good = {m, k, result.log_scale_rms};
    }
    const bool done =
        wanted >= 0 ? m >= wanted
                    : (largest <= options.max_log_scale && result.within_bounds) || m >= max_cones;
    if (done) break;
    // dF/dk_t (or dJ/dk_t) for every vertex t at once: q = A^-1 dF/du (A is symmetric); on a
    // closed surface a new cone's curvature comes out of the others', whose common gradient is
    // -lambda.
    const int batch = std::max(1, m / 8);
    const int room = (wanted >= 0 ? wanted : max_cones) - m;
    std::vector<std::pair<double, int>> order;
    for (int pass = 0; pass < 2 && order.empty(); ++pass) {
      for (int v = 0; v < nv; ++v) {
        if (held[v] || is_cone[v] || t.vertex_component[v] < 0 || ring[v] <= separation) continue;
        if (pass == 0 && on_sliver[v]) continue;
        order.emplace_back(-std::abs(q[v] + lambda), v);
      }
    }
    if (order.empty()) {
      if (separation == 0) break;
      --separation;  // crowded (high genus on a coarse mesh): let cones come closer
      reset_rings();
      continue;
    }
    std::sort(order.begin(), order.end());
    // On a closed surface the cones' curvatures sum to 2 pi chi, so their lower bounds must not
    // exceed it: a vertex with a corner near pi (a CAD sliver) must take a strong positive cone,
    // and a few of them made the bounds infeasible (unbounded curvatures of 3 pi on a needle
    // cylinder). Candidates with a positive lower bound are skipped once they would.
    double lower_sum = 0;
    for (int c : S) lower_sum += lower_bound(c);
    int added = 0;
    for (const auto& [gain, v] : order) {
      if (added >= std::min(batch, room)) break;
      if (ring[v] <= separation) continue;  // next to a cone added in this batch
      const double lo_v = lower_bound(v);
      if (closed && lo_v > 0 && lower_sum + lo_v > total + 1e-9) continue;
      add_cone(v);
      lower_sum += lo_v;
      ++added;
    }
    if (added == 0) break;  // no candidate keeps the bounds feasible
  }
  // Exchange: the greedy order is not the best placement of its cones (the first ones were
  // chosen when the others were missing). Each cone in turn is taken out and the best candidate
  // for the others put in its place; kept when the objective falls.
  const int chosen = static_cast<int>(S.size());
  if (result.within_bounds && chosen > 0 && chosen <= kExchangeCones &&
      (wanted < 0 || chosen == wanted) && fit.value < INFINITY) {
    const int passes = chosen <= kExchangeTwice ? 2 : 1;
    for (int pass = 0; pass < passes; ++pass) {
      bool improved = false;
      for (int i = 0; i < static_cast<int>(S.size()); ++i) {
        const std::vector<int> S_before = S;
        const Eigen::MatrixXd M_before = M, green_before = green;
        const Eigen::VectorXd r_before = r;
        const std::vector<int> ring_before = ring;
        const int removed = S[i];
        Eigen::VectorXd removed_column;
        const bool had_columns = columns.size() == S.size();
        if (had_columns) removed_column = std::move(columns[i]);
        auto erase = [&](Eigen::MatrixXd& X) {
          const int n = static_cast<int>(X.rows());
          Eigen::MatrixXd Y(n - 1, n - 1);
          for (int a = 0, ya = 0; a < n; ++a) {
            if (a == i) continue;
            for (int b = 0, yb = 0; b < n; ++b) {
              if (b == i) continue;
              Y(ya, yb++) = X(a, b);
            }
            ++ya;
          }
          X = std::move(Y);
        };
        erase(M);
        erase(green);
        Eigen::VectorXd r_less(r.size() - 1);
        for (int a = 0, ya = 0; a < r.size(); ++a) {
          if (a != i) r_less[ya++] = r[a];
        }
        r = std::move(r_less);
        S.erase(S.begin() + i);
        if (had_columns) columns.erase(columns.begin() + i);
        is_cone[removed] = 0;
        reset_rings();
        const Eigen::MatrixXd hessian_before = hessian;
        if (hessian.rows() == static_cast<int>(S_before.size())) {
          erase(hessian);  // a principal submatrix: still positive definite
        } else {
          hessian.resize(0, 0);
        }
        // Start: cone i's curvature shared by the others (the sum is kept).
        Eigen::VectorXd start(S.size());
        for (int a = 0, ya = 0; a < fit.k.size(); ++a) {
          if (a != i) start[ya++] = fit.k[a] + fit.k[i] / static_cast<double>(S.size());
        }
        const SetFit without = fit_set(&start, true);
        const int v = without.within ? best_candidate(without) : -1;
        bool accepted = false;
        if (v >= 0 && v != removed) {
          add_cone(v);
          Eigen::VectorXd extended = Eigen::VectorXd::Zero(static_cast<int>(S.size()));
          extended.head(without.k.size()) = without.k;
          const SetFit with = fit_set(&extended, false);
          if (with.within && with.value < fit.value - 1e-9 * (1 + std::abs(fit.value))) {
            // (The new cone goes to the end of `vertices`.)
            fit = with;
            accepted = improved = true;
          } else {
            is_cone[v] = 0;
          }
        }
        if (!accepted) {
          if (had_columns) {
            if (columns.size() > S_before.size() - 1) columns.pop_back();
            columns.insert(columns.begin() + i, std::move(removed_column));
          } else {
            columns.clear();
          }
          S = S_before;
          M = M_before;
          green = green_before;
          r = r_before;
          ring = ring_before;
          hessian = hessian_before;
          is_cone[removed] = 1;
        }
      }
      if (!improved) break;
    }
    k = fit.k;
    result.area_energy = std::expm1(area_energy(t, model.face_area, fit.u, nullptr));
    result.log_scale_rms = std::sqrt(std::max(0.0, fit.u.dot(spread(fit.u))));
  }
  if (!result.within_bounds && wanted < 0 && last_good.m > 0) {
    S.resize(static_cast<std::size_t>(last_good.m));
    if (columns.size() > S.size()) columns.resize(S.size());
    k = last_good.k;
    result.log_scale_rms = last_good.rms;
    result.within_bounds = true;
  }
  if (options.quantize && result.within_bounds && !S.empty()) {
    k = quantize_in_model(S, k);
    const ConeObjective objective{cholesky, rhs0, u0, t, model.face_area, S, columns, smooth};
    const Eigen::VectorXd u = objective.solve_u(k);
    result.area_energy = std::expm1(area_energy(t, model.face_area, u, nullptr));
    result.log_scale_rms = std::sqrt(std::max(0.0, u.dot(spread(u))));
  }
  result.linear_curvature.assign(k.data(), k.data() + k.size());
  return result;
}

namespace {

double log_scale_spread(const Topology& t, const Eigen::VectorXd& area, const Eigen::VectorXd& u,
                        const std::vector<int>& cones) {
  const int nv = t.num_vertices;
  std::vector<std::vector<int>> neighbours = vertex_neighbours(t);
  std::vector<int> ring(nv, std::numeric_limits<int>::max() / 2);
  for (int c : cones) grow_rings_within(neighbours, c, kSeparationRings, area, kRingArea, ring);
  double mean = 0, weight = 0;
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_component[v] < 0) continue;
    mean += area[v] * u[v];
    weight += area[v];
  }
  mean /= std::max(weight, 1e-300);
  double largest = 0;
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_component[v] < 0 || ring[v] <= kSeparationRings) continue;
    largest = std::max(largest, std::abs(u[v] - mean));
  }
  return largest;
}

}  // namespace

double log_scale_spread(const Mesh& mesh, const Topology& t, const Eigen::VectorXd& u,
                        const std::vector<int>& cones) {
  return log_scale_spread(t, vertex_areas(t, face_areas(mesh, t)), u, cones);
}

double log_scale_spread(const ConeModel& model, const Eigen::VectorXd& u,
                        const std::vector<int>& cones) {
  return log_scale_spread(*model.data().topology, model.data().area, u, cones);
}

std::vector<Cone> quantize_cones(const std::vector<Cone>& cones, double total) {
  const double quarter = std::numbers::pi / 2;
  const long target_units = std::lround(total / quarter);
  std::vector<long> units(cones.size());
  long sum = 0;
  for (std::size_t i = 0; i < cones.size(); ++i) {
    units[i] = std::min(std::lround(cones[i].curvature / quarter), 3L);  // below 2 pi
    sum += units[i];
  }
  // Move the cones whose curvature lies closest to the other rounding, one quarter turn each.
  while (sum != target_units && !cones.empty()) {
    const long step = sum < target_units ? 1 : -1;
    std::size_t best = 0;
    double best_cost = INFINITY;
    for (std::size_t i = 0; i < cones.size(); ++i) {
      const double cost =
          std::abs(cones[i].curvature / quarter - static_cast<double>(units[i] + step));
      if (units[i] + step < 4 && cost < best_cost) {  // a cone stays below 2 pi
        best_cost = cost;
        best = i;
      }
    }
    if (!std::isfinite(best_cost)) break;
    units[best] += step;
    sum += step;
  }
  std::vector<Cone> out;
  for (std::size_t i = 0; i < cones.size(); ++i) {
    if (units[i] != 0) out.push_back({cones[i].vertex, static_cast<double>(units[i]) * quarter});
  }
  return out;
}

}  // namespace ricci
