#include "ricci/param/cones/cones.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <numbers>

#include "param/cones/detail/cone_selection_steps.hpp"
#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/mesh/build_counts.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/numerics/bounded_least_squares.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace ricci {

using cone_steps::ConeModelData;

namespace {

/// The penalty that holds a vertex at u = 0, relative to the largest diagonal entry of the
/// Laplacian (at least 1): large enough that a held vertex's u is about 1e-10 of its
/// neighbours' (held as if exactly), and a large diagonal entry costs the Cholesky factorisation
/// no accuracy.
constexpr double kHeldPenalty = 1e10;

/// Whether L plus a large penalty on vertex 0 (the gauge) factorises: a connected component's
/// Laplacian with non-negative enough weights does.
bool positive_definite_with_one_pin(const Eigen::SparseMatrix<double>& L) {
  Eigen::SparseMatrix<double> A = L;
  A.coeffRef(0, 0) += kHeldPenalty * std::max(1.0, L.diagonal().cwiseAbs().maxCoeff());
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

/// Each vertex's neighbours along the edges, in edge order.
std::vector<std::vector<int>> vertex_neighbours(const Topology& t) {
  std::vector<std::vector<int>> neighbours(t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    neighbours[t.edge_vertices(e, 0)].push_back(t.edge_vertices(e, 1));
    neighbours[t.edge_vertices(e, 1)].push_back(t.edge_vertices(e, 0));
  }
  return neighbours;
}

/// The ring count of a vertex no cone's rings reach: above any count of rings.
constexpr int kFarFromCones = std::numeric_limits<int>::max() / 2;

/// Automatic selection's cap on the number of cones when options.max_cones is 0.
constexpr int kDefaultMaxCones = 64;
/// The greedy adds max(1, #S / kBatchDivisor) cones a step (one fit per batch, not per cone).
constexpr int kBatchDivisor = 8;

/// Curvature sums (radians) meet 2 pi chi within this, relative to 1 + |2 pi chi|; a lower
/// bound sum may exceed 2 pi chi by this (absolute): rounding of a sum of a few dozen
/// curvatures of order pi, far below any cone that matters.
constexpr double kCurvatureSumSlack = 1e-9;
/// A curvature within this of its bound counts as at the bound (not free) when the sum
/// constraint's multiplier is estimated from the free cones.
constexpr double kAtBound = 1e-9;
/// An exchange is kept when it lowers the objective by more than this, relative to 1 + |F|:
/// a smaller gain is rounding, and the exchange would only move cones around.
constexpr double kExchangeGain = 1e-9;
/// Quarter-turn curvatures may exceed their bounds by this: k pi / 2 against a bound that is
/// itself a multiple of pi / 2 (2 pi - 3 pi / 2) differs by rounding only.
constexpr double kQuarterTurnSlack = 1e-12;
/// A quarter-turn move is kept when it lowers the objective by more than this, relative to
/// 1 + |F| (a smaller gain is rounding).
constexpr double kQuantizeGain = 1e-12;
/// Quarter-turn moves tried per round, best predicted first.
constexpr std::size_t kMovesTried = 8;

/// The quasi-Newton iterations of minimise_cone_objective: at most kObjectiveIterations steps.
constexpr int kObjectiveIterations = 60;
/// The ridge on the model Hessian, relative to its largest diagonal entry: keeps it positive
/// definite where green or M are only semi-definite (a cone on a held vertex's neighbour).
constexpr double kModelHessianRidge = 1e-9;
/// Floor of the scale the ridge is relative to (a zero Hessian still gets a positive ridge).
constexpr double kSmallestScale = 1e-300;
/// A step whose largest curvature change is below this (radians) is no step: converged.
constexpr double kSmallestStep = 1e-12;
/// Armijo's sufficient decrease: the step is taken once F falls by this times the slope. The
/// same value as FlowOptions::armijo's default (1e-4), chosen on its own (the flow's line search
/// works on another function).
constexpr double kArmijo = 1e-4;
/// Line-search halvings before giving up (FlowOptions::max_backtracks is 50: 2^-30 of a
/// quasi-Newton step is already no step for curvatures).
constexpr int kBacktracks = 30;
/// Each backtrack halves the step.
constexpr double kBacktrackFactor = 0.5;
/// The BFGS update is skipped unless s.y exceeds this times |s| |y| (curvature condition, with
/// room for rounding): keeps B positive definite.
constexpr double kCurvatureCondition = 1e-12;
/// Stop once a step lowers F by at most this, relative to 1 + |F|.
constexpr double kRelativeDecrease = 1e-8;

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
      kModelHessianRidge * std::max(kSmallestScale, model_hessian.diagonal().cwiseAbs().maxCoeff());
  Eigen::MatrixXd start = model_hessian;
  const int kept = static_cast<int>(std::min<Eigen::Index>(B.rows(), m));
  if (kept > 0 && B.cols() == B.rows()) {
    start.topLeftCorner(kept, kept) = B.topLeftCorner(kept, kept);
    if (start.llt().info() != Eigen::Success) start = model_hessian;
  }
  B = std::move(start);
  for (int iteration = 0; iteration < kObjectiveIterations; ++iteration) {
    const Eigen::VectorXd linear = g - B * k;
    BoundedLeastSquaresOptions sum;
    sum.sum_constraint = closed;
    sum.total = total;
    const BoundedLeastSquaresResult step_target = bounded_least_squares(B, linear, lo, hi, sum);
    if (!step_target.feasible) break;
    const Eigen::VectorXd direction = step_target.x - k;
    if (direction.cwiseAbs().maxCoeff() < kSmallestStep) break;
    const double slope = g.dot(direction);
    if (!(slope < 0)) break;
    double step = 1;
    Eigen::VectorXd k_new, u_new;
    double value_new = INFINITY;
    for (int tries = 0; tries < kBacktracks; ++tries, step *= kBacktrackFactor) {
      k_new = k + step * direction;
      u_new = objective.solve_u(k_new);
      value_new = objective.value(u_new, k_new);
      if (value_new <= value + kArmijo * step * slope) break;
    }
    if (!(value_new < value)) break;
    const Eigen::VectorXd g_new = objective.gradient(u_new);
    const Eigen::VectorXd s = k_new - k, y = g_new - g;
    const double sy = s.dot(y);
    if (sy > kCurvatureCondition * s.norm() * y.norm()) {
      const Eigen::VectorXd Bs = B * s;
      B += y * y.transpose() / sy - Bs * Bs.transpose() / s.dot(Bs);
    }
    const double decrease = value - value_new;
    k = k_new;
    u = u_new;
    g = g_new;
    value = value_new;
    if (decrease <= kRelativeDecrease * (1 + std::abs(value))) break;
  }
  if (gradient_all) *gradient_all = objective.gradient_everywhere(u);
  return u;
}

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
  const double penalty = kHeldPenalty * std::max(1.0, L.diagonal().cwiseAbs().maxCoeff());
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

namespace cone_steps {

/// Cone bounds: drawable on the input's faces, and a positive angle. Near a cone the map scales
/// the angles at the vertex by about (its cone angle) / (its angle sum in the input), so the
/// largest input corner there, scaled, must stay below max_corner_angle; and the average below
/// max_face_angle.
double cone_lower_bound(const ConeModelData& model, const ConeSelectionOptions& options, int v) {
  const double by_average = options.max_face_angle * model.topology->vertex_degree[v];
  const double by_largest = options.max_corner_angle * model.angle_sum[v] / model.largest_corner[v];
  return 2 * std::numbers::pi - std::min(by_average, by_largest);
}

ConeSelector make_cone_selector(const ConeModelData& model, const ConeSelectionOptions& options) {
  const Topology& t = *model.topology;
  const int nv = model.nv;
  ConeSelector selector(model, options);
  selector.u0 = model.cholesky.solve(model.rhs0);
  selector.Pu0 = model.spread(selector.u0);
  selector.upper = options.max_curvature;
  selector.neighbours = vertex_neighbours(t);
  selector.separation = kSeparationRings;
  selector.ring.assign(nv, kFarFromCones);
  selector.M.resize(0, 0);
  selector.green.resize(0, 0);
  selector.smooth = options.smoothness / t.num_faces;
  selector.r.resize(0);
  selector.is_cone.assign(nv, 0);
  selector.max_cones = options.max_cones;
  if (selector.max_cones == 0) {
    selector.max_cones = kDefaultMaxCones;
    // Each cone can take at most about pi of negative curvature on a valence-6 vertex.
    if (model.closed && model.chi < 0) {
      selector.max_cones = std::max(selector.max_cones, 6 * -model.chi);
    }
  }
  selector.wanted =
      options.count > 0 ? std::min(options.count, std::max(selector.max_cones, 1)) : -1;
  selector.total = 2 * std::numbers::pi * model.chi;
  selector.on_sliver.assign(nv, 0);
  for (int f = 0; f < t.num_faces; ++f) {
    if (model.angles.row(f).maxCoeff() <= options.max_corner_angle) continue;
    for (int c = 0; c < 3; ++c) selector.on_sliver[t.triangles(f, c)] = 1;
  }
  return selector;
}

void add_cone(ConeSelector& selector, int v) {
  ConeSelector& s = selector;
  const ConeModelData& model = s.model;
  const int nv = model.nv;
  const int m = static_cast<int>(s.S.size());
  Eigen::VectorXd e = Eigen::VectorXd::Zero(nv);
  e[v] = 1;
  Eigen::VectorXd g = model.cholesky.solve(e);
  const Eigen::VectorXd Pg = model.spread(g);
  const bool keep = static_cast<double>(nv) * (m + 1) <= kColumnValues &&
                    s.columns.size() == static_cast<std::size_t>(m);
  s.M.conservativeResize(m + 1, m + 1);
  s.green.conservativeResize(m + 1, m + 1);
  s.r.conservativeResize(m + 1);
  if (keep) {
    // M_im = g_i^T P g_m (= (A^-1 P g_m)_{S_i}: A is symmetric).
    for (int i = 0; i < m; ++i) s.M(i, m) = s.M(m, i) = s.columns[i].dot(Pg);
    s.M(m, m) = g.dot(Pg);
  } else {
    s.columns.clear();
    const Eigen::VectorXd h = model.cholesky.solve(Pg);
    for (int i = 0; i < m; ++i) s.M(i, m) = s.M(m, i) = h[s.S[i]];
    s.M(m, m) = h[v];
  }
  s.S.push_back(v);
  s.is_cone[v] = 1;
  for (int i = 0; i <= m; ++i) s.green(i, m) = s.green(m, i) = g[s.S[i]];
  s.r[m] = g.dot(s.Pu0);
  if (keep) s.columns.push_back(std::move(g));
  grow_rings(s.neighbours, v, s.separation, s.ring);
}

void reset_rings(ConeSelector& selector) {
  std::fill(selector.ring.begin(), selector.ring.end(), kFarFromCones);
  for (int v : selector.S) grow_rings(selector.neighbours, v, selector.separation, selector.ring);
}

std::vector<int> first_cone_candidates(const ConeSelector& selector) {
  const ConeModelData& model = selector.model;
  const int nv = model.nv, chi = model.chi, gauge = model.gauge;
  const Eigen::VectorXd& curvature = model.curvature;
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
  grow_rings(selector.neighbours, first, std::numeric_limits<int>::max(), hops);
  while (static_cast<int>(candidates.size()) <
         std::max(1, selector.options.try_first_cone_candidates)) {
    int far = -1;
    for (int v = 0; v < nv; ++v) {
      if (v != gauge && (far < 0 || hops[v] > hops[far])) far = v;
    }
    if (far < 0 || hops[far] == 0) break;
    candidates.push_back(far);
    grow_rings(selector.neighbours, far, std::numeric_limits<int>::max(), hops);
  }
  return candidates;
}

int seed_cone(const ConeSelector& selector) {
  const ConeModelData& model = selector.model;
  const std::vector<int> candidates = first_cone_candidates(selector);
  int best = candidates.front();
  double best_energy = INFINITY;
  for (int c : candidates) {
    Eigen::VectorXd rhs = model.rhs0;
    rhs[c] += selector.total;
    const Eigen::VectorXd u = model.cholesky.solve(rhs);
    const double energy = u.dot(model.spread(u));
    if (energy < best_energy) {
      best_energy = energy;
      best = c;
    }
  }
  return best;
}

SetFit fit_cone_set(ConeSelector& selector, const Eigen::VectorXd* start, bool need_q) {
  ConeSelector& s = selector;
  const ConeModelData& model = s.model;
  const std::vector<int>& S = s.S;
  const int m = static_cast<int>(S.size());
  SetFit fit;
  Eigen::VectorXd lo(m), hi(m);
  for (int i = 0; i < m; ++i) {
    lo[i] = cone_lower_bound(model, s.options, S[i]);
    hi[i] = s.upper;
  }
  if (m > 0) {
    BoundedLeastSquaresOptions sum;
    sum.sum_constraint = model.closed;
    sum.total = s.total;
    BoundedLeastSquaresResult l2 = bounded_least_squares(s.M, s.r, lo, hi, sum);
    fit.within = l2.feasible;
    fit.k = std::move(l2.x);
    fit.lambda = l2.multiplier;
  }
  if (m > 0 && fit.within) {
    // From the L2 minimiser to the area distortion's: the gradient of F at it chooses the next
    // cone, so the greedy measures what the texture shows. A start within the bounds (the
    // previous step's minimiser) saves most iterations; `hessian` holds the previous estimate.
    const ConeObjective objective{model.cholesky,  model.rhs0, s.u0,      *model.topology,
                                  model.face_area, S,          s.columns, s.smooth};
    if (start && start->size() == m) {
      bool inside =
          std::abs(start->sum() - fit.k.sum()) <= kCurvatureSumSlack * (1 + std::abs(s.total));
      for (int i = 0; i < m; ++i) {
        inside = inside && (*start)[i] >= lo[i] && (*start)[i] <= hi[i];
      }
      if (inside) fit.k = *start;
    }
    fit.u = minimise_cone_objective(objective, s.M, s.green, lo, hi, model.closed, s.total, fit.k,
                                    s.hessian, need_q ? &fit.q : nullptr, fit.value);
    fit.lambda = 0;
    if (model.closed && need_q) {
      int free = 0;
      for (int i = 0; i < m; ++i) {
        if (fit.k[i] > lo[i] + kAtBound && fit.k[i] < hi[i] - kAtBound) {
          fit.lambda -= fit.q[S[i]];
          ++free;
        }
      }
      fit.lambda /= std::max(free, 1);
    }
  } else {
    Eigen::VectorXd rhs = model.rhs0;
    for (int i = 0; i < m; ++i) rhs[S[i]] += fit.k[i];
    fit.u = model.cholesky.solve(rhs);
    fit.q = model.cholesky.solve(model.spread(fit.u));
  }
  return fit;
}

namespace {

/// Whether v may take a new cone: not held, not a cone, in the mesh, outside the cones' rings,
/// and (on pass 0) not on a sliver.
bool open_for_cone(const ConeSelector& s, int v, int pass) {
  if (s.model.held[v] || s.is_cone[v] || s.model.topology->vertex_component[v] < 0 ||
      s.ring[v] <= s.separation) {
    return false;
  }
  return !(pass == 0 && s.on_sliver[v]);
}

/// The sum of the cones' lower bounds.
double lower_bound_sum(const ConeSelector& s) {
  double lower_sum = 0;
  for (int c : s.S) lower_sum += cone_lower_bound(s.model, s.options, c);
  return lower_sum;
}

}  // namespace

int best_candidate(const ConeSelector& selector, const SetFit& fit) {
  const ConeSelector& s = selector;
  const double lower_sum = lower_bound_sum(s);
  int best = -1;
  for (int pass = 0; pass < 2 && best < 0; ++pass) {
    double best_gain = -1;
    for (int v = 0; v < s.model.nv; ++v) {
      if (!open_for_cone(s, v, pass)) continue;
      const double gain = std::abs(fit.q[v] + fit.lambda);
      if (gain <= best_gain) continue;
      const double lo_v = cone_lower_bound(s.model, s.options, v);
      if (s.model.closed && lo_v > 0 && lower_sum + lo_v > s.total + kCurvatureSumSlack) continue;
      best = v;
      best_gain = gain;
    }
  }
  return best;
}

bool add_cones(ConeSelector& selector, const SetFit& fit) {
  ConeSelector& s = selector;
  const int m = static_cast<int>(s.S.size());
  // dF/dk_t (or dJ/dk_t) for every vertex t at once: q = A^-1 dF/du (A is symmetric); on a
  // closed surface a new cone's curvature comes out of the others', whose common gradient is
  // -lambda.
  const int batch = std::max(1, m / kBatchDivisor);
  const int room = (s.wanted >= 0 ? s.wanted : s.max_cones) - m;
  std::vector<std::pair<double, int>> order;
  for (int pass = 0; pass < 2 && order.empty(); ++pass) {
    for (int v = 0; v < s.model.nv; ++v) {
      if (open_for_cone(s, v, pass)) order.emplace_back(-std::abs(fit.q[v] + fit.lambda), v);
    }
  }
  if (order.empty()) {
    if (s.separation == 0) return false;
    --s.separation;  // crowded (high genus on a coarse mesh): let cones come closer
    reset_rings(s);
    return true;
  }
  std::sort(order.begin(), order.end());
  // On a closed surface the cones' curvatures sum to 2 pi chi, so their lower bounds must not
  // exceed it: a vertex with a corner near pi (a CAD sliver) must take a strong positive cone,
  // and a few of them made the bounds infeasible (unbounded curvatures of 3 pi on a needle
  // cylinder). Candidates with a positive lower bound are skipped once they would.
  double lower_sum = lower_bound_sum(s);
  int added = 0;
  for (const auto& [gain, v] : order) {
    if (added >= std::min(batch, room)) break;
    if (s.ring[v] <= s.separation) continue;  // next to a cone added in this batch
    const double lo_v = cone_lower_bound(s.model, s.options, v);
    if (s.model.closed && lo_v > 0 && lower_sum + lo_v > s.total + kCurvatureSumSlack) continue;
    add_cone(s, v);
    lower_sum += lo_v;
    ++added;
  }
  return added != 0;  // none: no candidate keeps the bounds feasible
}

namespace {

/// Records a greedy step's fit in result (in bounds, area energy, the log scale's spread
/// outside the rings and its rms) and in last_good; returns the spread.
double record_fit(ConeSelector& s, const SetFit& fit, ConeSelection& result) {
  const ConeModelData& model = s.model;
  const int m = static_cast<int>(s.S.size());
  result.within_bounds = fit.within;
  const Eigen::VectorXd& u = fit.u;
  if (m > 0 && fit.within) {
    result.area_energy = std::expm1(area_energy(*model.topology, model.face_area, u, nullptr));
  }
  const Eigen::VectorXd Pu = model.spread(u);
  const double mean = model.area.dot(u);
  double largest = 0;
  for (int v = 0; v < model.nv; ++v) {
    if (s.ring[v] > s.separation) largest = std::max(largest, std::abs(u[v] - mean));
  }
  result.max_log_scale.push_back(largest);
  result.log_scale_rms = std::sqrt(std::max(0.0, u.dot(Pu)));
  if (result.within_bounds && m > 0) {
    s.last_good = {m, fit.k, result.log_scale_rms};
  }
  return largest;
}

}  // namespace

SetFit grow_cone_set(ConeSelector& selector, ConeSelection& result) {
  ConeSelector& s = selector;
  SetFit fit;
  for (;;) {
    const int m = static_cast<int>(s.S.size());
    Eigen::VectorXd warm;
    if (fit.k.size() > 0 && fit.k.size() < m && fit.within) {
      warm = Eigen::VectorXd::Zero(m);  // the new cones at 0
      warm.head(fit.k.size()) = fit.k;
    }
    fit = fit_cone_set(s, &warm, true);
    const double largest = record_fit(s, fit, result);
    const bool done =
        s.wanted >= 0
            ? m >= s.wanted
            : (largest <= s.options.max_log_scale && result.within_bounds) || m >= s.max_cones;
    if (done || !add_cones(s, fit)) break;
  }
  return fit;
}

namespace {

/// Removes row and column i of the square X.
void erase_row_and_column(Eigen::MatrixXd& X, int i) {
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
}

/// What an exchange restores when it is not kept.
struct ConeSetBackup {
  std::vector<int> S;
  Eigen::MatrixXd M, green, hessian;
  Eigen::VectorXd r;
  std::vector<int> ring;
  int removed = -1;
  bool had_columns = false;
  Eigen::VectorXd removed_column;
};

/// Takes cone i out of the set (its rows of M, green, r, the Hessian and its column); returns
/// what restore_cone_set puts back.
ConeSetBackup take_out_cone(ConeSelector& s, int i) {
  ConeSetBackup before;
  before.S = s.S;
  before.M = s.M;
  before.green = s.green;
  before.r = s.r;
  before.ring = s.ring;
  before.removed = s.S[i];
  before.had_columns = s.columns.size() == s.S.size();
  if (before.had_columns) before.removed_column = std::move(s.columns[i]);
  erase_row_and_column(s.M, i);
  erase_row_and_column(s.green, i);
  Eigen::VectorXd r_less(s.r.size() - 1);
  for (int a = 0, ya = 0; a < s.r.size(); ++a) {
    if (a != i) r_less[ya++] = s.r[a];
  }
  s.r = std::move(r_less);
  s.S.erase(s.S.begin() + i);
  if (before.had_columns) s.columns.erase(s.columns.begin() + i);
  s.is_cone[before.removed] = 0;
  reset_rings(s);
  before.hessian = s.hessian;
  if (s.hessian.rows() == static_cast<int>(before.S.size())) {
    erase_row_and_column(s.hessian, i);  // a principal submatrix: still positive definite
  } else {
    s.hessian.resize(0, 0);
  }
  return before;
}

/// Puts cone i back where take_out_cone found it (a candidate added since at the end dropped).
void restore_cone_set(ConeSelector& s, ConeSetBackup&& before, int i) {
  if (before.had_columns) {
    if (s.columns.size() > before.S.size() - 1) s.columns.pop_back();
    s.columns.insert(s.columns.begin() + i, std::move(before.removed_column));
  } else {
    s.columns.clear();
  }
  s.S = before.S;
  s.M = before.M;
  s.green = before.green;
  s.r = before.r;
  s.ring = before.ring;
  s.hessian = before.hessian;
  s.is_cone[before.removed] = 1;
}

/// Cone i taken out and the best candidate for the others put in; kept (fit becomes the new
/// set's, the new cone at the end of S) when the objective falls. Returns whether it was kept.
bool exchange_cone(ConeSelector& s, SetFit& fit, int i) {
  ConeSetBackup before = take_out_cone(s, i);
  // Start: cone i's curvature shared by the others (the sum is kept).
  Eigen::VectorXd start(s.S.size());
  for (int a = 0, ya = 0; a < fit.k.size(); ++a) {
    if (a != i) start[ya++] = fit.k[a] + fit.k[i] / static_cast<double>(s.S.size());
  }
  const SetFit without = fit_cone_set(s, &start, true);
  const int v = without.within ? best_candidate(s, without) : -1;
  if (v >= 0 && v != before.removed) {
    add_cone(s, v);
    Eigen::VectorXd extended = Eigen::VectorXd::Zero(static_cast<int>(s.S.size()));
    extended.head(without.k.size()) = without.k;
    const SetFit with = fit_cone_set(s, &extended, false);
    if (with.within && with.value < fit.value - kExchangeGain * (1 + std::abs(fit.value))) {
      fit = with;
      return true;
    }
    s.is_cone[v] = 0;
  }
  restore_cone_set(s, std::move(before), i);
  return false;
}

}  // namespace

bool exchange_cones(ConeSelector& selector, SetFit& fit) {
  const int chosen = static_cast<int>(selector.S.size());
  const int passes = chosen <= kExchangeTwice ? 2 : 1;
  bool any = false;
  for (int pass = 0; pass < passes; ++pass) {
    bool improved = false;
    for (int i = 0; i < static_cast<int>(selector.S.size()); ++i) {
      if (exchange_cone(selector, fit, i)) improved = true;
    }
    any = any || improved;
    if (!improved) break;
  }
  return any;
}

Eigen::VectorXd quantize_in_model(const ConeSelector& selector, const std::vector<int>& cones,
                                  const Eigen::VectorXd& k_real) {
  const ConeSelector& s = selector;
  const ConeModelData& model = s.model;
  const int m = static_cast<int>(cones.size());
  const double quarter = std::numbers::pi / 2;
  std::vector<Cone> real(m);
  double sum = 0;
  for (int i = 0; i < m; ++i) {
    real[i] = {i, k_real[i]};
    sum += k_real[i];
  }
  const double units_total = std::round((model.closed ? s.total : sum) / quarter) * quarter;
  Eigen::VectorXd kq = Eigen::VectorXd::Zero(m);
  for (const Cone& c : quantize_cones(real, units_total)) kq[c.vertex] = c.curvature;
  auto allowed = [&](int i, double value) {
    return value <= s.options.max_curvature + kQuarterTurnSlack &&
           value >= cone_lower_bound(model, s.options, cones[i]) - kQuarterTurnSlack;
  };
  const ConeObjective objective{model.cholesky,  model.rhs0, s.u0,      *model.topology,
                                model.face_area, cones,      s.columns, s.smooth};
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
    for (std::size_t a = 0; a < std::min<std::size_t>(moves.size(), kMovesTried) && !improved;
         ++a) {
      const auto [i, j] = moves[a].second;
      Eigen::VectorXd trial = kq;
      trial[i] += quarter;
      trial[j] -= quarter;
      const Eigen::VectorXd u_trial = objective.solve_u(trial);
      const double v = objective.value(u_trial, trial);
      if (v < value - kQuantizeGain * (1 + std::abs(value))) {
        kq = trial;
        u = u_trial;
        value = v;
        improved = true;
      }
    }
    if (!improved) break;
  }
  return kq;
}

}  // namespace cone_steps

using cone_steps::ConeSelector;
using cone_steps::SetFit;

ConeSelection select_cones(const Mesh& mesh, const ConeSelectionOptions& options) {
  check_cone_options(options);
  const FlowProblem problem = make_flow_problem(mesh, options.structure);
  return select_cones(build_cone_model(problem), options);
}

ConeSelection select_cones(const ConeModel& handle, const ConeSelectionOptions& options) {
  check_cone_options(options);
  const ConeModelData& model = handle.data();
  const Topology& t = *model.topology;
  ConeSelector selector = cone_steps::make_cone_selector(model, options);
  std::vector<int>& S = selector.S;
  if (model.closed && model.chi != 0) add_cone(selector, seed_cone(selector));

  ConeSelection result;
  SetFit fit = grow_cone_set(selector, result);
  Eigen::VectorXd k = fit.k;
  // Exchange: the greedy order is not the best placement of its cones (the first ones were
  // chosen when the others were missing).
  const int chosen = static_cast<int>(S.size());
  const int wanted = selector.wanted;
  if (result.within_bounds && chosen > 0 && chosen <= kExchangeCones &&
      (wanted < 0 || chosen == wanted) && fit.value < INFINITY) {
    exchange_cones(selector, fit);
    k = fit.k;
    result.area_energy = std::expm1(area_energy(t, model.face_area, fit.u, nullptr));
    result.log_scale_rms = std::sqrt(std::max(0.0, fit.u.dot(model.spread(fit.u))));
  }
  const cone_steps::LastGood& last_good = selector.last_good;
  if (!result.within_bounds && wanted < 0 && last_good.m > 0) {
    S.resize(static_cast<std::size_t>(last_good.m));
    if (selector.columns.size() > S.size()) selector.columns.resize(S.size());
    k = last_good.k;
    result.log_scale_rms = last_good.rms;
    result.within_bounds = true;
  }
  if (options.quantize && result.within_bounds && !S.empty()) {
    k = quantize_in_model(selector, S, k);
    const ConeObjective objective{model.cholesky,  model.rhs0, selector.u0,      t,
                                  model.face_area, S,          selector.columns, selector.smooth};
    const Eigen::VectorXd u = objective.solve_u(k);
    result.area_energy = std::expm1(area_energy(t, model.face_area, u, nullptr));
    result.log_scale_rms = std::sqrt(std::max(0.0, u.dot(model.spread(u))));
  }
  result.vertices = std::move(S);
  result.linear_curvature.assign(k.data(), k.data() + k.size());
  return result;
}

namespace {

double log_scale_spread(const Topology& t, const Eigen::VectorXd& area, const Eigen::VectorXd& u,
                        const std::vector<int>& cones) {
  const int nv = t.num_vertices;
  std::vector<std::vector<int>> neighbours = vertex_neighbours(t);
  std::vector<int> ring(nv, kFarFromCones);
  for (int c : cones) grow_rings_within(neighbours, c, kSeparationRings, area, kRingArea, ring);
  double mean = 0, weight = 0;
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_component[v] < 0) continue;
    mean += area[v] * u[v];
    weight += area[v];
  }
  mean /= std::max(weight, kSmallestScale);
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
