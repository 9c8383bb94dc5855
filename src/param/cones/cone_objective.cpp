#include "param/cones/detail/cone_objective.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "numerics/detail/parallel.hpp"
#include "ricci/numerics/bounded_least_squares.hpp"

namespace ricci::cone_steps {
namespace {

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

}  // namespace

VertexFaces vertex_faces(const Topology& t) {
  VertexFaces incidence;
  incidence.offset.assign(static_cast<std::size_t>(t.num_vertices) + 1, 0);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int c = 0; c < 3; ++c) ++incidence.offset[t.triangles(f, c) + 1];
  }
  for (int v = 0; v < t.num_vertices; ++v) incidence.offset[v + 1] += incidence.offset[v];
  incidence.faces.resize(static_cast<std::size_t>(incidence.offset[t.num_vertices]));
  std::vector<int> fill(incidence.offset.begin(), incidence.offset.end() - 1);
  for (int f = 0; f < t.num_faces; ++f) {
    for (int c = 0; c < 3; ++c) incidence.faces[fill[t.triangles(f, c)]++] = f;
  }
  return incidence;
}

namespace {

/// area_energy's chunks of faces start at multiples of this: Eigen's vectorised exp then takes
/// the same elements in packets (and the same last ones one by one) as over the whole array,
/// which keeps the bits (packets of up to 8 doubles).
constexpr std::int64_t kFaceBlock = 8;

/// body(begin, end) over consecutive ranges of [0, n) that start at multiples of kFaceBlock, in
/// parallel when in_parallel (one range otherwise).
template <class Body>
void for_face_blocks(int n, bool in_parallel, Body&& body) {
  if (!in_parallel) {
    body(0, n);
    return;
  }
  const std::int64_t blocks = (n + kFaceBlock - 1) / kFaceBlock;
  parallel::for_chunks(
      blocks,
      [&](std::int64_t b, std::int64_t e, int) {
        body(static_cast<int>(b * kFaceBlock),
             static_cast<int>(std::min<std::int64_t>(e * kFaceBlock, n)));
      },
      parallel::kDefaultMinChunk / kFaceBlock);
}

}  // namespace

Eigen::VectorXd face_means(const Topology& t, const Eigen::VectorXd& x, bool in_parallel) {
  Eigen::VectorXd means(t.num_faces);
  for_face_blocks(t.num_faces, in_parallel, [&](int begin, int end) {
    for (int f = begin; f < end; ++f) {
      means[f] = (x[t.triangles(f, 0)] + x[t.triangles(f, 1)] + x[t.triangles(f, 2)]) / 3;
    }
  });
  return means;
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
                   Eigen::VectorXd* gradient, const VertexFaces* incidence) {
  const int nf = t.num_faces;
  const bool in_parallel = incidence != nullptr;
  Eigen::ArrayXd uf = face_means(t, u, in_parallel).array();
  const double top = uf.maxCoeff();  // e^{4 (u - top)} cannot overflow
  Eigen::ArrayXd e2(nf), e4(nf);
  for_face_blocks(nf, in_parallel, [&](int begin, int end) {
    const int n = end - begin;
    const Eigen::ArrayXd scale = (2 * (uf.segment(begin, n) - top)).exp();
    e2.segment(begin, n) = scale * face_area.array().segment(begin, n);
    e4.segment(begin, n) = scale * e2.segment(begin, n);
  });
  const double s2 = e2.sum(), s4 = e4.sum();
  if (gradient) {
    Eigen::ArrayXd& per_face = uf;  // (uf is done with)
    for_face_blocks(nf, in_parallel, [&](int begin, int end) {
      const int n = end - begin;
      per_face.segment(begin, n) =
          (4.0 / 3) * (e4.segment(begin, n) / s4 - e2.segment(begin, n) / s2);
    });
    *gradient = Eigen::VectorXd::Zero(u.size());
    if (in_parallel) {
      // Each vertex sums its faces in increasing order, as the sequential pass over the faces.
      parallel::for_each(u.size(), [&](std::int64_t v) {
        double sum = 0;
        for (int i = incidence->offset[v]; i < incidence->offset[v + 1]; ++i) {
          sum += per_face[incidence->faces[i]];
        }
        (*gradient)[v] = sum;
      });
    } else {
      for (int f = 0; f < nf; ++f) {
        for (int c = 0; c < 3; ++c) (*gradient)[t.triangles(f, c)] += per_face[f];
      }
    }
  }
  return std::log(s4) - 2 * std::log(s2);
}

namespace {

/// evaluate's passes work in blocks of this many faces or vertices (a multiple of kFaceBlock),
/// each block's sums kept apart and added in block order afterwards: the same sums whatever the
/// thread count, with a block's values in cache while every column passes over it.
constexpr int kEvaluationBlock = 2048;

/// body(block, begin, count) for the blocks of [0, n), in parallel when in_parallel.
template <class Body>
void for_blocks(int n, bool in_parallel, Body&& body) {
  const int blocks = (n + kEvaluationBlock - 1) / kEvaluationBlock;
  auto run = [&](std::int64_t b, std::int64_t e, int) {
    for (std::int64_t block = b; block < e; ++block) {
      const int begin = static_cast<int>(block) * kEvaluationBlock;
      body(static_cast<int>(block), begin, std::min(n, begin + kEvaluationBlock) - begin);
    }
  };
  if (in_parallel) {
    parallel::for_chunks(blocks, run, parallel::kDefaultMinChunk / kEvaluationBlock);
  } else {
    run(0, blocks, 0);
  }
}

int block_count(int n) {
  return (n + kEvaluationBlock - 1) / kEvaluationBlock;
}

}  // namespace

ObjectiveValue ConeObjective::evaluate(const Eigen::VectorXd& k) const {
  const int m = static_cast<int>(S.size());
  const bool in_parallel = incidence != nullptr;
  ObjectiveValue out;
  if (!has_columns()) {
    const Eigen::VectorXd u = solve_u(k);
    Eigen::VectorXd dfdu;
    out.value = value(u, k, &dfdu);
    out.gradient = gradient(u, dfdu);
    return out;
  }
  // u at the cones (green) and D = u . rhs0 + u_S . k (the columns' g . rhs0), without u.
  Eigen::VectorXd u_cones(m);
  for (int i = 0; i < m; ++i) u_cones[i] = u0[S[i]];
  if (green != nullptr && green->rows() == m) u_cones += *green * k;
  double dirichlet = u0_rhs0;
  for (int i = 0; i < m; ++i) dirichlet += k[i] * columns[i]->rhs0_dot;
  Eigen::VectorXd area_gradient(m);
  double area = 0;
  if (on_faces()) {
    // Pass 1: u_f and each block's largest (e^{4 (u_f - top)} cannot overflow).
    const int nf = t.num_faces, blocks = block_count(nf);
    Eigen::ArrayXd uf(nf);
    std::vector<double> block_top(static_cast<std::size_t>(blocks));
    for_blocks(nf, in_parallel, [&](int block, int begin, int n) {
      auto segment = uf.segment(begin, n);
      segment = u0_faces->array().segment(begin, n);
      for (int i = 0; i < m; ++i) segment += k[i] * columns[i]->faces.array().segment(begin, n);
      block_top[block] = segment.maxCoeff();
    });
    const double top = *std::max_element(block_top.begin(), block_top.end());
    // Pass 2: e2 = a e^{2 (u_f - top)}, e4 = a e^{4 (u_f - top)}, their sums, and each column
    // against e4 / s4 - e2 / s2 (dF/dk_i = 4 sum_f g_i,f (e4_f / s4 - e2_f / s2)) from its sums
    // against both.
    Eigen::MatrixXd sums(2 * m + 2, blocks);
    for_blocks(nf, in_parallel, [&](int block, int begin, int n) {
      const Eigen::ArrayXd scale = (2 * (uf.segment(begin, n) - top)).exp();
      const Eigen::ArrayXd e2 = scale * face_area.array().segment(begin, n);
      const Eigen::ArrayXd e4 = scale * e2;
      sums(0, block) = e2.sum();
      sums(1, block) = e4.sum();
      for (int i = 0; i < m; ++i) {
        const auto column = columns[i]->faces.segment(begin, n);
        sums(2 + i, block) = column.dot(e2.matrix());
        sums(2 + m + i, block) = column.dot(e4.matrix());
      }
    });
    Eigen::VectorXd total = Eigen::VectorXd::Zero(2 * m + 2);
    for (int block = 0; block < blocks; ++block) total += sums.col(block);
    const double s2 = total[0], s4 = total[1];
    area = std::log(s4) - 2 * std::log(s2);
    for (int i = 0; i < m; ++i) area_gradient[i] = 4 * (total[2 + m + i] / s4 - total[2 + i] / s2);
  } else {
    // u = u0 + sum_i k_i g_i a block of vertices at a time, area_energy, then each column
    // against dF/du the same way: each column read twice.
    const int nv = static_cast<int>(u0.size()), blocks = block_count(nv);
    Eigen::VectorXd u(nv);
    for_blocks(nv, in_parallel, [&](int, int begin, int n) {
      auto segment = u.segment(begin, n);
      segment = u0.segment(begin, n);
      for (int i = 0; i < m; ++i) segment += k[i] * columns[i]->g.segment(begin, n);
    });
    if (green == nullptr || green->rows() != m) {
      for (int i = 0; i < m; ++i) u_cones[i] = u[S[i]];
    }
    Eigen::VectorXd dfdu;
    area = area_energy(t, face_area, u, &dfdu, incidence);
    Eigen::MatrixXd sums(m, blocks);
    for_blocks(nv, in_parallel, [&](int block, int begin, int n) {
      for (int i = 0; i < m; ++i) {
        sums(i, block) = columns[i]->g.segment(begin, n).dot(dfdu.segment(begin, n));
      }
    });
    area_gradient = sums.rowwise().sum();
  }
  for (int i = 0; i < m; ++i) dirichlet += u_cones[i] * k[i];
  out.value = area + smooth * dirichlet;
  out.gradient = area_gradient + 2 * smooth * u_cones;
  return out;
}

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
  // u itself (and dF/du at every vertex) only at the minimiser.
  auto finish = [&] {
    Eigen::VectorXd u = objective.solve_u(k);
    if (gradient_all) {
      Eigen::VectorXd dfdu;
      area_energy(objective.t, objective.face_area, u, &dfdu, objective.incidence);
      *gradient_all = objective.gradient_everywhere(u, dfdu);
    }
    return u;
  };
  if (m == 0) {
    Eigen::VectorXd u = finish();
    value = objective.value(u, k);
    return u;
  }
  ObjectiveValue at = objective.evaluate(k);
  value = at.value;
  Eigen::VectorXd g = std::move(at.gradient);
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
  // Each step's programme starts from the bounds active at the step before.
  std::vector<int> active;
  for (int iteration = 0; iteration < kObjectiveIterations; ++iteration) {
    const Eigen::VectorXd linear = g - B * k;
    BoundedLeastSquaresOptions sum;
    sum.sum_constraint = closed;
    sum.total = total;
    sum.start_state = std::move(active);
    BoundedLeastSquaresResult step_target = bounded_least_squares(B, linear, lo, hi, sum);
    if (!step_target.feasible) break;
    active = std::move(step_target.state);
    const Eigen::VectorXd direction = step_target.x - k;
    if (direction.cwiseAbs().maxCoeff() < kSmallestStep) break;
    const double slope = g.dot(direction);
    if (!(slope < 0)) break;
    double step = 1;
    Eigen::VectorXd k_new;
    ObjectiveValue trial;
    trial.value = INFINITY;
    for (int tries = 0; tries < kBacktracks; ++tries, step *= kBacktrackFactor) {
      k_new = k + step * direction;
      trial = objective.evaluate(k_new);
      if (trial.value <= value + kArmijo * step * slope) break;
    }
    const double value_new = trial.value;
    if (!(value_new < value)) break;
    const Eigen::VectorXd& g_new = trial.gradient;
    const Eigen::VectorXd s = k_new - k, y = g_new - g;
    const double sy = s.dot(y);
    if (sy > kCurvatureCondition * s.norm() * y.norm()) {
      const Eigen::VectorXd Bs = B * s;
      B += y * y.transpose() / sy - Bs * Bs.transpose() / s.dot(Bs);
    }
    const double decrease = value - value_new;
    k = k_new;
    g = g_new;
    value = value_new;
    if (decrease <= objective.relative_decrease * (1 + std::abs(value))) break;
  }
  return finish();
}

}  // namespace ricci::cone_steps
