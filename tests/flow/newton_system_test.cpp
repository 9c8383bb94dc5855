// The Newton system of ricci_flow (src/flow/detail/newton_system.hpp): its rows, the values
// assembly gives H (exactly the sums of a sequential pass over the edges), its solves, and when
// a chord step is due.

#include "flow/detail/newton_system.hpp"

#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "ricci/flow/target.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/background.hpp"
#include "ricci/metric/lengths.hpp"

namespace ricci {
namespace {

using flow_detail::ChordSteps;
using flow_detail::NewtonSystem;

struct Metric {
  Topology topology;
  ConformalStructure structure;
  Eigen::VectorXd u, lengths;
  CornerAngles angles;
};

Metric make_metric(const Mesh& mesh) {
  Metric m;
  m.topology = build_topology(mesh.triangles, mesh.num_vertices());
  m.structure =
      make_conformal_structure(m.topology, input_edge_lengths(mesh, m.topology), {}).structure;
  m.u = m.structure.initial_u;
  EXPECT_TRUE(edge_lengths(m.topology, m.structure, m.u, m.lengths).ok());
  EXPECT_TRUE(corner_angles(m.topology, m.lengths, m.angles, m.structure.geometry).ok());
  return m;
}

/// H by a sequential pass over the edges, in the order assembly promises to reproduce.
Eigen::MatrixXd sequential_hessian(const Topology& t, const NewtonSystem& system) {
  std::vector<int> row(t.num_vertices, -1);
  for (int r = 0; r < system.rows(); ++r) row[system.vertex_of_row()[r]] = r;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(system.rows(), system.rows());
  for (int e = 0; e < t.num_edges; ++e) {
    const int ri = row[t.edge_vertices(e, 0)], rj = row[t.edge_vertices(e, 1)];
    const double w = system.edge_weights()[e];
    if (ri >= 0 && rj >= 0) H(ri, rj) -= w;
    if (ri >= 0 && rj >= 0) H(rj, ri) -= w;
    if (ri >= 0) H(ri, ri) += w;
    if (rj >= 0) H(rj, rj) += w;
  }
  return H;
}

TEST(NewtonSystem, ClosedSurfacePinsOneVertexAndAssemblesTheSequentialSums) {
  const Metric m = make_metric(make_icosphere(2));
  const Target target = uniform_target(m.topology);
  FlowTimings timings;
  NewtonSystem system(/*use_cholmod=*/true, /*analyse_beside=*/true);
  system.new_pattern(m.topology, m.structure.geometry, target, timings);
  system.build_slots(m.topology, timings);
  system.assemble(m.topology, m.structure, m.u, m.lengths, m.angles, timings);
  EXPECT_TRUE(system.closed());
  ASSERT_EQ(system.rows(), m.topology.num_vertices - 1);  // the gauge vertex is held
  EXPECT_EQ(system.vertex_of_row()[0], 1);                // vertex 0 is the gauge
  EXPECT_EQ(system.analyses(), 1);                        // booked by assemble
  const Eigen::MatrixXd H = system.matrix();
  EXPECT_EQ((H - sequential_hessian(m.topology, system)).cwiseAbs().maxCoeff(), 0.0);
}

TEST(NewtonSystem, FixedBoundaryRowsAndSolves) {
  const Metric m = make_metric(make_disk(4, 0.3));
  const Target target = flat_target(m.topology, {});  // u held on the boundary
  FlowTimings timings;
  NewtonSystem system(/*use_cholmod=*/true, /*analyse_beside=*/false);
  system.new_pattern(m.topology, m.structure.geometry, target, timings);
  system.build_slots(m.topology, timings);
  EXPECT_FALSE(system.closed());
  int interior = 0;
  for (int v = 0; v < m.topology.num_vertices; ++v) interior += !m.topology.is_boundary_vertex[v];
  ASSERT_EQ(system.rows(), interior);
  system.assemble(m.topology, m.structure, m.u, m.lengths, m.angles, timings);
  system.ensure_analyzed(timings);
  EXPECT_EQ(system.analyses(), 1);
  EXPECT_FALSE(system.factor_matches_pattern());
  system.factorize(/*iteration=*/7, timings);
  EXPECT_TRUE(system.factor_matches_pattern());
  EXPECT_EQ(system.factored_at(), 7);
  EXPECT_EQ(system.factorizations(), 1);

  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(system.rows(), -1.0, 1.0);
  const Eigen::VectorXd x = system.solve(b, timings);
  EXPECT_LT((system.matrix() * x - b).norm(), 1e-12 * b.norm());
  // The factorisation of H itself preconditions H perfectly: one iteration.
  Eigen::VectorXd y;
  EXPECT_TRUE(system.solve_reusing_factor(b, 25, /*tolerance=*/0, y, timings));
  EXPECT_EQ(system.cg_iterations(), 1);
  EXPECT_LT((y - x).norm(), 1e-12 * x.norm());

  // A new pattern (after flips) has no factorisation of its own, but the one before, on the same
  // rows, still preconditions: here the matrix did not change, so again one iteration, and no
  // analysis of the new pattern is made for it.
  system.new_pattern(m.topology, m.structure.geometry, target, timings);
  system.build_slots(m.topology, timings);
  system.assemble(m.topology, m.structure, m.u, m.lengths, m.angles, timings);
  EXPECT_FALSE(system.factor_matches_pattern());
  EXPECT_TRUE(system.has_preconditioner());
  Eigen::VectorXd z;
  EXPECT_TRUE(system.solve_reusing_factor(b, 25, /*tolerance=*/0, z, timings));
  EXPECT_EQ(system.cg_iterations(), 2);
  EXPECT_LT((z - x).norm(), 1e-12 * x.norm());
  EXPECT_EQ(system.analyses(), 1);
  // Its own factorisation replaces it.
  system.ensure_analyzed(timings);
  system.factorize(/*iteration=*/8, timings);
  EXPECT_TRUE(system.factor_matches_pattern());
  EXPECT_EQ(system.analyses(), 2);
}

TEST(NewtonSystem, StartPreconditionerUntilTheFirstFactorisation) {
  const Metric m = make_metric(make_disk(4, 0.3));
  const Target target = flat_target(m.topology, {});  // u held on the boundary
  FlowTimings timings;
  NewtonSystem system(/*use_cholmod=*/true, /*analyse_beside=*/true);
  const int nv = m.topology.num_vertices;
  int calls = 0;
  // H's inverse itself, given on all vertices (held ones 0): a perfect preconditioner.
  Eigen::MatrixXd inverse_rows;
  system.set_start_preconditioner(
      [&](const Eigen::VectorXd& r) {
        EXPECT_EQ(r.size(), nv);
        ++calls;
        Eigen::VectorXd on_rows(system.rows());
        for (int i = 0; i < system.rows(); ++i) on_rows[i] = r[system.vertex_of_row()[i]];
        const Eigen::VectorXd solved = inverse_rows * on_rows;
        Eigen::VectorXd z = Eigen::VectorXd::Constant(nv, 1e300);  // (ignored off the rows)
        for (int i = 0; i < system.rows(); ++i) z[system.vertex_of_row()[i]] = solved[i];
        return z;
      },
      nv);
  system.new_pattern(m.topology, m.structure.geometry, target, timings);
  system.build_slots(m.topology, timings);
  system.assemble(m.topology, m.structure, m.u, m.lengths, m.angles, timings);
  EXPECT_EQ(system.analyses(), 0);  // none started: the preconditioner comes first
  ASSERT_TRUE(system.has_preconditioner());
  inverse_rows = Eigen::MatrixXd(system.matrix()).inverse();
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(system.rows(), -1.0, 1.0);
  Eigen::VectorXd x;
  EXPECT_TRUE(system.solve_reusing_factor(b, 25, /*tolerance=*/0, x, timings));
  EXPECT_EQ(system.cg_iterations(), 1);
  EXPECT_GE(calls, 1);
  EXPECT_LT((system.matrix() * x - b).norm(), 1e-10 * b.norm());
  // A poor preconditioner (the identity) needs more iterations; a flow tolerance far above the
  // residual lets it stop at the forcing term's loosest (max_forcing) instead.
  system.set_start_preconditioner([](const Eigen::VectorXd& r) { return r; }, nv);
  // (An error of 1e-6: the forcing term asks 1e-7 of it.)
  const Eigen::VectorXd small = 1e-6 * b;
  const int before = system.cg_iterations();
  system.solve_reusing_factor(small, 100, /*tolerance=*/0.0, x, timings);
  const int tight = system.cg_iterations() - before;
  EXPECT_GT(tight, 1);
  EXPECT_TRUE(system.solve_reusing_factor(small, 100, /*tolerance=*/1e3, x, timings));
  EXPECT_LT(system.cg_iterations() - before - tight, tight);
  EXPECT_LE((system.matrix() * x - small).norm(), NewtonSystem::max_forcing * small.norm());
  // The first factorisation ends it.
  system.ensure_analyzed(timings);
  system.factorize(/*iteration=*/1, timings);
  const int calls_before = calls;
  EXPECT_TRUE(system.solve_reusing_factor(b, 25, /*tolerance=*/0, x, timings));
  EXPECT_EQ(calls, calls_before);
}

TEST(ChordSteps, DueOnlyAfterAThousandfoldCutByTheLastFactorisation) {
  const Metric m = make_metric(make_disk(3));
  const Target target = flat_target(m.topology, {});
  FlowTimings timings;
  NewtonSystem system(true, false);
  system.new_pattern(m.topology, m.structure.geometry, target, timings);
  system.build_slots(m.topology, timings);
  system.assemble(m.topology, m.structure, m.u, m.lengths, m.angles, timings);
  system.ensure_analyzed(timings);
  FlowOptions options;  // chord_error 1e-8
  std::vector<IterationRecord> history(2);
  history[0].max_error = 1e-4;
  history[1].max_error = 1e-9;  // cut 1e5-fold, below chord_error
  ChordSteps chord;
  EXPECT_FALSE(chord.due(options, system, 2, history));  // no factorisation yet
  system.factorize(1, timings);
  EXPECT_TRUE(chord.due(options, system, 2, history));
  EXPECT_FALSE(chord.due(options, system, 3, history));  // factorised two iterations ago
  history[1].max_error = 2e-8;                           // above chord_error
  EXPECT_FALSE(chord.due(options, system, 2, history));
  history[0].max_error = 1e-5;
  history[1].max_error = 5e-9;  // cut 2000-fold
  EXPECT_TRUE(chord.due(options, system, 2, history));
  history[1].max_error = 9e-9;  // under a thousandfold
  history[0].max_error = 8e-6;
  EXPECT_FALSE(chord.due(options, system, 2, history));
  history[0].max_error = 1e-4;
  // A chord step that cut the error less than tenfold allows no next one.
  chord.active = true;
  chord.finished(1e-9, 2e-10);
  EXPECT_FALSE(chord.active);
  EXPECT_FALSE(chord.allowed);
  EXPECT_FALSE(chord.due(options, system, 2, history));
  chord.finished(1e-9, 5e-11);
  EXPECT_TRUE(chord.allowed);
  options.chord_error = 0;  // never
  EXPECT_FALSE(chord.due(options, system, 2, history));
}

}  // namespace
}  // namespace ricci
