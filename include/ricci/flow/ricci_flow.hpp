#pragma once
/// \file
/// The discrete Ricci flow solvers (THEORY.md section 5) on one connected component: Newton's
/// method on the convex Ricci energy, and the tutorial's gradient flow. Both find log radii u with
/// K(u) = K-bar at every vertex with a target, u fixed where the target says so.

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/errors.hpp"
#include "ricci/flow/target.hpp"
#include "ricci/intrinsic/intrinsic_triangulation.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/scheme.hpp"

namespace ricci {

/// Which solver runs the flow.
enum class FlowSolver {
  Newton,    ///< Newton's method with a backtracking line search (quadratic convergence)
  Gradient,  ///< the tutorial's explicit flow u += dt (K-bar - K) (exponential convergence)
};

template <>
struct EnumNames<FlowSolver> {
  static constexpr const char* noun = "solver";
  static constexpr std::array<EnumName<FlowSolver>, 2> names{{
      {FlowSolver::Newton, "newton"},
      {FlowSolver::Gradient, "gradient"},
  }};
};

/// "newton" or "gradient". \throw InvalidInput on any other string
FlowSolver parse_flow_solver(const std::string& name);
const char* flow_solver_name(FlowSolver solver);

/// Whether the flow keeps the triangulation intrinsically Delaunay with edge flips
/// (ricci/intrinsic/delaunay_flips.hpp).
enum class EdgeFlips {
  Auto,      ///< Delaunay for vertex scaling (the only scheme whose class flips preserve), else Off
  Off,       ///< the input's triangulation throughout
  Delaunay,  ///< Ptolemy flips to the intrinsic Delaunay triangulation at every accepted step
};

/// "none" is an old spelling of "off", parsed but not listed.
template <>
struct EnumNames<EdgeFlips> {
  static constexpr const char* noun = "flips";
  static constexpr std::array<EnumName<EdgeFlips>, 4> names{{
      {EdgeFlips::Auto, "auto"},
      {EdgeFlips::Off, "off"},
      {EdgeFlips::Off, "none", NameRole::Hidden},
      {EdgeFlips::Delaunay, "delaunay"},
  }};
};

/// "auto", "off" or "delaunay". \throw InvalidInput on any other string
EdgeFlips parse_edge_flips(const std::string& name);
const char* edge_flips_name(EdgeFlips flips);

/// One iteration of a flow, as reported in the history and to the progress callback.
struct IterationRecord {
  int iteration = 0;          ///< 0 is the initial state
  double max_error = 0;       ///< max |K-bar - K| over vertices with a target after the step
  double rms_error = 0;       ///< root mean square of the same
  double step_length = 0;     ///< alpha of u += alpha delta (gradient flow: alpha dt)
  int backtracks = 0;         ///< step halvings of the line search
  int triangle_failures = 0;  ///< trial steps rejected: a triangle inequality broke or a
                              ///< length became non-positive or overflowed
  int flips = 0;              ///< edges flipped by the accepted step (EdgeFlips::Delaunay)
  bool chord = false;         ///< a chord step: the previous factorisation, as it was
  double seconds = 0;         ///< wall time since the solve started
};

/// Called after every iteration; return false to stop the flow (status Cancelled).
using FlowProgress = std::function<bool(const IterationRecord&)>;

/// Options of ricci_flow.
struct FlowOptions {
  FlowSolver solver = FlowSolver::Newton;  ///< Newton or gradient flow
  double tolerance = 1e-10;                ///< stop when max |K-bar - K| <= tolerance (radians)
  int max_iterations = 0;                  ///< 0: 200 for Newton, 1'000'000 for the gradient flow
  /// Newton: stop (FlowStatus::MaxIterations, the message saying it stalled) when max |K-bar -
  /// K| is not below half of what it was this many iterations before, outside the floor of the
  /// metric: damped steps that no longer converge (a high-genus surface with one hole ran 200
  /// iterations of steps near 1e-3 at an error near 2.9, then as many again glued to its
  /// mirror). 0: never. parameterize sets 30 where it has the charts to fall back on.
  int stall_iterations = 0;
  /// Gradient flow time step dt (radians^-1... a dimensionless factor on the curvature error);
  /// 0 picks 1 / (largest diagonal entry of the Hessian), the stable explicit step.
  double gradient_step = 0;
  double armijo = 1e-4;     ///< sufficient decrease of |K-bar - K|^2 in the line search
  int max_backtracks = 50;  ///< line search halvings before the flow gives up
  bool use_cholmod = true;  ///< CHOLMOD when available, Eigen's solver otherwise
  /// Newton: solve with the previous factorisation as a preconditioner (conjugate gradients)
  /// and refactorise only when that needs more than this many iterations; 0 refactorises at
  /// every Newton step.
  int reuse_factorization_cg_iterations = 25;
  /// Newton: once max |K-bar - K| is at most this, and the last step (which factorised) cut it
  /// at least a thousandfold, the next steps reuse that factorisation as it is (chord steps: no
  /// assembly, one solve) while each cuts the error at least tenfold; 0: never.
  double chord_error = 1e-8;
  /// Intrinsic Delaunay flips, in the Euclidean and in the hyperbolic background. With them
  /// vertex scaling reaches every target that satisfies Gauss-Bonnet (and K < 2 pi inside): no
  /// triangle inequality can break. Delaunay with another scheme is an InvalidInput.
  EdgeFlips flips = EdgeFlips::Auto;
  /// Only flips that keep a simplicial complex (no double edge, no loop): the result can be
  /// written as an ordinary mesh, at the price of leaving some edges non-Delaunay (the
  /// parameterization falls back to this when the unrestricted result is a Delta-complex).
  bool simplicial_flips = false;
  /// With flips: first retriangulate the input metric isometrically to its intrinsic Delaunay
  /// triangulation (the class of the input surface, Gu, Luo, Sun and Wu's definition), which
  /// keeps the map closest to the input's own shapes. Off: Ptolemy flips only, from the input's
  /// triangulation (Bobenko, Pinkall and Springborn's class, in which a mesh and its image under
  /// a Moebius transformation of space are equivalent exactly: what matching needs).
  bool isometric_start = true;
  /// Where the flow starts: empty, the structure's initial u; else #V log factors near the
  /// solution (the flow linearised at the initial metric: what the first Newton step would
  /// reach, so that step and its factorisation are saved). Fixed vertices keep their initial u
  /// whatever this says. A start whose rms |K-bar - K| is not below the initial metric's, or
  /// that breaks a triangle (no flips), is dropped for the initial u.
  Eigen::VectorXd start_u;
  /// Newton: the inverse of a matrix close to the Hessian, applied to a #V vector (zero at the
  /// vertices whose u is held; those entries of the result are ignored), e.g. the linearised
  /// flow's that start_u came from (linearised_inverse). It preconditions conjugate gradients
  /// until the flow needs a factorisation of its own (reuse_factorization_cg_iterations), which
  /// then saves the first analysis and factorisation. Used on a flow of the whole mesh only
  /// (vertex indices of its topology); must stay valid through the flow.
  std::function<Eigen::VectorXd(const Eigen::VectorXd&)> start_preconditioner;
  FlowProgress progress;  ///< optional callback after each iteration
};

/// The flow options of the layouts (parameterize, parameterize_hyperbolic, sphere_map): the
/// defaults with Newton run to max |K-bar - K| <= 1e-12. A layout closes around each interior
/// vertex only as well as the metric has converged there: 1e-10 leaves length errors of 2e-9 on
/// meshes of ~5k vertices.
inline FlowOptions layout_flow_options() {
  /// The curvature error (radians) a layout asks of the flow, see above.
  constexpr double layout_tolerance = 1e-12;
  FlowOptions f;
  f.tolerance = layout_tolerance;
  return f;
}

/// Whether a flow with these options flips edges (Auto: exactly for vertex scaling).
/// \throw InvalidInput for EdgeFlips::Delaunay with a scheme other than vertex scaling
bool uses_edge_flips(const ConformalStructure& structure, const FlowOptions& options);

/// Why a flow stopped.
enum class FlowStatus {
  Converged,         ///< max error <= tolerance
  MaxIterations,     ///< iteration limit reached first
  LineSearchFailed,  ///< no step length reduced the error (target not reachable from here)
  SolverFailed,      ///< the Hessian lost positive definiteness in floating point (the metric
                     ///< is degenerating: radii spanning many orders of magnitude)
  Cancelled,         ///< the progress callback asked to stop
};

template <>
struct EnumNames<FlowStatus> {
  static constexpr const char* noun = "flow status";
  static constexpr std::array<EnumName<FlowStatus>, 5> names{{
      {FlowStatus::Converged, "converged"},
      {FlowStatus::MaxIterations, "max-iterations"},
      {FlowStatus::LineSearchFailed, "line-search-failed"},
      {FlowStatus::SolverFailed, "solver-failed"},
      {FlowStatus::Cancelled, "cancelled"},
  }};
};

const char* flow_status_name(FlowStatus status);

/// Wall time spent in each phase, seconds.
struct FlowTimings {
  double setup = 0;          ///< index maps, sparsity pattern
  double assembly = 0;       ///< Hessian weights and matrix values
  double analysis = 0;       ///< symbolic factorisation (once)
  double factorization = 0;  ///< numeric factorisations
  double solve = 0;          ///< triangular solves (and conjugate gradients)
  double line_search = 0;    ///< lengths, angles and curvature of trial steps
  double total = 0;
};

/// What ricci_flow returns.
struct FlowResult {
  bool converged = false;
  FlowStatus status = FlowStatus::MaxIterations;
  std::string message;  ///< why it stopped, in words
  /// Option settings that may let a flow that stopped short converge (e.g. {flips, delaunay}
  /// when triangles break without flips); the message names them as option fields, and each
  /// front end phrases them in its own terms (`--flips delaunay`, `flips="delaunay"`).
  std::vector<OptionFix> fixes;
  Eigen::VectorXd u;                 ///< #V final log radii
  Eigen::VectorXd curvature;         ///< #V final curvature K
  Eigen::VectorXd target_curvature;  ///< #V K-bar (the final K where the vertex is fixed)
  /// #E final edge lengths, edges as in intrinsic.topology() (the input's, or after flips those
  /// of the intrinsic Delaunay triangulation: a flip reuses the index of the edge it replaces).
  Eigen::VectorXd lengths;
  /// The final triangulation: the input topology itself (shared, not copied, referred to as the
  /// flow was given it: the caller keeps it alive) or, after flips, its intrinsic Delaunay
  /// triangulation (the same vertices, face count and Euler characteristic; possibly a
  /// Delta-complex, see ricci/intrinsic/delaunay_flips.hpp), with the structure's eta on it
  /// (intrinsic.eta(): edge_lengths of intrinsic.structure() on intrinsic.topology() gives
  /// `lengths` at u), every accepted flip in order (intrinsic.flipped_edges(), edge indices of
  /// the topology the flow was given; the first intrinsic.isometric_flips() retriangulate the
  /// input metric isometrically into its intrinsic Delaunay triangulation, the others are the
  /// flow's Ptolemy flips), the count of flips and of non-Delaunay edges left unflipped at the
  /// end (intrinsic.blocked_flips(), see DelaunayFlipResult::blocked).
  IntrinsicTriangulation intrinsic;
  int iterations = 0;
  double max_error = 0;  ///< final max |K-bar - K| over vertices with a target
  /// The smallest max error double arithmetic resolves at the final metric (rounding of the
  /// angle sums and of the angles' dependence on u; large next to needles). A flow that cannot
  /// improve on an error below it counts as converged, and its message says so.
  double error_floor = 0;
  std::vector<IterationRecord> history;  ///< iteration 0 (initial) to the last
  FlowTimings timings;
  int analyses = 0, factorizations = 0, cg_iterations = 0;
  int chord_steps = 0;        ///< Newton steps made with the previous factorisation as it was
  std::string linear_solver;  ///< backend of the Cholesky factorisation (Newton)
  /// Of the final curvature: |sum K - 2 pi chi| (Euclidean) or |sum K - area - 2 pi chi|
  /// (hyperbolic) relative to max(1, 2 pi #V).
  double gauss_bonnet_relative_error = 0;
  double total_area = 0;  ///< hyperbolic background: total area of the final metric (else 0)
};

/// A flow in progress, one iteration per step(); ricci_flow runs it to the end.
class RicciFlow {
 public:
  /// \pre topology has one connected component; target and structure belong to it
  /// \throw InvalidInput when the target is not admissible (check_admissible) or the initial
  ///        metric breaks a triangle inequality
  RicciFlow(const Topology& topology, const ConformalStructure& structure, const Target& target,
            const FlowOptions& options = {});
  ~RicciFlow();
  RicciFlow(const RicciFlow&) = delete;
  RicciFlow& operator=(const RicciFlow&) = delete;

  /// Starts the flow from these log radii instead of structure.initial_u.
  void set_u(const Eigen::VectorXd& u);
  /// One iteration; returns false once the flow has stopped (converged or failed). A failed
  /// factorisation stops it with FlowStatus::SolverFailed (no exception).
  /// \throw SolverError as ricci_flow
  bool step();
  bool finished() const;
  const Eigen::VectorXd& u() const;
  const Eigen::VectorXd& curvature() const;
  double max_error() const;
  /// The result so far (complete once finished()).
  FlowResult result() const;

 private:
  /// The constructor's start at FlowOptions::start_u; false (the caller starts at the initial u)
  /// when that start is dropped.
  bool start_at(const Eigen::VectorXd& start_u);
  /// result() as the flow's last use: its arrays and flipped topology are moved out, not copied
  /// (ricci_flow calls it; the flow must not be used afterwards).
  FlowResult release_result();
  friend FlowResult ricci_flow(const Topology& topology, const ConformalStructure& structure,
                               const Target& target, const FlowOptions& options);

  struct State;
  std::unique_ptr<State> state_;
};

/// Runs the flow to convergence or failure. A Hessian that cannot be factorised (no longer
/// positive definite in floating point: the metric is degenerating) is no exception: the result
/// has FlowStatus::SolverFailed and a message naming the iteration and the span of the log radii.
/// \throw InvalidInput as RicciFlow's constructor
/// \throw SolverError when a factorised Newton system still gives a non-finite step
FlowResult ricci_flow(const Topology& topology, const ConformalStructure& structure,
                      const Target& target, const FlowOptions& options = {});

}  // namespace ricci
