#include "ricci/flow/ricci_flow.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "flow/detail/line_search.hpp"
#include "flow/detail/newton_system.hpp"
#include "flow/detail/stopping.hpp"
#include "flow/detail/trial_point.hpp"
#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/metric/background.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {

FlowSolver parse_flow_solver(const std::string& name) {
  return parse_enum<FlowSolver>(name, "parse_flow_solver");
}

const char* flow_solver_name(FlowSolver solver) {
  return enum_name(solver);
}

EdgeFlips parse_edge_flips(const std::string& name) {
  return parse_enum<EdgeFlips>(name, "parse_edge_flips");
}

const char* edge_flips_name(EdgeFlips flips) {
  return enum_name(flips);
}

bool uses_edge_flips(const ConformalStructure& structure, const FlowOptions& options) {
  if (options.flips == EdgeFlips::Off) return false;
  // Both backgrounds: Ptolemy's relation holds for l (Euclidean) and for sinh(l / 2)
  // (hyperbolic), see ricci/intrinsic/delaunay_flips.hpp.
  const bool vertex_scaling = scheme_traits(structure.scheme).ptolemy_flips;
  if (options.flips == EdgeFlips::Auto) return vertex_scaling;
  if (!vertex_scaling) {
    throw InvalidInput(
        std::string("RicciFlow: Delaunay edge flips need the vertex-scaling scheme; ") +
        scheme_name(structure.scheme) +
        " metrics do not keep their conformal class through a flip (Ptolemy's "
        "relation holds for vertex scaling only)");
  }
  return true;
}

const char* flow_status_name(FlowStatus status) {
  return enum_name(status);
}

struct RicciFlow::State {
  // The caller's topology is never changed: the intrinsic triangulation refers to it until the
  // first flip the flow needs, which makes its own copy (a mesh that is Delaunay throughout is
  // never copied). `topology` and `structure` are the triangulation's current connectivity and
  // conformal structure (eta set by the flips).
  const bool flips;
  IntrinsicTriangulation intrinsic;
  const Topology* topology;
  const ConformalStructure& structure;
  Target target;
  FlowOptions options;
  Clock::time_point start;

  Eigen::VectorXd u, lengths, curvature;
  CornerAngles angles;
  // The trial point of the line search, swapped in on acceptance.
  flow_detail::TrialPoint trial;
  // Set by the constructor when `lengths` hold the initial metric's, all valid, and no edge
  // failed the Delaunay test: its own call of set_u(initial u) then neither recomputes nor tests
  // them again (the same computation would give the same values).
  bool initial_lengths_delaunay = false;
  // The constructor started the symbolic analysis of the input triangulation's pattern ahead of
  // its Delaunay test: its set_u keeps it when no flip changed the triangulation.
  bool pattern_ahead = false;

  double gauge_mean = 0;  // mean of u held on a closed component
  double gradient_dt = 0;
  int iteration = 0;
  bool finished = false;
  FlowStatus status = FlowStatus::MaxIterations;
  std::string message;
  std::vector<OptionFix> fixes;  // FlowResult::fixes
  std::vector<IterationRecord> history;
  FlowTimings timings;
  int blocked_steps = 0;  // consecutive iterations whose steps broken triangles cut below
                          // blocked_step_length
  flow_detail::ChordSteps chord;
  // Last: destroyed first, which waits for a symbolic analysis under way.
  flow_detail::NewtonSystem system;

  State(const Topology& t, const ConformalStructure& s, const Target& tg, const FlowOptions& o)
      : flips(uses_edge_flips(s, o)),
        intrinsic(t, s),
        topology(&intrinsic.topology()),
        structure(intrinsic.structure()),
        target(tg),
        options(o),
        start(Clock::now()),
        system(o.use_cholmod, o.solver == FlowSolver::Newton) {
    if (o.start_preconditioner && o.solver == FlowSolver::Newton) {
      system.set_start_preconditioner(o.start_preconditioner, t.num_vertices);
    }
  }

  /// Flips the current triangulation to the Delaunay one at u (lengths l, updated); its own copy
  /// of the topology is made only when some edge fails the test.
  DelaunayFlipResult flip_current_to_delaunay(const Eigen::VectorXd& at, Eigen::VectorXd& l,
                                              const DelaunayFlipOptions& o) {
    DelaunayFlipResult r = intrinsic.flip_to_delaunay(at, l, o);
    topology = &intrinsic.topology();
    return r;
  }

  DelaunayFlipOptions flip_options() const {
    DelaunayFlipOptions o;
    o.keep_simplicial = options.simplicial_flips;
    return o;
  }

  /// A new pattern of the Newton system for the current triangulation, its slots built while
  /// its symbolic analysis runs.
  void new_pattern() { system.new_pattern(*topology, structure.geometry, target, timings); }

  /// Makes the trial triangulation the current one: a new sparsity pattern, analysed afresh.
  void accept_trial_flips() {
    if (!trial.flipped) return;
    // (The trial holds the flips before its own in its log: it was copied from the current
    // triangulation.)
    std::swap(intrinsic, trial.triangulation);
    topology = &intrinsic.topology();
    new_pattern();
    system.build_slots(*topology, timings);
  }

  double error_floor() const {
    return flow_detail::error_floor(*topology, target, u, system.edge_weights());
  }

  void record(double step, int backtracks, int triangle_failures, int flipped = 0) {
    const flow_detail::CurvatureErrors e =
        flow_detail::curvature_errors(*topology, target, curvature);
    IterationRecord r;
    r.iteration = iteration;
    r.max_error = e.max;
    r.rms_error = e.count > 0 ? std::sqrt(e.sum_sq / e.count) : 0.0;
    r.step_length = step;
    r.backtracks = backtracks;
    r.triangle_failures = triangle_failures;
    r.flips = flipped;
    r.chord = chord.active;
    r.seconds = seconds_since(start);
    history.push_back(r);
    // A finished flow has its status already (a failed line search).
    if (!finished) {
      if (auto stop = flow_detail::stopping_rule(history, iteration, options,
                                                 [this] { return error_floor(); })) {
        finish(std::move(*stop));
      }
    }
    if (options.progress && !options.progress(r) && !finished) {
      finish({FlowStatus::Cancelled, "cancelled by the progress callback"});
    }
  }

  /// finish_at the floor (flow_detail::stop_at_floor) when max_error is within it. Returns
  /// whether it did.
  bool finish_at_floor(double max_error) {
    auto stop = flow_detail::stop_at_floor(max_error, error_floor(), options.tolerance);
    if (!stop) return false;
    finish(std::move(*stop));
    return true;
  }

  void finish(flow_detail::Stop stop) {
    finished = true;
    status = stop.status;
    message = std::move(stop.message);
  }

  /// The fix for triangles that break without flips: flips where the scheme keeps its class
  /// through them, else the scheme that does (whose default, EdgeFlips::Auto, flips).
  void suggest_flips() {
    fixes = scheme_traits(structure.scheme).ptolemy_flips
                ? fixes_of({{"flips", "delaunay"}})
                : fixes_of({{"scheme", "vertex-scaling"}});
  }

  void normalise_gauge() {
    if (!system.closed()) return;
    double mean = 0;
    int count = 0;
    for (int v = 0; v < topology->num_vertices; ++v) {
      if (topology->vertex_component[v] < 0) continue;
      mean += u[v];
      ++count;
    }
    const double shift = gauge_mean - mean / std::max(count, 1);
    for (int v = 0; v < topology->num_vertices; ++v) {
      if (topology->vertex_component[v] >= 0) u[v] += shift;
    }
    lengths *= std::exp(shift);  // every scheme's lengths scale with a common factor on gamma
  }

  /// On a closed component sum (K-bar - K) is zero in exact arithmetic, but in floating point
  /// it drifts: fl(2 pi) sits 2.4e-16 below 2 pi, which adds up to 1e-10 over 500k vertices.
  /// No u can remove that drift; the mean is taken out of the right-hand side so that it spreads
  /// evenly (2.4e-16 per vertex) instead of piling up on the gauge vertex.
  double gauss_bonnet_drift() const {
    if (!system.closed()) return 0.0;
    double sum = 0;
    int count = 0;
    for (int v = 0; v < topology->num_vertices; ++v) {
      if (topology->vertex_component[v] < 0) continue;
      sum += target.curvature[v] - curvature[v];
      ++count;
    }
    return count > 0 ? sum / count : 0.0;
  }

  /// The right-hand side of the Newton system: K-bar - K on its rows, less the drift.
  Eigen::VectorXd newton_rhs() const {
    const double drift = gauss_bonnet_drift();
    const int n = system.rows();
    Eigen::VectorXd rhs(n);
    for (int r = 0; r < n; ++r) {
      const int v = system.vertex_of_row()[r];
      rhs[r] = target.curvature[v] - curvature[v] - drift;
    }
    return rhs;
  }

  /// A step on the rows of the system as one on all vertices (zero where u is held).
  Eigen::VectorXd step_of_rows(const Eigen::VectorXd& delta_rows) const {
    Eigen::VectorXd delta = Eigen::VectorXd::Zero(topology->num_vertices);
    for (int r = 0; r < system.rows(); ++r) delta[system.vertex_of_row()[r]] = delta_rows[r];
    return delta;
  }

  /// A chord step (ChordSteps); false when its solve was not finite (then a full step follows).
  bool chord_step() {
    const Eigen::VectorXd rhs = newton_rhs();
    const Eigen::VectorXd delta_rows = system.solve(rhs, timings);
    if (!delta_rows.allFinite()) return false;
    const double before = history.back().max_error;
    const Eigen::VectorXd delta = step_of_rows(delta_rows);
    ++chord.steps;
    chord.active = true;
    line_search(delta, 1.0);
    chord.finished(before, history.back().max_error);
    return true;
  }

  void newton_step() {
    if (chord.due(options, system, iteration, history) && chord_step()) return;
    chord.allowed = true;
    system.assemble(*topology, structure, u, lengths, angles, timings);
    const Eigen::VectorXd rhs = newton_rhs();

    // An earlier factorisation preconditions conjugate gradients well while the Hessian changes
    // little (NewtonSystem::solve_reusing_factor).
    Eigen::VectorXd delta_rows;
    bool solved = false;
    if (options.reuse_factorization_cg_iterations > 0 && system.has_preconditioner()) {
      solved = system.solve_reusing_factor(rhs, options.reuse_factorization_cg_iterations,
                                           options.tolerance, delta_rows, timings);
    }
    if (!solved) {
      system.ensure_analyzed(timings);
      try {
        system.factorize(iteration, timings);
      } catch (const SolverError& e) {
        ++iteration;
        const auto [lo, hi] = std::minmax_element(u.data(), u.data() + u.size());
        finish({FlowStatus::SolverFailed,
                std::string(e.what()) + " at iteration " + std::to_string(iteration) +
                    "; log radii span [" + flow_detail::short_number(*lo) + ", " +
                    flow_detail::short_number(*hi) +
                    "]: the metric is degenerating, so the target is probably not reachable "
                    "with this mesh (raise the valence around strong cones)"});
        record(0.0, 0, 0);
        return;
      }
      delta_rows = system.solve(rhs, timings);
    }
    if (!delta_rows.allFinite()) {
      throw SolverError("ricci_flow: the Newton system gave a non-finite step at iteration " +
                        std::to_string(iteration + 1));
    }
    line_search(step_of_rows(delta_rows), 1.0);
  }

  void gradient_step() {
    const double drift = gauss_bonnet_drift();
    Eigen::VectorXd delta = Eigen::VectorXd::Zero(topology->num_vertices);
    for (int v = 0; v < topology->num_vertices; ++v) {
      if (topology->vertex_component[v] < 0 || target.fixed[v]) continue;
      delta[v] = target.curvature[v] - curvature[v] - drift;
    }
    line_search(delta, gradient_dt);
  }

  /// The line search found no step: finish (at the floor, or LineSearchFailed saying why).
  void fail_line_search(const flow_detail::BacktrackingResult& b, double max0) {
    const bool newton = options.solver == FlowSolver::Newton;
    std::ostringstream why;
    why << "no step along the " << (newton ? "Newton" : "gradient") << " direction in "
        << b.backtracks
        << " halvings reduced max |K-bar - K| = " << flow_detail::short_number(max0);
    if (b.triangle_failures > 0) {
      why << " (" << b.triangle_failures
          << (flips ? " trial steps broke a triangle inequality next to the boundary, which "
                      "interior flips cannot repair)"
                    : " trial steps broke a triangle inequality: the target may need edge "
                      "flips (FlowOptions::flips = Delaunay, with the vertex-scaling scheme) "
                      "or another scheme)");
      if (!flips) suggest_flips();
    }
    if (b.length_failures > 0) {
      why << " (" << b.length_failures
          << " trial steps gave an edge a non-positive or overflowing length)";
    }
    if (!finish_at_floor(max0)) finish({FlowStatus::LineSearchFailed, why.str()});
    record(0.0, b.backtracks, b.triangle_failures + b.length_failures);
  }

  /// Steps cut to almost nothing by triangles that break (with flips: next to a boundary, whose
  /// edges cannot flip) make no progress however long the flow runs: give up after a few, so
  /// that the caller can do something else (flow_mesh retries on the doubled surface). The
  /// repaired dragon crept at steps of 4e-12 for 200 iterations (190 s) before this.
  void check_blocked_steps(double alpha, int triangle_failures, double max0) {
    blocked_steps = alpha < blocked_step_length && triangle_failures > 0 ? blocked_steps + 1 : 0;
    if (options.solver != FlowSolver::Newton || blocked_steps < max_blocked_steps) return;
    if (!flips) suggest_flips();
    finish({FlowStatus::LineSearchFailed,
            "the Newton steps are blocked by triangles that break a triangle inequality" +
                std::string(flips ? " next to the boundary (whose edges cannot flip)"
                                  : " (the target may need edge flips: FlowOptions::flips = "
                                    "Delaunay with the vertex-scaling scheme, or another "
                                    "scheme)") +
                ": steps of " + flow_detail::short_number(alpha) + " for " +
                std::to_string(blocked_steps) +
                " iterations at max |K-bar - K| = " + flow_detail::short_number(max0)});
  }

  /// Tries u + alpha delta from alpha = initial, halving while a triangle inequality breaks or
  /// (for Newton) while |K-bar - K|^2 does not decrease enough.
  void line_search(const Eigen::VectorXd& delta, double initial) {
    const auto t0 = Clock::now();
    const flow_detail::CurvatureErrors e0 =
        flow_detail::curvature_errors(*topology, target, curvature);
    flow_detail::BacktrackingOptions o;
    o.max_backtracks = options.max_backtracks;
    o.sufficient_decrease = options.solver == FlowSolver::Newton;
    o.armijo = options.armijo;
    o.tolerance = options.tolerance;
    const flow_detail::BacktrackingResult b = flow_detail::backtrack(
        o, initial, e0.sum_sq,
        [&](double alpha) {
          trial.u = u + alpha * delta;
          return trial.evaluate(intrinsic, *topology, structure, flips, flip_options());
        },
        [&] { return flow_detail::curvature_errors(*topology, target, trial.curvature); });
    if (!b.found) {
      timings.line_search += seconds_since(t0);
      ++iteration;
      fail_line_search(b, e0.max);
      return;
    }
    std::swap(u, trial.u);
    std::swap(lengths, trial.lengths);
    std::swap(angles, trial.angles);
    std::swap(curvature, trial.curvature);
    const int flipped = trial.flipped ? trial.flips : 0;
    accept_trial_flips();
    normalise_gauge();
    timings.line_search += seconds_since(t0);
    ++iteration;
    check_blocked_steps(b.alpha, b.triangle_failures, e0.max);
    record(b.alpha, b.backtracks, b.triangle_failures + b.length_failures, flipped);
  }

  /// The result so far; release: the flow's last use (ricci_flow), which moves the arrays and
  /// the flipped topology out instead of copying them.
  FlowResult make_result(bool release) {
    FlowResult r;
    r.status = status;
    r.converged = finished && status == FlowStatus::Converged;
    r.message = finished ? message : "running";
    if (finished && status != FlowStatus::Converged) r.fixes = fixes;
    r.error_floor = error_floor();
    r.total_area = gauss_bonnet_area(structure.geometry, angles);
    r.gauss_bonnet_relative_error =
        gauss_bonnet_relative_error(structure.geometry, *topology, curvature, r.total_area);
    r.target_curvature = target.curvature;
    for (int v = 0; v < topology->num_vertices; ++v) {
      if (target.fixed[v]) r.target_curvature[v] = curvature[v];
    }
    r.iterations = iteration;
    r.max_error = history.back().max_error;
    r.timings = timings;
    r.timings.total = seconds_since(start);
    r.analyses = system.analyses();
    r.factorizations = system.factorizations();
    r.cg_iterations = system.cg_iterations();
    r.chord_steps = chord.steps;
    r.linear_solver = options.solver == FlowSolver::Newton ? system.backend() : "none";
    if (release) {
      r.u = std::move(u);
      r.curvature = std::move(curvature);
      r.lengths = std::move(lengths);
      r.history = std::move(history);
      r.intrinsic = std::move(intrinsic);
    } else {
      r.u = u;
      r.curvature = curvature;
      r.lengths = lengths;
      r.history = history;
      r.intrinsic = intrinsic;  // (shares the connectivity until the flow flips again)
    }
    return r;
  }

  /// A step below this length cut by a broken triangle counts as blocked.
  static constexpr double blocked_step_length = 1e-6;
  /// Consecutive blocked Newton steps after which the flow gives up.
  static constexpr int max_blocked_steps = 3;
};

RicciFlow::RicciFlow(const Topology& topology, const ConformalStructure& structure,
                     const Target& target, const FlowOptions& options)
    : state_(std::make_unique<State>(topology, structure, target, options)) {
  State& s = *state_;
  if (topology.components.size() > 1) {
    throw InvalidInput("RicciFlow: the mesh has " + std::to_string(topology.components.size()) +
                       " connected components; solve them one by one (flow_mesh does)");
  }
  if (structure.epsilon.size() != topology.num_vertices ||
      structure.eta.size() != topology.num_edges ||
      structure.initial_u.size() != topology.num_vertices) {
    throw InvalidInput("RicciFlow: the conformal structure does not belong to this mesh");
  }
  if (!(options.tolerance > 0)) {
    throw InvalidInput("RicciFlow: tolerance must be positive, got " +
                       flow_detail::short_number(options.tolerance));
  }
  AdmissibilityOptions admissibility;
  admissibility.edge_flips = s.flips;
  check_admissible(topology, structure, target, admissibility);
  const Eigen::VectorXd& start_u = options.start_u;
  if (start_u.size() != 0 && (start_u.size() != topology.num_vertices || !start_u.allFinite())) {
    throw InvalidInput("RicciFlow: start_u has " + std::to_string(start_u.size()) +
                       " values (or one not finite); expected " +
                       std::to_string(topology.num_vertices) + " finite log factors or none");
  }
  const bool warm = start_u.size() != 0;
  if (s.flips) {
    // The input's triangulation is usually Delaunay already: its pattern's analysis starts now,
    // beside the test below, and set_u keeps it if no edge flips. (A flow started elsewhere
    // needs the pattern there.)
    if (!warm) {
      s.new_pattern();
      s.pattern_ahead = true;
    }
    // The initial metric (the input's lengths) is first retriangulated isometrically to its
    // intrinsic Delaunay triangulation: the same flat (or hyperbolic) surface, so the discrete
    // conformal class is that of the input surface (Gu, Luo, Sun and Wu's definition: vertex
    // scaling on Delaunay triangulations, flips between them). Ptolemy flips there would change the
    // metric where the input is not Delaunay: on face.obj (13k such edges) the map's mean angle
    // distortion on the input faces went from 1.029 to 1.068.
    if (options.isometric_start &&
        edge_lengths(*s.topology, s.structure, s.structure.initial_u, s.lengths).ok()) {
      DelaunayFlipOptions isometric = s.flip_options();
      isometric.isometric = true;
      if (count_non_delaunay_edges(*s.topology, s.lengths, isometric.tolerance,
                                   s.structure.geometry) == 0) {
        s.initial_lengths_delaunay = true;
      } else {
        s.flip_current_to_delaunay(s.structure.initial_u, s.lengths, isometric);
      }
    }
  }
  if (s.options.max_iterations <= 0) {
    s.options.max_iterations = options.solver == FlowSolver::Newton ? 200 : 1000000;
  }
  if (warm && start_at(start_u)) return;
  set_u(structure.initial_u);
}

bool RicciFlow::start_at(const Eigen::VectorXd& start_u) {
  State& s = *state_;
  // The initial metric's rms error, on the triangulation in hand (the intrinsic Delaunay one of
  // the input lengths, with flips): the start must beat it. (Not the largest error, which may
  // sit at a vertex the start hardly moves: 0.1407 at both on a generated disk.)
  Eigen::VectorXd lengths, curvature;
  CornerAngles angles;
  double initial_error = INFINITY;
  if (flow_detail::evaluate_metric(*s.topology, s.structure, s.structure.initial_u, lengths, angles,
                                   curvature) == flow_detail::Evaluation::Valid) {
    const flow_detail::CurvatureErrors e =
        flow_detail::curvature_errors(*s.topology, s.target, curvature);
    initial_error = e.count > 0 ? std::sqrt(e.sum_sq / e.count) : 0.0;
  }
  // (The lengths in hand are the initial u's, not the start's.)
  s.initial_lengths_delaunay = false;
  Eigen::VectorXd u = start_u;
  for (int v = 0; v < s.topology->num_vertices; ++v) {
    if (s.target.fixed[v]) u[v] = s.structure.initial_u[v];
  }
  try {
    set_u(u);
  } catch (const InvalidInput&) {  // a broken triangle there (no flips)
    return false;
  }
  return s.history.back().rms_error < initial_error;
}

RicciFlow::~RicciFlow() = default;

void RicciFlow::set_u(const Eigen::VectorXd& u) {
  State& s = *state_;
  if (u.size() != s.topology->num_vertices || !u.allFinite()) {
    throw InvalidInput("RicciFlow::set_u: expected " + std::to_string(s.topology->num_vertices) +
                       " finite log radii");
  }
  // Only the constructor's own call (u is the initial u) finds the lengths in hand, and with
  // them the pattern of the unchanged triangulation, whose analysis is under way.
  const bool lengths_in_hand = s.initial_lengths_delaunay;
  const bool pattern_in_hand = lengths_in_hand && s.pattern_ahead;
  s.initial_lengths_delaunay = false;
  s.pattern_ahead = false;
  if (!pattern_in_hand)
    s.system.finish_analysis(s.timings, /*keep=*/false);  // of the pattern this call replaces
  s.u = u;
  int initial_flips = 0;
  if (s.flips && !lengths_in_hand) {
    // Start on the intrinsic Delaunay triangulation of the initial metric: the same metric, the
    // triangulation on which the flow's energy is defined (and a broken triangle gets repaired).
    if (edge_lengths(*s.topology, s.structure, s.u, s.lengths).ok()) {
      const DelaunayFlipResult r = s.flip_current_to_delaunay(s.u, s.lengths, s.flip_options());
      initial_flips = r.flips;
    }
  }
  // The triangulation is final for this u: its system's pattern, whose symbolic analysis runs
  // beside the evaluation below.
  s.iteration = 0;
  s.history.clear();
  s.finished = false;
  if (!pattern_in_hand) {
    s.system.forget_gauge_vertex();
    s.new_pattern();
  }
  s.system.build_slots(*s.topology, s.timings);
  using flow_detail::Evaluation;
  const Evaluation ev = lengths_in_hand
                            ? flow_detail::evaluate_angles(*s.topology, s.structure.geometry,
                                                           s.lengths, s.angles, s.curvature)
                            : flow_detail::evaluate_metric(*s.topology, s.structure, s.u, s.lengths,
                                                           s.angles, s.curvature);
  if (ev == Evaluation::BadLength) {
    throw InvalidInput("RicciFlow: the initial metric has an edge of non-positive squared length");
  }
  if (ev == Evaluation::TriangleInequality) {
    const int f =
        corner_angles(*s.topology, s.lengths, s.angles, s.structure.geometry).first_bad_face;
    throw InvalidInput("RicciFlow: face " + std::to_string(f) +
                       " of the initial metric breaks a triangle inequality");
  }
  s.gauge_mean = 0;
  int count = 0;
  for (int v = 0; v < s.topology->num_vertices; ++v) {
    if (s.topology->vertex_component[v] < 0) continue;
    s.gauge_mean += s.u[v];
    ++count;
  }
  s.gauge_mean /= std::max(count, 1);
  if (s.options.solver == FlowSolver::Gradient) {
    s.gradient_dt = s.options.gradient_step;
    if (s.gradient_dt <= 0) {
      // Explicit Euler on du/dt = K-bar - K is stable for dt < 2 / lambda_max(L) and
      // lambda_max <= 2 max L_ii (Gershgorin): dt = 1 / max L_ii is safe.
      s.system.compute_edge_weights(*s.topology, s.structure, s.u, s.lengths, s.angles);
      const Eigen::VectorXd& edge_w = s.system.edge_weights();
      Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(s.topology->num_vertices);
      for (int e = 0; e < s.topology->num_edges; ++e) {
        diagonal[s.topology->edge_vertices(e, 0)] += std::abs(edge_w[e]);
        diagonal[s.topology->edge_vertices(e, 1)] += std::abs(edge_w[e]);
      }
      if (s.structure.geometry == Geometry::Hyperbolic) {
        diagonal += s.system.vertex_diagonal().cwiseAbs();
      }
      const double top = diagonal.maxCoeff();
      s.gradient_dt = top > 0 ? 1.0 / top : 0.1;
    }
  }
  s.record(0.0, 0, 0, initial_flips);
}

bool RicciFlow::step() {
  State& s = *state_;
  if (s.finished) return false;
  if (s.options.solver == FlowSolver::Newton) {
    s.newton_step();
  } else {
    s.gradient_step();
  }
  s.timings.total = seconds_since(s.start);
  return !s.finished;
}

bool RicciFlow::finished() const {
  return state_->finished;
}
const Eigen::VectorXd& RicciFlow::u() const {
  return state_->u;
}
const Eigen::VectorXd& RicciFlow::curvature() const {
  return state_->curvature;
}
double RicciFlow::max_error() const {
  return state_->history.back().max_error;
}

FlowResult RicciFlow::result() const {
  return state_->make_result(/*release=*/false);
}

FlowResult RicciFlow::release_result() {
  return state_->make_result(/*release=*/true);
}

FlowResult ricci_flow(const Topology& topology, const ConformalStructure& structure,
                      const Target& target, const FlowOptions& options) {
  RicciFlow flow(topology, structure, target, options);
  while (flow.step()) {
  }
  return flow.release_result();
}

}  // namespace ricci
