#include "ricci/param/cones/refine_curvatures.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "numerics/detail/conjugate_gradients.hpp"
#include "param/cones/detail/cone_objective.hpp"
#include "param/cones/detail/linear_flow.hpp"
#include "ricci/errors.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace ricci {
namespace {

/// The penalty that pins the gauge (or the held boundary) in the Hessian's solve, relative to
/// its largest diagonal entry: as the cone model's.
constexpr double kPinPenalty = 1e10;
/// The BFGS update is skipped unless s.y exceeds this times |s| |y| (keeps the estimate positive
/// definite, with room for rounding).
constexpr double kCurvatureCondition = 1e-12;
/// A cone within this (radians) of its lowest curvature counts as at it.
constexpr double kAtLowest = 1e-9;

/// Conjugate-gradient iterations the gradient's solve at a new flat metric may take,
/// preconditioned by the factorisation of H at an earlier one, before H there is factorised:
/// between the small steps of the refinement they take 3-10 (fertility, 8 cones), and a
/// factorisation with its analysis costs about 30 of them.
constexpr int kGradientIterations = 30;
/// Their relative residual: far below what moves a quasi-Newton step on curvatures of order 1.
constexpr double kGradientTolerance = 1e-10;

/// One flow to the flat metric with the cones, and its area distortion.
struct FlatPoint {
  bool converged = false;
  FlowResult flow;
  double energy = INFINITY;  ///< log(1 + E)
  Eigen::VectorXd dfdu;      ///< d log(1 + E) / du
};

/// The flows of the refinement and the solves with the flow's Hessian H at their flat metrics.
/// One factorisation serves several points: H changes little between the steps' flat metrics,
/// so the factorisation at an earlier one preconditions conjugate gradients at the next (and
/// the next flow's first Newton steps), and H is factorised afresh only when they stall.
class Refiner {
 public:
  Refiner(const FlowProblem& problem, const FlowOptions& flow)
      : problem_(problem),
        flow_(flow),
        face_area_(cone_steps::face_areas(*problem.mesh, problem.topology)) {
    // The gauge of a closed surface: the vertex the flow holds (its first vertex in the mesh),
    // so that the factorisation preconditions the flow's own system. (The gradient does not
    // depend on it: dE/du sums to 0, and the curvatures' gradient is projected on sum 0.)
    const Topology& t = problem.topology;
    while (gauge_ < t.num_vertices && t.vertex_component[gauge_] < 0) ++gauge_;
  }

  FlatPoint flatten(const std::vector<Cone>& cones, Eigen::VectorXd start) {
    FlatPoint p;
    FlowOptions o = flow_;
    o.start_u = std::move(start);
    o.progress = {};
    if (factored_) {
      o.start_preconditioner = [this](const Eigen::VectorXd& r) { return predict(r); };
    }
    ++flows_;
    try {
      p.flow = ricci_flow(
          problem_.topology, problem_.structure.structure,
          flat_target(problem_.topology, cones, BoundaryMode::Free, problem_.input_lengths), o);
    } catch (const InvalidInput&) {  // a curvature the flow refuses
      return p;
    } catch (const SolverError&) {
      return p;
    }
    p.converged = p.flow.converged;
    if (p.converged) {
      p.energy = cone_steps::area_energy(problem_.topology, face_area_, p.flow.u, &p.dfdu);
    }
    return p;
  }

  /// Assembles H at the flat metric p (dK-bar/du there, on its intrinsic triangulation), the
  /// gauge (closed) or the boundary held at 0 by a penalty: solve_here() then gives H^-1 b.
  void move_to(const FlatPoint& p) {
    const Topology& t = p.flow.intrinsic.topology();
    CornerAngles angles;
    corner_angles(t, p.flow.lengths, angles);
    Eigen::VectorXd hw, ew;
    halfedge_weights(t, p.flow.intrinsic.structure(), p.flow.u, p.flow.lengths, angles, hw);
    edge_weights(t, hw, ew);
    H_ = curvature_hessian(t, ew);
    const double penalty = kPinPenalty * std::max(1.0, H_.diagonal().cwiseAbs().maxCoeff());
    const bool closed = t.num_boundary_loops() == 0;
    pinned_.assign(t.num_vertices, 0);
    for (int v = 0; v < t.num_vertices; ++v) {
      if ((closed && v == gauge_) || (!closed && t.is_boundary_vertex[v])) {
        H_.coeffRef(v, v) += penalty;
        pinned_[v] = 1;
      }
    }
  }

  /// H^-1 b at the point of the last move_to: conjugate gradients preconditioned by the last
  /// factorisation, or (when they stall, or there is none) a factorisation of H here.
  Eigen::VectorXd solve_here(Eigen::VectorXd b) {
    hold(b);
    if (factored_) {
      Eigen::VectorXd x;
      const auto apply = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd { return H_ * d; };
      const auto precondition = [&](const Eigen::VectorXd& r) { return cholesky_.solve(r); };
      if (numerics_detail::conjugate_gradients(apply, precondition, b, kGradientTolerance,
                                               kGradientIterations, x)
              .converged) {
        return x;
      }
    }
    factorise_here();
    return cholesky_.solve(b);
  }

  /// The last factorisation's solve (H^-1 b at the point where it was made, or near it): where
  /// the next flat metric lies to first order, and the next flow's preconditioner.
  Eigen::VectorXd predict(Eigen::VectorXd b) const {
    hold(b);
    return cholesky_.solve(b);
  }

  int flows() const { return flows_; }

 private:
  void hold(Eigen::VectorXd& b) const {
    for (std::size_t v = 0; v < pinned_.size(); ++v) {
      if (pinned_[v]) b[static_cast<Eigen::Index>(v)] = 0;
    }
  }

  /// Factorises H; its pattern is analysed when flips since the last analysis changed it.
  void factorise_here() {
    const auto* outer = H_.outerIndexPtr();
    const auto* inner = H_.innerIndexPtr();
    const bool same_pattern =
        cholesky_.analyzed() &&
        std::equal(outer, outer + H_.outerSize() + 1, analysed_outer_.begin(),
                   analysed_outer_.end()) &&
        std::equal(inner, inner + H_.nonZeros(), analysed_inner_.begin(), analysed_inner_.end());
    if (!same_pattern) {
      cholesky_.analyze(H_);
      analysed_outer_.assign(outer, outer + H_.outerSize() + 1);
      analysed_inner_.assign(inner, inner + H_.nonZeros());
    }
    factored_ = false;
    cholesky_.factorize(H_);
    factored_ = true;
  }

  const FlowProblem& problem_;
  const FlowOptions& flow_;
  Eigen::VectorXd face_area_;
  Eigen::SparseMatrix<double> H_;
  SparseCholesky cholesky_;
  std::vector<int> analysed_outer_, analysed_inner_;
  std::vector<char> pinned_;
  bool factored_ = false;  ///< cholesky_ holds a factorisation (of H at this or an earlier point)
  int gauge_ = 0;
  int flows_ = 0;
};

}  // namespace

CurvatureRefinement refine_cone_curvatures(const FlowProblem& problem,
                                           const std::vector<Cone>& cones, const FlowOptions& flow,
                                           const CurvatureRefinementOptions& options) {
  const Topology& t = problem.topology;
  const bool closed = t.num_boundary_loops() == 0;
  const int m = static_cast<int>(cones.size());
  Refiner refiner(problem, flow);
  CurvatureRefinement result;
  result.cones = cones;
  FlatPoint here = refiner.flatten(cones, flow.start_u);
  result.converged = here.converged;
  if (!here.converged || m == 0) {
    result.flows = refiner.flows();
    if (here.converged) result.u = std::move(here.flow.u);
    return result;
  }
  result.area_energy_before = std::expm1(here.energy);
  std::vector<double> lowest(static_cast<std::size_t>(m), -INFINITY);
  for (int i = 0; i < m && static_cast<std::size_t>(i) < options.lower_bounds.size(); ++i) {
    lowest[i] = std::min(options.lower_bounds[i], cones[i].curvature);
  }
  // Quasi-Newton (BFGS) on the curvatures, within the subspace that keeps their sum on a closed
  // surface; the first step moves the most sensitive cone by first_step.
  Eigen::MatrixXd inverse;  // of the Hessian of log(1 + E) in the curvatures, estimated
  Eigen::VectorXd g_before, s_before;
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(m, m);
  auto project = [&](Eigen::VectorXd x) {
    if (closed) x.array() -= x.mean();
    return x;
  };
  for (int iteration = 0; iteration < options.max_steps; ++iteration) {
    refiner.move_to(here);
    const Eigen::VectorXd z = refiner.solve_here(here.dfdu);
    Eigen::VectorXd g(m);
    for (int i = 0; i < m; ++i) g[i] = z[result.cones[i].vertex];
    g = project(g);
    const double largest = g.cwiseAbs().maxCoeff();
    if (!(largest > 0)) break;
    const double sy = iteration > 0 ? s_before.dot(g - g_before) : 0.0;
    if (iteration > 0 && sy > kCurvatureCondition * s_before.norm() * (g - g_before).norm()) {
      const Eigen::VectorXd y = g - g_before;
      inverse = (identity - s_before * y.transpose() / sy) * inverse *
                    (identity - y * s_before.transpose() / sy) +
                s_before * s_before.transpose() / sy;
    } else if (iteration == 0) {
      inverse = (options.first_step / largest) * identity;
    }
    Eigen::VectorXd direction = project(-(inverse * g));
    if (!(g.dot(direction) < 0)) {  // not a descent direction: start the estimate afresh
      inverse = (options.first_step / largest) * identity;
      direction = project(-(inverse * g));
    }
    // Cones at their lowest curvature that the step would push lower stay there (the others
    // keep the sum).
    std::vector<char> held(static_cast<std::size_t>(m), 0);
    for (int pass = 0; pass < m; ++pass) {
      bool changed = false;
      for (int i = 0; i < m; ++i) {
        if (!held[i] && direction[i] < 0 && result.cones[i].curvature <= lowest[i] + kAtLowest) {
          held[i] = 1;
          changed = true;
        }
      }
      if (!changed) break;
      double sum = 0;
      int free = 0;
      for (int i = 0; i < m; ++i) {
        if (held[i]) {
          direction[i] = 0;
        } else {
          sum += direction[i];
          ++free;
        }
      }
      if (closed && free > 0) {
        for (int i = 0; i < m; ++i) {
          if (!held[i]) direction[i] -= sum / free;
        }
      }
    }
    if (!(g.dot(direction) < 0)) break;  // no descent left within the bounds
    // No further than the nearest bound, nor than largest_step.
    double reach = options.largest_step / std::max(direction.cwiseAbs().maxCoeff(), 1e-300);
    for (int i = 0; i < m; ++i) {
      if (direction[i] < 0) {
        reach = std::min(reach, (result.cones[i].curvature - lowest[i]) / -direction[i]);
      }
    }
    direction *= std::min(1.0, reach);
    bool kept = false;
    for (double alpha = 1; alpha * direction.cwiseAbs().maxCoeff() >= options.smallest_step;
         alpha *= 0.5) {
      std::vector<Cone> trial = result.cones;
      Eigen::VectorXd change = Eigen::VectorXd::Zero(t.num_vertices);
      bool allowed = true;
      for (int i = 0; i < m; ++i) {
        trial[i].curvature += alpha * direction[i];
        change[trial[i].vertex] = alpha * direction[i];
      }
      if (closed) {
        // Exactly 2 pi chi (the steps sum to zero up to rounding).
        double others = 0;
        for (int i = 0; i + 1 < m; ++i) others += trial[i].curvature;
        trial[m - 1].curvature = 2 * std::numbers::pi * t.euler_characteristic() - others;
      }
      for (int i = 0; i < m; ++i) {
        allowed = allowed && trial[i].curvature <= options.max_curvature &&
                  trial[i].curvature >= lowest[i] - kAtLowest;
      }
      if (!allowed) continue;
      // Started where the Hessian here predicts the new flat metric.
      FlatPoint next = refiner.flatten(trial, here.flow.u + refiner.predict(change));
      if (next.converged && next.energy < here.energy) {
        const double gain = here.energy - next.energy;
        s_before = alpha * direction;
        g_before = g;
        result.cones = std::move(trial);
        here = std::move(next);
        ++result.steps;
        kept = gain > options.relative_gain * (1 + here.energy);
        break;
      }
    }
    if (!kept) break;
  }
  result.area_energy = std::expm1(here.energy);
  result.u = std::move(here.flow.u);
  result.flows = refiner.flows();
  return result;
}

}  // namespace ricci
