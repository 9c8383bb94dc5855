#include "ricci/flow/ricci_flow.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include <Eigen/SparseCore>

#include "numerics/detail/parallel.hpp"
#include "ricci/errors.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/metric/background.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {
namespace {

/// Outcome of evaluating the metric at trial log radii.
enum class Evaluation { Valid, BadLength, TriangleInequality };

}  // namespace

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
  // (hyperbolic), see ricci/metric/delaunay_flips.hpp.
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
  const bool hyperbolic;  // hyperbolic background: no gauge, a diagonal term in the Hessian
  IntrinsicTriangulation intrinsic;
  const Topology* topology;
  const ConformalStructure& structure;
  Target target;
  FlowOptions options;
  Clock::time_point start;

  Eigen::VectorXd u, lengths, curvature;
  CornerAngles angles;
  // Trial buffers of the line search, swapped in on acceptance.
  Eigen::VectorXd trial_u, trial_lengths, trial_curvature;
  CornerAngles trial_angles;
  // The triangulation of the trial point, flipped from the current one (only when it needed
  // flips), swapped in on acceptance.
  IntrinsicTriangulation trial;
  bool trial_flipped = false;
  int trial_flips = 0;
  // Set by the constructor when `lengths` hold the initial metric's, all valid, and no edge
  // failed the Delaunay test: its own call of set_u(initial u) then neither recomputes nor tests
  // them again (the same computation would give the same values).
  bool initial_lengths_delaunay = false;
  // The constructor started the symbolic analysis of the input triangulation's pattern ahead of
  // its Delaunay test: its set_u keeps it when no flip changed the triangulation.
  bool pattern_ahead = false;
  bool factor_matches_pattern = false;  // the Cholesky factor belongs to H's current pattern

  std::vector<int> row_of_vertex;  // #V: row of the reduced system, -1 when u is held
  std::vector<int> vertex_of_row;
  bool closed = true;      // no fixed vertex: angles invariant under u += c
  int pinned_vertex = -1;  // gauge of a closed component
  double gauge_mean = 0;   // mean of u held on a closed component

  Eigen::SparseMatrix<double> H;  // reduced Hessian, both triangles
  // Per value of H, the edge terms it sums, in order (slot_terms_start: #nnz + 1 offsets into
  // slot_terms; a term is 2 e + 1 for + w_e, 2 e for - w_e).
  std::vector<int> slot_terms_start, slot_terms;
  std::vector<int> diagonal_slot;  // per row
  SparseCholesky cholesky;
  Eigen::VectorXd halfedge_w, edge_w;
  Eigen::VectorXd corner_diagonal, vertex_diagonal;  // hyperbolic only (see hyperbolic.hpp)

  double gradient_dt = 0;
  int iteration = 0;
  bool finished = false;
  FlowStatus status = FlowStatus::MaxIterations;
  std::string message;
  std::vector<OptionFix> fixes;  // FlowResult::fixes
  std::vector<IterationRecord> history;
  FlowTimings timings;
  int analyses = 0, factorizations = 0, cg_iterations = 0;

  State(const Topology& t, const ConformalStructure& s, const Target& tg, const FlowOptions& o)
      : flips(uses_edge_flips(s, o)),
        hyperbolic(s.geometry == Geometry::Hyperbolic),
        intrinsic(t, s),
        topology(&intrinsic.topology()),
        structure(intrinsic.structure()),
        target(tg),
        options(o),
        start(Clock::now()),
        cholesky(o.use_cholmod) {}

  /// Flips the current triangulation to the Delaunay one at u (lengths l, updated); its own copy
  /// of the topology is made only when some edge fails the test.
  DelaunayFlipResult flip_current_to_delaunay(const Eigen::VectorXd& at, Eigen::VectorXd& l,
                                              const DelaunayFlipOptions& o) {
    DelaunayFlipResult r = intrinsic.flip_to_delaunay(at, l, o);
    topology = &intrinsic.topology();
    return r;
  }

  /// Lengths, angles and curvature of the current triangulation at u = at (no flips).
  Evaluation evaluate(const Eigen::VectorXd& at, Eigen::VectorXd& l, CornerAngles& a,
                      Eigen::VectorXd& k) const {
    if (!edge_lengths(*topology, structure, at, l).ok()) return Evaluation::BadLength;
    return evaluate_angles(l, a, k);
  }

  /// The same from lengths l in hand (valid ones).
  Evaluation evaluate_angles(const Eigen::VectorXd& l, CornerAngles& a, Eigen::VectorXd& k) const {
    if (!corner_angles(*topology, l, a, structure.geometry).ok()) {
      return Evaluation::TriangleInequality;
    }
    vertex_curvature(*topology, a, k);
    return Evaluation::Valid;
  }

  /// The trial point of the line search: with flips, on the Delaunay triangulation at trial_u
  /// (flipped on a copy when the current one is not Delaunay there).
  Evaluation evaluate_trial() {
    trial_flipped = false;
    trial_flips = 0;
    if (!flips) return evaluate(trial_u, trial_lengths, trial_angles, trial_curvature);
    if (!edge_lengths(*topology, structure, trial_u, trial_lengths).ok()) {
      return Evaluation::BadLength;
    }
    const Topology* t = topology;
    if (count_non_delaunay_edges(*topology, trial_lengths, flip_options().tolerance,
                                 structure.geometry) > intrinsic.blocked_flips()) {
      trial = intrinsic;
      const DelaunayFlipResult r = trial.flip_to_delaunay(trial_u, trial_lengths, flip_options());
      if (!r.complete) return Evaluation::TriangleInequality;
      trial_flipped = r.flips > 0;
      trial_flips = r.flips;
      t = &trial.topology();
    }
    if (!corner_angles(*t, trial_lengths, trial_angles, structure.geometry).ok()) {
      return Evaluation::TriangleInequality;
    }
    vertex_curvature(*t, trial_angles, trial_curvature);
    return Evaluation::Valid;
  }

  DelaunayFlipOptions flip_options() const {
    DelaunayFlipOptions o;
    o.keep_simplicial = options.simplicial_flips;
    return o;
  }

  /// Makes the trial triangulation the current one: a new sparsity pattern, analysed afresh.
  void accept_trial_flips() {
    if (!trial_flipped) return;
    // (The trial holds the flips before its own in its log: it was copied from the current
    // triangulation.)
    std::swap(intrinsic, trial);
    topology = &intrinsic.topology();
    finish_analysis();
    build_pattern();
    cholesky = SparseCholesky(options.use_cholmod);
    factor_matches_pattern = false;
    start_analysis();
    build_slots();
  }

  /// max and sum of squares of |K-bar - K| over the vertices with a target.
  void errors(const Eigen::VectorXd& k, double& max_error, double& sum_sq, int& count) const {
    max_error = 0;
    sum_sq = 0;
    count = 0;
    for (int v = 0; v < topology->num_vertices; ++v) {
      if (target.fixed[v] || topology->vertex_component[v] < 0) continue;
      const double d = target.curvature[v] - k[v];
      max_error = std::max(max_error, std::abs(d));
      sum_sq += d * d;
      ++count;
    }
  }

  void record(double step, int backtracks, int triangle_failures, int flipped = 0) {
    double max_error, sum_sq;
    int count;
    errors(curvature, max_error, sum_sq, count);
    IterationRecord r;
    r.iteration = iteration;
    r.max_error = max_error;
    r.rms_error = count > 0 ? std::sqrt(sum_sq / count) : 0.0;
    r.step_length = step;
    r.backtracks = backtracks;
    r.triangle_failures = triangle_failures;
    r.flips = flipped;
    r.chord = chord_step;
    r.seconds = seconds_since(start);
    history.push_back(r);
    // A finished flow has its status already (a failed line search). Otherwise: converged; or
    // stagnating within the floor (finish_at_floor ends it there); or out of iterations.
    if (!finished) {
      const bool stagnating =
          history.size() >= 2 && max_error > 0.5 * history[history.size() - 2].max_error;
      if (max_error <= options.tolerance) {
        finish(FlowStatus::Converged, "reached max |K-bar - K| = " + format(max_error) +
                                          " <= " + format(options.tolerance));
      } else if (!(stagnating && finish_at_floor(max_error)) &&
                 iteration >= options.max_iterations && !finish_at_floor(max_error)) {
        finish(FlowStatus::MaxIterations,
               "stopped after " + std::to_string(iteration) +
                   " iterations at max |K-bar - K| = " + format(max_error));
      }
    }
    const int window = options.stall_iterations;
    if (!finished && window > 0 && options.solver == FlowSolver::Newton &&
        history.size() > static_cast<std::size_t>(window)) {
      const double before = history[history.size() - 1 - window].max_error;
      if (!(max_error < 0.5 * before) && !finish_at_floor(max_error)) {
        finish(FlowStatus::MaxIterations, "stalled: max |K-bar - K| = " + format(max_error) +
                                              " after " + std::to_string(iteration) +
                                              " iterations, not half of its " + format(before) +
                                              " " + std::to_string(window) + " iterations before");
      }
    }
    if (options.progress && !options.progress(r) && !finished) {
      finish(FlowStatus::Cancelled, "cancelled by the progress callback");
    }
  }

  /// The smallest max |K-bar - K| double arithmetic can resolve at the current metric, per
  /// vertex: the rounding of its angle sum (about eps per angle, 2 pi in all, times its valence)
  /// and of its angles' dependence on the log radii (eps (1 + |u|) each, times dK/du, the edge
  /// weights: large next to needles), with a factor 4 of room. Well-shaped meshes sit near 1e-14;
  /// 0.1-degree needles bring it to the 1e-12 a parameterization asks for.
  double error_floor() const {
    // The weights of the last assembly (or of the gradient flow's step size): one step stale
    // at most, which an estimate with a factor of room tolerates.
    if (edge_w.size() != topology->num_edges) return 0.0;
    constexpr double eps = std::numeric_limits<double>::epsilon();
    std::vector<double> weight(topology->num_vertices, 0.0);
    for (int e = 0; e < topology->num_edges; ++e) {
      const int i = topology->edge_vertices(e, 0), j = topology->edge_vertices(e, 1);
      const double w = std::abs(edge_w[e]) * (1 + std::max(std::abs(u[i]), std::abs(u[j])));
      weight[i] += w;
      weight[j] += w;
    }
    double worst = 0;
    for (int v = 0; v < topology->num_vertices; ++v) {
      if (target.fixed[v] || topology->vertex_component[v] < 0) continue;
      const double floor =
          4 * eps * (2 * std::numbers::pi * topology->vertex_degree[v] + 2 * weight[v]);
      worst = std::max(worst, floor);
    }
    return worst;
  }

  /// A flow that cannot improve on an error within the floating-point floor has converged as
  /// far as the arithmetic goes: finish it so, saying so. Returns whether it did.
  bool finish_at_floor(double max_error) {
    const double floor = error_floor();
    if (!(max_error <= floor)) return false;
    finish(FlowStatus::Converged, "reached max |K-bar - K| = " + format(max_error) +
                                      ", the floating-point floor of this metric (about " +
                                      format(floor) + "), above the tolerance " +
                                      format(options.tolerance));
    return true;
  }

  static std::string format(double x) {
    std::ostringstream out;
    out.precision(3);
    out << x;
    return out.str();
  }

  void finish(FlowStatus s, const std::string& why) {
    finished = true;
    status = s;
    message = why;
  }

  /// The fix for triangles that break without flips: flips where the scheme keeps its class
  /// through them, else the scheme that does (whose default, EdgeFlips::Auto, flips).
  void suggest_flips() {
    fixes = scheme_traits(structure.scheme).ptolemy_flips
                ? fixes_of({{"flips", "delaunay"}})
                : fixes_of({{"scheme", "vertex-scaling"}});
  }

  /// The reduced system's rows and H's sparsity pattern (values zero).
  void build_pattern() {
    const auto t0 = Clock::now();
    const int nv = topology->num_vertices;
    row_of_vertex.assign(nv, -1);
    vertex_of_row.clear();
    // The hyperbolic energy is strictly convex: no gauge, every vertex with a target is free.
    closed = geometry_traits(structure.geometry).scale_gauge && !target.has_fixed_vertices();
    for (int v = 0; v < nv; ++v) {
      if (topology->vertex_component[v] < 0 || target.fixed[v]) continue;
      if (closed && pinned_vertex < 0) pinned_vertex = v;  // the gauge: u of one vertex stays put
      if (v == pinned_vertex) continue;                    // during the solve
      row_of_vertex[v] = static_cast<int>(vertex_of_row.size());
      vertex_of_row.push_back(v);
    }
    const int n = static_cast<int>(vertex_of_row.size());
    const int ne = topology->num_edges;
    // The pattern in compressed columns, built directly: per column (free vertex) its diagonal
    // and its free neighbours, sorted, double edges of a Delta-complex merged, as
    // setFromTriplets would make it.
    std::vector<int> outer(static_cast<std::size_t>(n) + 1, 0);
    for (int r = 0; r < n; ++r) outer[r + 1] = 1;
    for (int e = 0; e < ne; ++e) {
      const int ri = row_of_vertex[topology->edge_vertices(e, 0)];
      const int rj = row_of_vertex[topology->edge_vertices(e, 1)];
      if (ri >= 0 && rj >= 0 && ri != rj) {
        ++outer[ri + 1];
        ++outer[rj + 1];
      }
    }
    for (int r = 0; r < n; ++r) outer[r + 1] += outer[r];
    std::vector<int> inner(static_cast<std::size_t>(outer[n]));
    {
      std::vector<int> fill(outer.begin(), outer.end() - 1);
      for (int r = 0; r < n; ++r) inner[fill[r]++] = r;
      for (int e = 0; e < ne; ++e) {
        const int ri = row_of_vertex[topology->edge_vertices(e, 0)];
        const int rj = row_of_vertex[topology->edge_vertices(e, 1)];
        if (ri >= 0 && rj >= 0 && ri != rj) {
          inner[fill[ri]++] = rj;
          inner[fill[rj]++] = ri;
        }
      }
    }
    std::vector<int> column_size(static_cast<std::size_t>(n));
    parallel::for_each(n, [&](std::int64_t r) {
      int* begin = inner.data() + outer[r];
      int* end = inner.data() + outer[r + 1];
      std::sort(begin, end);
      column_size[r] = static_cast<int>(std::unique(begin, end) - begin);
    });
    H.resize(n, n);
    std::int64_t nnz = 0;
    for (int r = 0; r < n; ++r) nnz += column_size[r];
    H.resizeNonZeros(static_cast<Eigen::Index>(nnz));
    {
      int* outer_ptr = H.outerIndexPtr();
      int* inner_ptr = H.innerIndexPtr();
      outer_ptr[0] = 0;
      for (int r = 0; r < n; ++r) {
        std::copy_n(inner.data() + outer[r], column_size[r], inner_ptr + outer_ptr[r]);
        outer_ptr[r + 1] = outer_ptr[r] + column_size[r];
      }
      std::fill_n(H.valuePtr(), nnz, 0.0);
    }
    timings.setup += seconds_since(t0);
  }

  /// What each value of H sums (slot_terms), from H's pattern: built while the symbolic
  /// analysis of that pattern runs (build_pattern, start_analysis, build_slots), both only
  /// reading it.
  void build_slots() {
    const auto t0 = Clock::now();
    const int n = static_cast<int>(vertex_of_row.size());
    const int ne = topology->num_edges;
    const std::int64_t nnz = H.nonZeros();
    auto slot = [&](int r, int c) -> int {
      if (r < 0 || c < 0) return -1;
      const int* begin = H.innerIndexPtr() + H.outerIndexPtr()[c];
      const int* end = H.innerIndexPtr() + H.outerIndexPtr()[c + 1];
      return static_cast<int>(std::lower_bound(begin, end, r) - H.innerIndexPtr());
    };
    diagonal_slot.resize(n);
    for (int r = 0; r < n; ++r) diagonal_slot[r] = slot(r, r);
    // What each matrix entry sums, in the order of a sequential pass over the edges (-w into the
    // two off-diagonal entries ij and ji, +w into the diagonal entries ii and jj): assembly then
    // fills the entries in parallel with exactly the sequential pass's sums.
    std::vector<int> edge_slots(4 * static_cast<std::size_t>(ne));
    parallel::for_each(ne, [&](std::int64_t e) {
      const int ri = row_of_vertex[topology->edge_vertices(e, 0)];
      const int rj = row_of_vertex[topology->edge_vertices(e, 1)];
      edge_slots[4 * e + 0] = slot(ri, rj);
      edge_slots[4 * e + 1] = slot(rj, ri);
      edge_slots[4 * e + 2] = ri >= 0 ? diagonal_slot[ri] : -1;
      edge_slots[4 * e + 3] = rj >= 0 ? diagonal_slot[rj] : -1;
    });
    slot_terms_start.assign(static_cast<std::size_t>(nnz) + 1, 0);
    for (const int x : edge_slots) {
      if (x >= 0) ++slot_terms_start[x + 1];
    }
    for (std::int64_t x = 0; x < nnz; ++x) slot_terms_start[x + 1] += slot_terms_start[x];
    slot_terms.resize(static_cast<std::size_t>(slot_terms_start[nnz]));
    {
      std::vector<int> fill(slot_terms_start.begin(), slot_terms_start.end() - 1);
      for (std::size_t i = 0; i < edge_slots.size(); ++i) {
        const int x = edge_slots[i];
        // term: 2 e + 1 adds w_e, 2 e subtracts it
        if (x >= 0) slot_terms[fill[x]++] = 2 * static_cast<int>(i / 4) + (i % 4 >= 2 ? 1 : 0);
      }
    }
    timings.setup += seconds_since(t0);
  }

  /// Starts the symbolic analysis of H's new pattern beside this thread (Newton only): it needs
  /// nothing but the pattern, and runs while the first evaluation and the Hessian's weights are
  /// computed. H and the Cholesky object are left alone until finish_analysis().
  void start_analysis() {
    finish_analysis();
    if (options.solver != FlowSolver::Newton) return;
    pending_analysis = parallel::run_beside([this]() -> double {
      const auto t0 = Clock::now();
      cholesky.analyze(H);
      return seconds_since(t0);
    });
  }

  /// Waits for an analysis started by start_analysis and books it (rethrowing its exception);
  /// keep = false: one whose result is thrown away, failed or not.
  void finish_analysis(bool keep = true) {
    if (!pending_analysis.valid()) return;
    std::future<double> pending = std::move(pending_analysis);
    if (!keep) {
      pending.wait();
      return;
    }
    timings.analysis += pending.get();
    ++analyses;
  }

  void compute_edge_weights() {
    hessian_terms(*topology, structure, u, lengths, angles, halfedge_w, corner_diagonal,
                  vertex_diagonal);
    edge_weights(*topology, halfedge_w, edge_w);
  }

  void assemble() {
    const auto t0 = Clock::now();
    compute_edge_weights();
    // The symbolic analysis reads H: wait for it before writing the values.
    finish_analysis();
    double* values = H.valuePtr();
    parallel::for_each(H.nonZeros(), [&](std::int64_t x) {
      double sum = 0.0;
      for (int i = slot_terms_start[x]; i < slot_terms_start[x + 1]; ++i) {
        const int term = slot_terms[i];
        const double w = edge_w[term >> 1];
        sum = (term & 1) ? sum + w : sum - w;
      }
      values[x] = sum;
    });
    if (hyperbolic) {
      for (std::size_t r = 0; r < vertex_of_row.size(); ++r) {
        values[diagonal_slot[r]] += vertex_diagonal[vertex_of_row[r]];
      }
    }
    timings.assembly += seconds_since(t0);
  }

  void normalise_gauge() {
    if (!closed) return;
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
    if (!closed) return 0.0;
    double sum = 0;
    int count = 0;
    for (int v = 0; v < topology->num_vertices; ++v) {
      if (topology->vertex_component[v] < 0) continue;
      sum += target.curvature[v] - curvature[v];
      ++count;
    }
    return count > 0 ? sum / count : 0.0;
  }

  /// Conjugate gradients on H x = b preconditioned with the last factorisation (of an earlier
  /// Hessian). Returns false when it does not reach the relative residual within max_iterations.
  bool preconditioned_cg(const Eigen::VectorXd& b, double relative_tolerance, int max_iterations,
                         Eigen::VectorXd& x) {
    x.setZero(b.size());
    Eigen::VectorXd r = b;
    Eigen::VectorXd z = cholesky.solve(r);
    Eigen::VectorXd p = z;
    double rz = r.dot(z);
    const double goal = relative_tolerance * b.norm();
    for (int k = 1; k <= max_iterations; ++k) {
      const Eigen::VectorXd Hp = H * p;
      const double curvature_along_p = p.dot(Hp);
      if (!(curvature_along_p > 0)) return false;
      const double alpha = rz / curvature_along_p;
      x += alpha * p;
      r -= alpha * Hp;
      ++cg_iterations;
      if (r.norm() <= goal) return true;
      z = cholesky.solve(r);
      const double rz_next = r.dot(z);
      p = z + (rz_next / rz) * p;
      rz = rz_next;
    }
    return false;
  }

  void newton_step() {
    const int n = static_cast<int>(vertex_of_row.size());
    // Chord step: next to the solution the Hessian barely changes between iterations (the last
    // step moved u by about the error), so the factorisation in hand solves the new system as
    // well as a new one would, without assembling: on a 1M-face disk the last iteration took
    // 0.35 s with assembly and conjugate gradients, 0.15 s as a chord step. It must cut the
    // error tenfold or the next iteration is a full one.
    const std::size_t h = history.size();
    if (options.chord_error > 0 && factor_matches_pattern && chord_allowed &&
        factored_at == iteration - 1 && h >= 2 && history[h - 1].max_error <= options.chord_error &&
        history[h - 1].max_error <= 1e-3 * history[h - 2].max_error) {
      const double drift = gauss_bonnet_drift();
      Eigen::VectorXd rhs(n);
      for (int r = 0; r < n; ++r) {
        const int v = vertex_of_row[r];
        rhs[r] = target.curvature[v] - curvature[v] - drift;
      }
      const auto t0 = Clock::now();
      const Eigen::VectorXd delta_rows = cholesky.solve(rhs);
      timings.solve += seconds_since(t0);
      if (delta_rows.allFinite()) {
        const double before = history.back().max_error;
        Eigen::VectorXd delta = Eigen::VectorXd::Zero(topology->num_vertices);
        for (int r = 0; r < n; ++r) delta[vertex_of_row[r]] = delta_rows[r];
        ++chord_steps;
        chord_step = true;
        line_search(delta, 1.0);
        chord_step = false;
        chord_allowed = history.back().max_error <= 0.1 * before;
        return;
      }
    }
    chord_allowed = true;
    assemble();
    if (!cholesky.analyzed()) {
      const auto t0 = Clock::now();
      cholesky.analyze(H);
      ++analyses;
      timings.analysis += seconds_since(t0);
    }
    const double drift = gauss_bonnet_drift();
    Eigen::VectorXd rhs(n);
    for (int r = 0; r < n; ++r) {
      const int v = vertex_of_row[r];
      rhs[r] = target.curvature[v] - curvature[v] - drift;
    }

    // An earlier factorisation preconditions conjugate gradients well while the Hessian changes
    // little; the relative residual asked for shrinks with the error (inexact Newton with a
    // forcing term proportional to the error keeps the convergence quadratic).
    Eigen::VectorXd delta_rows;
    bool solved = false;
    if (options.reuse_factorization_cg_iterations > 0 && factor_matches_pattern) {
      const auto t0 = Clock::now();
      const double forcing = std::clamp(0.1 * rhs.cwiseAbs().maxCoeff(), 1e-14, 1e-2);
      solved =
          preconditioned_cg(rhs, forcing, options.reuse_factorization_cg_iterations, delta_rows);
      timings.solve += seconds_since(t0);
    }
    if (!solved) {
      auto t0 = Clock::now();
      try {
        cholesky.factorize(H);
      } catch (const SolverError& e) {
        timings.factorization += seconds_since(t0);
        ++iteration;
        const auto [lo, hi] = std::minmax_element(u.data(), u.data() + u.size());
        finish(FlowStatus::SolverFailed,
               std::string(e.what()) + " at iteration " + std::to_string(iteration) +
                   "; log radii span [" + format(*lo) + ", " + format(*hi) +
                   "]: the metric is degenerating, so the target is probably not reachable "
                   "with this mesh (raise the valence around strong cones)");
        record(0.0, 0, 0);
        return;
      }
      ++factorizations;
      factored_at = iteration;
      factor_matches_pattern = true;
      timings.factorization += seconds_since(t0);
      t0 = Clock::now();
      delta_rows = cholesky.solve(rhs);
      timings.solve += seconds_since(t0);
    }
    if (!delta_rows.allFinite()) {
      throw SolverError("ricci_flow: the Newton system gave a non-finite step at iteration " +
                        std::to_string(iteration + 1));
    }
    Eigen::VectorXd delta = Eigen::VectorXd::Zero(topology->num_vertices);
    for (int r = 0; r < n; ++r) delta[vertex_of_row[r]] = delta_rows[r];
    line_search(delta, 1.0);
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

  /// Tries u + alpha delta from alpha = initial, halving while a triangle inequality breaks or
  /// (for Newton) while |K-bar - K|^2 does not decrease enough.
  void line_search(const Eigen::VectorXd& delta, double initial) {
    const auto t0 = Clock::now();
    double max0, sum0;
    int count;
    errors(curvature, max0, sum0, count);
    const bool newton = options.solver == FlowSolver::Newton;
    double alpha = initial;
    int backtracks = 0, triangle_failures = 0, length_failures = 0;
    for (;; alpha *= 0.5, ++backtracks) {
      if (backtracks > options.max_backtracks) {
        timings.line_search += seconds_since(t0);
        ++iteration;
        std::ostringstream why;
        why << "no step along the " << (newton ? "Newton" : "gradient") << " direction in "
            << backtracks << " halvings reduced max |K-bar - K| = " << format(max0);
        if (triangle_failures > 0) {
          why << " (" << triangle_failures
              << (flips ? " trial steps broke a triangle inequality next to the boundary, which "
                          "interior flips cannot repair)"
                        : " trial steps broke a triangle inequality: the target may need edge "
                          "flips (FlowOptions::flips = Delaunay, with the vertex-scaling scheme) "
                          "or another scheme)");
          if (!flips) suggest_flips();
        }
        if (length_failures > 0) {
          why << " (" << length_failures
              << " trial steps gave an edge a non-positive or overflowing length)";
        }
        if (!finish_at_floor(max0)) finish(FlowStatus::LineSearchFailed, why.str());
        record(0.0, backtracks, triangle_failures + length_failures);
        return;
      }
      trial_u = u + alpha * delta;
      const Evaluation ev = evaluate_trial();
      if (ev != Evaluation::Valid) {
        // A step that breaks a triangle is shortened, never accepted.
        ++(ev == Evaluation::TriangleInequality ? triangle_failures : length_failures);
        continue;
      }
      if (!newton) break;
      double max1, sum1;
      errors(trial_curvature, max1, sum1, count);
      if (sum1 <= (1.0 - 2.0 * options.armijo * alpha) * sum0 || max1 <= options.tolerance) break;
    }
    std::swap(u, trial_u);
    std::swap(lengths, trial_lengths);
    std::swap(angles, trial_angles);
    std::swap(curvature, trial_curvature);
    const int flipped = trial_flipped ? trial_flips : 0;
    accept_trial_flips();
    normalise_gauge();
    timings.line_search += seconds_since(t0);
    ++iteration;
    // Steps cut to almost nothing by triangles that break (with flips: next to a boundary, whose
    // edges cannot flip) make no progress however long the flow runs: give up after a few, so
    // that the caller can do something else (flow_mesh retries on the doubled surface). The
    // repaired dragon crept at steps of 4e-12 for 200 iterations (190 s) before this.
    blocked_steps = alpha < 1e-6 && triangle_failures > 0 ? blocked_steps + 1 : 0;
    if (newton && blocked_steps >= 3) {
      if (!flips) suggest_flips();
      finish(
          FlowStatus::LineSearchFailed,
          "the Newton steps are blocked by triangles that break a triangle inequality" +
              std::string(flips ? " next to the boundary (whose edges cannot flip)"
                                : " (the target may need edge flips: FlowOptions::flips = "
                                  "Delaunay with the vertex-scaling scheme, or another scheme)") +
              ": steps of " + format(alpha) + " for " + std::to_string(blocked_steps) +
              " iterations at max |K-bar - K| = " + format(max0));
    }
    record(alpha, backtracks, triangle_failures + length_failures, flipped);
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
    r.analyses = analyses;
    r.factorizations = factorizations;
    r.cg_iterations = cg_iterations;
    r.chord_steps = chord_steps;
    r.linear_solver = options.solver == FlowSolver::Newton ? cholesky.backend() : "none";
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

  int blocked_steps = 0;      // consecutive iterations whose step triangles cut below 1e-6
  bool chord_allowed = true;  // the last chord step cut the error tenfold (or none was made)
  bool chord_step = false;    // the step being taken is one
  int factored_at = -1;       // iteration whose Newton step factorised the Hessian in hand
  int chord_steps = 0;

  // The symbolic analysis running beside the flow (start_analysis); last, so that it is
  // destroyed, which waits for the analysis, before H and the Cholesky object it reads.
  std::future<double> pending_analysis;
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
                       State::format(options.tolerance));
  }
  AdmissibilityOptions admissibility;
  admissibility.edge_flips = s.flips;
  check_admissible(topology, structure, target, admissibility);
  if (s.flips) {
    // The input's triangulation is usually Delaunay already: its pattern's analysis starts now,
    // beside the test below, and set_u keeps it if no edge flips.
    s.build_pattern();
    s.start_analysis();
    s.pattern_ahead = true;
    // The initial metric (the input's lengths) is first retriangulated isometrically to its
    // intrinsic Delaunay triangulation: the same flat (or hyperbolic) surface, so the discrete
    // conformal class is that of the input surface (Gu, Luo, Sun and Wu's definition: vertex
    // scaling on Delaunay triangulations, flips between them). Ptolemy flips there would change the
    // metric where the input is not Delaunay: on face.obj (13k such edges) the map's mean angle
    // distortion on the input faces went from 1.029 to 1.068.
    if (edge_lengths(*s.topology, s.structure, s.structure.initial_u, s.lengths).ok()) {
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
  set_u(structure.initial_u);
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
  if (!pattern_in_hand) s.finish_analysis(/*keep=*/false);  // of the pattern this call replaces
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
    s.pinned_vertex = -1;
    s.build_pattern();
    s.cholesky = SparseCholesky(s.options.use_cholmod);
    s.factor_matches_pattern = false;
    s.start_analysis();
  }
  s.build_slots();
  const Evaluation ev = lengths_in_hand ? s.evaluate_angles(s.lengths, s.angles, s.curvature)
                                        : s.evaluate(s.u, s.lengths, s.angles, s.curvature);
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
      s.compute_edge_weights();
      Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(s.topology->num_vertices);
      for (int e = 0; e < s.topology->num_edges; ++e) {
        diagonal[s.topology->edge_vertices(e, 0)] += std::abs(s.edge_w[e]);
        diagonal[s.topology->edge_vertices(e, 1)] += std::abs(s.edge_w[e]);
      }
      if (s.hyperbolic) diagonal += s.vertex_diagonal.cwiseAbs();
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
