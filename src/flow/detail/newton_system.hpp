#pragma once
/// \file
/// Internal to ricci_flow: the Newton system H delta = K-bar - K on the free vertices. Its
/// sparsity pattern (built directly in compressed columns), what each value of H sums (so that
/// assembly fills the values in parallel with the sums of a sequential pass over the edges), the
/// symbolic analysis started beside the flow, the numeric factorisation and solves, and
/// conjugate gradients preconditioned with an earlier factorisation.

#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "numerics/detail/parallel.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/flow/target.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace ricci::flow_detail {

/// The reduced Hessian of one triangulation and its Cholesky factorisation. Not movable: the
/// symbolic analysis running beside the flow refers to it.
class NewtonSystem {
 public:
  /// analyse_beside: start the symbolic analysis of each new pattern beside the caller's thread
  /// (Newton; the gradient flow only reads the edge weights).
  NewtonSystem(bool use_cholmod, bool analyse_beside);
  NewtonSystem(const NewtonSystem&) = delete;
  NewtonSystem& operator=(const NewtonSystem&) = delete;
  /// Waits for an analysis under way (its result thrown away).
  ~NewtonSystem();

  /// Lets the next pattern pick the gauge vertex afresh (the first free vertex of a closed
  /// component; kept through new patterns otherwise).
  void forget_gauge_vertex() { pinned_vertex_ = -1; }

  /// The rows of the reduced system and H's sparsity pattern (values zero) for triangulation t,
  /// a new Cholesky object, and (analyse_beside) its symbolic analysis started beside this
  /// thread. Waits for an earlier analysis first and books it.
  void new_pattern(const Topology& t, Geometry geometry, const Target& target,
                   FlowTimings& timings);
  /// What each value of H sums, from H's pattern: built while the symbolic analysis of that
  /// pattern runs, both only reading it.
  void build_slots(const Topology& t, FlowTimings& timings);
  /// Waits for an analysis started by new_pattern and books it (rethrowing its exception);
  /// keep = false: one whose result is thrown away, failed or not.
  void finish_analysis(FlowTimings& timings, bool keep = true);

  /// The Hessian's weights at the given metric (edge_weights(), vertex_diagonal()).
  void compute_edge_weights(const Topology& t, const ConformalStructure& s,
                            const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                            const CornerAngles& angles);
  /// compute_edge_weights, then H's values (after the symbolic analysis, which reads H).
  void assemble(const Topology& t, const ConformalStructure& s, const Eigen::VectorXd& u,
                const Eigen::VectorXd& lengths, const CornerAngles& angles, FlowTimings& timings);
  /// The symbolic analysis, when none was made (or started) for this pattern.
  void ensure_analyzed(FlowTimings& timings);
  /// Conjugate gradients on H x = rhs preconditioned with the factorisation in hand (of an
  /// earlier Hessian, possibly of an earlier pattern: has_preconditioner), to a relative residual
  /// proportional to the error (clamped to [min_forcing, max_forcing]). Returns false when
  /// max_iterations do not reach it. A residual of norm at most tolerance_share * tolerance is
  /// enough whatever the forcing term asks (`tolerance`: the flow's, on max |K-bar - K|): the
  /// step's linear error then lies a tenth below it. (The last step from 6e-11 to the tolerance
  /// 1e-12 took 18 iterations of 0.025 s on igea to a relative residual of 6e-12, where 2e-3 does.)
  bool solve_reusing_factor(const Eigen::VectorXd& rhs, int max_iterations, double tolerance,
                            Eigen::VectorXd& x, FlowTimings& timings);
  /// The numeric factorisation of H, made at this flow iteration.
  /// \throw SolverError when H is not positive definite in floating point
  void factorize(int iteration, FlowTimings& timings);
  /// H^-1 rhs with the factorisation in hand.
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs, FlowTimings& timings) const;

  int rows() const { return static_cast<int>(vertex_of_row_.size()); }
  const std::vector<int>& vertex_of_row() const { return vertex_of_row_; }
  /// No fixed vertex and a scale gauge: angles invariant under u += c.
  bool closed() const { return closed_; }
  /// The factorisation in hand belongs to H's current pattern.
  bool factor_matches_pattern() const { return factor_matches_pattern_; }
  /// A factorisation that can precondition H: the current pattern's, or the one the pattern
  /// before the last flips had (same rows; a few flipped edges change H by a few entries, so
  /// it preconditions the new H about as well as its own: igea with 4 cones, flips of 14 and 2
  /// edges, each a new analysis and factorisation of 0.5 s before).
  bool has_preconditioner() const {
    return factor_matches_pattern_ || previous_factor_ || start_preconditioner_;
  }
  /// FlowOptions::start_preconditioner for a triangulation of nv vertices: preconditions until
  /// the first factorisation (none: an empty function).
  void set_start_preconditioner(std::function<Eigen::VectorXd(const Eigen::VectorXd&)> inverse,
                                int nv) {
    start_preconditioner_ = std::move(inverse);
    start_vertices_ = nv;
  }
  /// The flow iteration whose step made the factorisation in hand, -1 before any.
  int factored_at() const { return factored_at_; }
  const Eigen::VectorXd& edge_weights() const { return edge_w_; }
  const Eigen::VectorXd& vertex_diagonal() const { return vertex_diagonal_; }
  const Eigen::SparseMatrix<double>& matrix() const { return H_; }
  int analyses() const { return analyses_; }
  int factorizations() const { return factorizations_; }
  int cg_iterations() const { return cg_iterations_; }
  const char* backend() const { return cholesky_.backend(); }

  /// Bounds of the forcing term of solve_reusing_factor: 0.1 max |rhs| (inexact Newton with a
  /// forcing term proportional to the error keeps the convergence quadratic), not below what
  /// double arithmetic resolves on the residual and not above a hundredth (then the factorisation
  /// is no longer a good preconditioner).
  static constexpr double forcing_factor = 0.1;
  static constexpr double min_forcing = 1e-14;
  static constexpr double max_forcing = 1e-2;
  static constexpr double tolerance_share = 0.1;

 private:
  void build_pattern(const Topology& t, Geometry geometry, const Target& target,
                     FlowTimings& timings);
  void start_analysis();
  bool preconditioned_cg(const Eigen::VectorXd& b, double relative_tolerance, int max_iterations,
                         Eigen::VectorXd& x);

  bool use_cholmod_;
  bool analyse_beside_;
  std::vector<int> row_of_vertex_;  // #V: row of the reduced system, -1 when u is held
  std::vector<int> vertex_of_row_;
  bool closed_ = true;      // no fixed vertex: angles invariant under u += c
  int pinned_vertex_ = -1;  // gauge of a closed component

  Eigen::SparseMatrix<double> H_;  // reduced Hessian, both triangles
  // Per value of H, the edge terms it sums, in order (slot_terms_start: #nnz + 1 offsets into
  // slot_terms; a term is 2 e + 1 for + w_e, 2 e for - w_e).
  std::vector<int> slot_terms_start_, slot_terms_;
  std::vector<int> diagonal_slot_;  // per row
  SparseCholesky cholesky_;
  bool factor_matches_pattern_ = false;
  // The last factorisation of an earlier pattern with the same rows (new_pattern keeps it),
  // until this pattern has its own.
  std::unique_ptr<SparseCholesky> previous_factor_;
  // FlowOptions::start_preconditioner (on start_vertices_ vertices), until the first
  // factorisation.
  std::function<Eigen::VectorXd(const Eigen::VectorXd&)> start_preconditioner_;
  int start_vertices_ = 0;
  int factored_at_ = -1;
  Eigen::VectorXd halfedge_w_, edge_w_;
  Eigen::VectorXd corner_diagonal_, vertex_diagonal_;  // hyperbolic only (see hyperbolic.hpp)
  int analyses_ = 0, factorizations_ = 0, cg_iterations_ = 0;

  // The symbolic analysis running beside the flow (new_pattern); last, so that it is destroyed,
  // which waits for the analysis, before H and the Cholesky object it reads.
  parallel::Task<double> pending_analysis_;
};

/// When a Newton iteration is a chord step: next to the solution the Hessian barely changes
/// between iterations (the last step moved u by about the error), so the factorisation in hand
/// solves the new system as well as a new one would, without assembling: on a 1M-face disk the
/// last iteration took 0.35 s with assembly and conjugate gradients, 0.15 s as a chord step. It
/// must cut the error tenfold or the next iteration is a full one.
struct ChordSteps {
  /// The last full step must have cut the error at least this much.
  static constexpr double required_full_step_cut = 1e-3;
  /// Each chord step must cut the error at least this much to allow the next one.
  static constexpr double required_chord_cut = 0.1;

  bool allowed = true;  // the last chord step cut the error tenfold (or none was made)
  bool active = false;  // the step being taken is one
  int steps = 0;

  /// Whether the next step is a chord step: the factorisation of the last iteration in hand, the
  /// error at most options.chord_error and a thousandth of the one before.
  bool due(const FlowOptions& options, const NewtonSystem& system, int iteration,
           const std::vector<IterationRecord>& history) const;
  /// Books a chord step that took the error from before to after.
  void finished(double before, double after) {
    active = false;
    allowed = after <= required_chord_cut * before;
  }
};

}  // namespace ricci::flow_detail
