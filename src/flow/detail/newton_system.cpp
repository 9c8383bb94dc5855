#include "flow/detail/newton_system.hpp"

#include <algorithm>
#include <cstdint>

#include "numerics/detail/conjugate_gradients.hpp"
#include "numerics/detail/parallel.hpp"
#include "ricci/errors.hpp"
#include "ricci/metric/background.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci::flow_detail {

NewtonSystem::NewtonSystem(bool use_cholmod, bool analyse_beside)
    : use_cholmod_(use_cholmod), analyse_beside_(analyse_beside), cholesky_(use_cholmod) {}

NewtonSystem::~NewtonSystem() {
  // Dropped before the members it reads go: waited for when a thread has started it, else not
  // run at all.
  pending_analysis_ = parallel::Task<double>();
}

void NewtonSystem::new_pattern(const Topology& t, Geometry geometry, const Target& target,
                               FlowTimings& timings) {
  finish_analysis(timings);
  const std::vector<int> rows_before = vertex_of_row_;
  build_pattern(t, geometry, target, timings);
  if (vertex_of_row_ != rows_before) {
    previous_factor_.reset();
  } else if (factor_matches_pattern_) {
    previous_factor_ = std::make_unique<SparseCholesky>(std::move(cholesky_));
  }  // (else the previous pattern had none of its own: the older one stays)
  cholesky_ = SparseCholesky(use_cholmod_);
  factor_matches_pattern_ = false;
  // With an earlier factorisation in hand the next steps try conjugate gradients first: this
  // pattern is analysed only when they need a factorisation of their own (ensure_analyzed).
  if (!previous_factor_ && !start_preconditioner_) start_analysis();
}

void NewtonSystem::build_pattern(const Topology& t, Geometry geometry, const Target& target,
                                 FlowTimings& timings) {
  const auto t0 = Clock::now();
  const int nv = t.num_vertices;
  row_of_vertex_.assign(nv, -1);
  vertex_of_row_.clear();
  // The hyperbolic energy is strictly convex: no gauge, every vertex with a target is free.
  closed_ = geometry_traits(geometry).scale_gauge && !target.has_fixed_vertices();
  for (int v = 0; v < nv; ++v) {
    if (t.vertex_component[v] < 0 || target.fixed[v]) continue;
    if (closed_ && pinned_vertex_ < 0) pinned_vertex_ = v;  // the gauge: u of one vertex stays
    if (v == pinned_vertex_) continue;                      // put during the solve
    row_of_vertex_[v] = static_cast<int>(vertex_of_row_.size());
    vertex_of_row_.push_back(v);
  }
  const int n = static_cast<int>(vertex_of_row_.size());
  const int ne = t.num_edges;
  // The pattern in compressed columns, built directly: per column (free vertex) its diagonal
  // and its free neighbours, sorted, double edges of a Delta-complex merged, as
  // setFromTriplets would make it.
  std::vector<int> outer(static_cast<std::size_t>(n) + 1, 0);
  for (int r = 0; r < n; ++r) outer[r + 1] = 1;
  for (int e = 0; e < ne; ++e) {
    const int ri = row_of_vertex_[t.edge_vertices(e, 0)];
    const int rj = row_of_vertex_[t.edge_vertices(e, 1)];
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
      const int ri = row_of_vertex_[t.edge_vertices(e, 0)];
      const int rj = row_of_vertex_[t.edge_vertices(e, 1)];
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
  H_.resize(n, n);
  std::int64_t nnz = 0;
  for (int r = 0; r < n; ++r) nnz += column_size[r];
  H_.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer_ptr = H_.outerIndexPtr();
  int* inner_ptr = H_.innerIndexPtr();
  outer_ptr[0] = 0;
  for (int r = 0; r < n; ++r) {
    std::copy_n(inner.data() + outer[r], column_size[r], inner_ptr + outer_ptr[r]);
    outer_ptr[r + 1] = outer_ptr[r] + column_size[r];
  }
  std::fill_n(H_.valuePtr(), nnz, 0.0);
  timings.setup += seconds_since(t0);
}

void NewtonSystem::build_slots(const Topology& t, FlowTimings& timings) {
  const auto t0 = Clock::now();
  const int n = static_cast<int>(vertex_of_row_.size());
  const int ne = t.num_edges;
  const std::int64_t nnz = H_.nonZeros();
  auto slot = [&](int r, int c) -> int {
    if (r < 0 || c < 0) return -1;
    const int* begin = H_.innerIndexPtr() + H_.outerIndexPtr()[c];
    const int* end = H_.innerIndexPtr() + H_.outerIndexPtr()[c + 1];
    return static_cast<int>(std::lower_bound(begin, end, r) - H_.innerIndexPtr());
  };
  diagonal_slot_.resize(n);
  for (int r = 0; r < n; ++r) diagonal_slot_[r] = slot(r, r);
  // What each matrix entry sums, in the order of a sequential pass over the edges (-w into the
  // two off-diagonal entries ij and ji, +w into the diagonal entries ii and jj): assembly then
  // fills the entries in parallel with exactly the sequential pass's sums.
  std::vector<int> edge_slots(4 * static_cast<std::size_t>(ne));
  parallel::for_each(ne, [&](std::int64_t e) {
    const int ri = row_of_vertex_[t.edge_vertices(e, 0)];
    const int rj = row_of_vertex_[t.edge_vertices(e, 1)];
    edge_slots[4 * e + 0] = slot(ri, rj);
    edge_slots[4 * e + 1] = slot(rj, ri);
    edge_slots[4 * e + 2] = ri >= 0 ? diagonal_slot_[ri] : -1;
    edge_slots[4 * e + 3] = rj >= 0 ? diagonal_slot_[rj] : -1;
  });
  slot_terms_start_.assign(static_cast<std::size_t>(nnz) + 1, 0);
  for (const int x : edge_slots) {
    if (x >= 0) ++slot_terms_start_[x + 1];
  }
  for (std::int64_t x = 0; x < nnz; ++x) slot_terms_start_[x + 1] += slot_terms_start_[x];
  slot_terms_.resize(static_cast<std::size_t>(slot_terms_start_[nnz]));
  std::vector<int> fill(slot_terms_start_.begin(), slot_terms_start_.end() - 1);
  for (std::size_t i = 0; i < edge_slots.size(); ++i) {
    const int x = edge_slots[i];
    // term: 2 e + 1 adds w_e, 2 e subtracts it
    if (x >= 0) slot_terms_[fill[x]++] = 2 * static_cast<int>(i / 4) + (i % 4 >= 2 ? 1 : 0);
  }
  timings.setup += seconds_since(t0);
}

/// Starts the symbolic analysis of H's new pattern beside this thread (Newton only): it needs
/// nothing but the pattern, and runs while the first evaluation and the Hessian's weights are
/// computed. H and the Cholesky object are left alone until finish_analysis().
void NewtonSystem::start_analysis() {
  if (!analyse_beside_) return;
  pending_analysis_ = parallel::run_beside([this]() -> double {
    const auto t0 = Clock::now();
    cholesky_.analyze(H_);
    return seconds_since(t0);
  });
}

void NewtonSystem::finish_analysis(FlowTimings& timings, bool keep) {
  if (!pending_analysis_.valid()) return;
  parallel::Task<double> pending = std::move(pending_analysis_);
  // Not kept: dropped (waited for when a thread has started it, else never run).
  if (!keep) return;
  timings.analysis += pending.get();
  ++analyses_;
}

void NewtonSystem::compute_edge_weights(const Topology& t, const ConformalStructure& s,
                                        const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                                        const CornerAngles& angles) {
  hessian_terms(t, s, u, lengths, angles, halfedge_w_, corner_diagonal_, vertex_diagonal_);
  ricci::edge_weights(t, halfedge_w_, edge_w_);
}

void NewtonSystem::assemble(const Topology& t, const ConformalStructure& s,
                            const Eigen::VectorXd& u, const Eigen::VectorXd& lengths,
                            const CornerAngles& angles, FlowTimings& timings) {
  const auto t0 = Clock::now();
  compute_edge_weights(t, s, u, lengths, angles);
  // The symbolic analysis reads H: wait for it before writing the values.
  finish_analysis(timings);
  double* values = H_.valuePtr();
  parallel::for_each(H_.nonZeros(), [&](std::int64_t x) {
    double sum = 0.0;
    for (int i = slot_terms_start_[x]; i < slot_terms_start_[x + 1]; ++i) {
      const int term = slot_terms_[i];
      const double w = edge_w_[term >> 1];
      sum = (term & 1) ? sum + w : sum - w;
    }
    values[x] = sum;
  });
  if (s.geometry == Geometry::Hyperbolic) {
    for (std::size_t r = 0; r < vertex_of_row_.size(); ++r) {
      values[diagonal_slot_[r]] += vertex_diagonal_[vertex_of_row_[r]];
    }
  }
  timings.assembly += seconds_since(t0);
}

void NewtonSystem::ensure_analyzed(FlowTimings& timings) {
  if (cholesky_.analyzed()) return;
  const auto t0 = Clock::now();
  cholesky_.analyze(H_);
  ++analyses_;
  timings.analysis += seconds_since(t0);
}

bool NewtonSystem::preconditioned_cg(const Eigen::VectorXd& b, double relative_tolerance,
                                     int max_iterations, Eigen::VectorXd& x) {
  const SparseCholesky* factor = factor_matches_pattern_ ? &cholesky_ : previous_factor_.get();
  Eigen::VectorXd on_vertices;  // (the start preconditioner's)
  auto precondition = [&](const Eigen::VectorXd& residual) -> Eigen::VectorXd {
    // (A preconditioner needs no more than single precision: solve_approximately halves the
    // memory traffic of a large factor's solves.)
    if (factor != nullptr) return factor->solve_approximately(residual);
    on_vertices.setZero(start_vertices_);
    for (std::size_t i = 0; i < vertex_of_row_.size(); ++i) {
      on_vertices[vertex_of_row_[i]] = residual[static_cast<Eigen::Index>(i)];
    }
    const Eigen::VectorXd solved = start_preconditioner_(on_vertices);
    Eigen::VectorXd z(residual.size());
    for (std::size_t i = 0; i < vertex_of_row_.size(); ++i) {
      z[static_cast<Eigen::Index>(i)] = solved[vertex_of_row_[i]];
    }
    return z;
  };
  const auto apply = [&](const Eigen::VectorXd& p) -> Eigen::VectorXd { return H_ * p; };
  const numerics_detail::ConjugateGradients cg = numerics_detail::conjugate_gradients(
      apply, precondition, b, relative_tolerance, max_iterations, x);
  cg_iterations_ += cg.iterations;
  return cg.converged;
}

bool NewtonSystem::solve_reusing_factor(const Eigen::VectorXd& rhs, int max_iterations,
                                        double tolerance, Eigen::VectorXd& x,
                                        FlowTimings& timings) {
  const auto t0 = Clock::now();
  const double norm = rhs.norm();
  double forcing = std::clamp(forcing_factor * rhs.cwiseAbs().maxCoeff(), min_forcing, max_forcing);
  if (norm > 0)
    forcing = std::max(forcing, std::min(max_forcing, tolerance_share * tolerance / norm));
  const bool solved = preconditioned_cg(rhs, forcing, max_iterations, x);
  timings.solve += seconds_since(t0);
  return solved;
}

void NewtonSystem::factorize(int iteration, FlowTimings& timings) {
  const auto t0 = Clock::now();
  try {
    cholesky_.factorize(H_);
  } catch (const SolverError&) {
    timings.factorization += seconds_since(t0);
    throw;
  }
  ++factorizations_;
  factored_at_ = iteration;
  factor_matches_pattern_ = true;
  previous_factor_.reset();
  start_preconditioner_ = nullptr;
  timings.factorization += seconds_since(t0);
}

Eigen::VectorXd NewtonSystem::solve(const Eigen::VectorXd& rhs, FlowTimings& timings) const {
  const auto t0 = Clock::now();
  Eigen::VectorXd x = cholesky_.solve(rhs);
  timings.solve += seconds_since(t0);
  return x;
}

bool ChordSteps::due(const FlowOptions& options, const NewtonSystem& system, int iteration,
                     const std::vector<IterationRecord>& history) const {
  const std::size_t h = history.size();
  return options.chord_error > 0 && system.factor_matches_pattern() && allowed &&
         system.factored_at() == iteration - 1 && h >= 2 &&
         history[h - 1].max_error <= options.chord_error &&
         history[h - 1].max_error <= required_full_step_cut * history[h - 2].max_error;
}

}  // namespace ricci::flow_detail
