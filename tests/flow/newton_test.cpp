#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "flow/flow_test_util.hpp"
#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/hard_cases.hpp"
#include "ricci/mesh/split.hpp"
#include "ricci/metric/curvature.hpp"
#include "support/test_meshes.hpp"

namespace ricci {
namespace {

struct Problem {
  Topology topology;
  StructureResult structure;
  Eigen::VectorXd lbar;
};

Problem make_problem(const Mesh& mesh, Scheme scheme = Scheme::Thurston) {
  Problem p;
  p.topology = build_topology(mesh.triangles, mesh.num_vertices());
  p.lbar = input_edge_lengths(mesh, p.topology);
  StructureOptions options;
  options.scheme = scheme;
  p.structure = make_conformal_structure(p.topology, p.lbar, options);
  return p;
}

void expect_solution(const Problem& p, const Target& target, const FlowResult& r,
                     double tolerance = 1e-10) {
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_EQ(r.status, FlowStatus::Converged);
  EXPECT_LE(r.max_error, tolerance);
  for (int v = 0; v < p.topology.num_vertices; ++v) {
    if (!target.fixed[v]) {
      EXPECT_NEAR(r.curvature[v], target.curvature[v], tolerance) << "vertex " << v;
    } else {
      EXPECT_EQ(r.u[v], p.structure.structure.initial_u[v]) << "fixed vertex " << v << " moved";
    }
  }
  EXPECT_LT(r.gauss_bonnet_relative_error, 1e-12);
  EXPECT_EQ(r.history.front().iteration, 0);
  EXPECT_EQ(static_cast<int>(r.history.size()), r.iterations + 1);
  EXPECT_LE(r.history.back().max_error, tolerance);
}

TEST(Newton, FlatTorusConvergesQuadratically) {
  for (Scheme scheme :
       {Scheme::Thurston, Scheme::Tangential, Scheme::VertexScaling, Scheme::InversiveDistance}) {
    const Problem p = make_problem(make_torus(40, 16), scheme);
    const Target target = flat_target(p.topology, {});
    const FlowResult r = ricci_flow(p.topology, p.structure.structure, target);
    expect_solution(p, target, r);
    EXPECT_LE(r.iterations, 12) << scheme_name(scheme);
    EXPECT_EQ(r.analyses, 1);  // the symbolic analysis is reused while the pattern holds
    EXPECT_LE(r.factorizations, r.iterations);
    testing::expect_quadratic_convergence(r);
  }
}

// With factorisation reuse off, every Newton step factorises; with it on (the default), later
// steps solve by conjugate gradients preconditioned with an earlier factor, and both reach the
// same metric.
TEST(Newton, FactorisationReuseSavesFactorisationsAndKeepsTheAnswer) {
  const Problem p = make_problem(make_closed_surface(2, 16));
  const Target target = uniform_target(p.topology);
  FlowOptions options;
  options.reuse_factorization_cg_iterations = 0;
  const FlowResult every = ricci_flow(p.topology, p.structure.structure, target, options);
  options.reuse_factorization_cg_iterations = 25;
  const FlowResult reuse = ricci_flow(p.topology, p.structure.structure, target, options);
  ASSERT_TRUE(every.converged && reuse.converged);
  EXPECT_EQ(every.factorizations + every.chord_steps, every.iterations);
  EXPECT_EQ(every.cg_iterations, 0);
  EXPECT_LT(reuse.factorizations, reuse.iterations);
  EXPECT_GT(reuse.cg_iterations, 0);
  testing::expect_quadratic_convergence(every);
  EXPECT_LT((every.u - reuse.u).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Newton, DiskWithFreeBoundaryKeepsBoundaryRadii) {
  const Problem p = make_problem(make_disk(8, 0.8));
  const Target target = flat_target(p.topology, {}, BoundaryMode::Free);
  const FlowResult r = ricci_flow(p.topology, p.structure.structure, target);
  expect_solution(p, target, r);
  testing::expect_quadratic_convergence(r);
}

TEST(Newton, DiskBoundaryUniformAndByLength) {
  const Problem p = make_problem(make_disk(8, 0.8));
  for (BoundaryMode mode : {BoundaryMode::DiskUniform, BoundaryMode::DiskLength}) {
    const Target target = flat_target(p.topology, {}, mode, p.lbar);
    const FlowResult r = ricci_flow(p.topology, p.structure.structure, target);
    expect_solution(p, target, r);
    testing::expect_quadratic_convergence(r);
    // The boundary is a convex polygon whose turning angles are the targets: 2 pi / m each.
    if (mode == BoundaryMode::DiskUniform) {
      const int m = static_cast<int>(p.topology.boundary_loops[0].size());
      for (int v : p.topology.boundary_loops[0]) {
        EXPECT_NEAR(r.curvature[v], 2 * std::numbers::pi / m, 1e-10);
      }
    }
  }
}

TEST(Newton, Genus3WithOneConeOfTwoPiChi) {
  // chi = -4: one cone of -8 pi. Its single-vertex bound asks for valence > 10 (more with
  // Thurston's Phi > 0), so edges around it are split first (tutorial section 5.3); one midpoint
  // subdivision after that gives its neighbours enough faces for Thurston's conditions on the
  // vertex sets around the cone, not only on the cone itself.
  const Mesh base = make_closed_surface(3, 20);
  const ValenceResult refined = raise_valence(base, 0, 24);
  ASSERT_GE(refined.final_valence, 24);
  const Problem p = make_problem(subdivide_midpoint(refined.mesh));
  ASSERT_EQ(p.topology.euler_characteristic(), -4);
  const Target target = flat_target(p.topology, {{0, -8 * std::numbers::pi}});
  const FlowResult r = ricci_flow(p.topology, p.structure.structure, target);
  expect_solution(p, target, r);
  testing::expect_quadratic_convergence(r);
  // The cone angle is 2 pi - K = 10 pi.
  EXPECT_NEAR(2 * std::numbers::pi - r.curvature[0], 10 * std::numbers::pi, 1e-10);
}

TEST(Newton, SphereWithFourAndEightCones) {
  const Mesh sphere = make_icosphere(3);
  const Problem p = make_problem(sphere);
  // Four cones of pi at the vertices nearest a regular tetrahedron's corners, and eight of pi/2
  // nearest a cube's corners.
  const std::vector<Cone> four = testing::tetrahedron_cones(sphere);
  const std::vector<Cone> eight = testing::cube_cones(sphere);
  for (const auto& cones : {four, eight}) {
    const Target target = flat_target(p.topology, cones);
    const FlowResult r = ricci_flow(p.topology, p.structure.structure, target);
    expect_solution(p, target, r);
    testing::expect_quadratic_convergence(r);
  }
}

TEST(Newton, SolutionDoesNotDependOnTheInitialRadii) {
  const Problem p = make_problem(make_closed_surface(2, 8));
  const Target target = uniform_target(p.topology);
  const FlowResult a = ricci_flow(p.topology, p.structure.structure, target);
  ASSERT_TRUE(a.converged) << a.message;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  RicciFlow flow(p.topology, p.structure.structure, target);
  Eigen::VectorXd start = p.structure.structure.initial_u;
  for (int v = 0; v < start.size(); ++v) start[v] += noise(rng);
  flow.set_u(start);
  while (flow.step()) {
  }
  const FlowResult b = flow.result();
  ASSERT_TRUE(b.converged) << b.message;
  // Same metric up to one global scale factor.
  const Eigen::ArrayXd ratio = a.lengths.array() / b.lengths.array();
  EXPECT_LT((ratio / ratio.mean() - 1.0).abs().maxCoeff(), 1e-9);
}

/// A disk with a free boundary and interior cones, vertex scaling with flips: the generated disk
/// is Delaunay as it is, the case whose lengths the constructor has in hand.
struct ConeDisk {
  Problem p = make_problem(make_disk(12, 0.3), Scheme::VertexScaling);
  Target target;
  FlowOptions options;
  ConeDisk() {
    const int centre = 0;  // make_disk's centre vertex
    target = flat_target(p.topology, {{centre, 0.6}, {40, -0.3}, {90, 0.4}});
    options.tolerance = 1e-12;
  }
  FlowResult flow(const Eigen::VectorXd& start = {}) const {
    FlowOptions o = options;
    o.start_u = start;
    return ricci_flow(p.topology, p.structure.structure, target, o);
  }
};

TEST(Newton, AStartNearTheSolutionSavesStepsAndKeepsTheAnswer) {
  const ConeDisk disk;
  const FlowResult cold = disk.flow();
  expect_solution(disk.p, disk.target, cold, 1e-12);
  // Halfway to the solution: the first error is below the initial metric's, fewer steps follow.
  const Eigen::VectorXd& u0 = disk.p.structure.structure.initial_u;
  const FlowResult warm = disk.flow(u0 + 0.9 * (cold.u - u0));
  expect_solution(disk.p, disk.target, warm, 1e-12);
  EXPECT_LT(warm.history.front().max_error, 0.5 * cold.history.front().max_error);
  EXPECT_LT(warm.iterations, cold.iterations);
  EXPECT_LE(warm.factorizations, cold.factorizations);
  EXPECT_LT((warm.u - cold.u).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Newton, AStartWorseThanTheInitialMetricIsDropped) {
  const ConeDisk disk;
  const FlowResult cold = disk.flow();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-2.0, 2.0);
  Eigen::VectorXd start = disk.p.structure.structure.initial_u;
  for (int v = 0; v < start.size(); ++v) start[v] += noise(rng);
  const FlowResult r = disk.flow(start);
  expect_solution(disk.p, disk.target, r, 1e-12);
  // It started where the cold flow did (the triangulation flipped there and back: rounding).
  EXPECT_NEAR(r.history.front().max_error, cold.history.front().max_error, 1e-12);
  EXPECT_EQ(r.iterations, cold.iterations);
}

TEST(Newton, AStartOfTheWrongSizeIsRefused) {
  const ConeDisk disk;
  EXPECT_THROW(disk.flow(Eigen::VectorXd::Zero(3)), InvalidInput);
  Eigen::VectorXd nan = disk.p.structure.structure.initial_u;
  nan[1] = std::nan("");
  EXPECT_THROW(disk.flow(nan), InvalidInput);
}

TEST(Newton, CholmodAndEigenAgree) {
  const Problem p = make_problem(make_torus(20, 10));
  const Target target = flat_target(p.topology, {});
  FlowOptions options;
  const FlowResult a = ricci_flow(p.topology, p.structure.structure, target, options);
  options.use_cholmod = false;
  const FlowResult b = ricci_flow(p.topology, p.structure.structure, target, options);
  ASSERT_TRUE(a.converged && b.converged);
  EXPECT_EQ(b.linear_solver, std::string("eigen-simplicial-ldlt"));
  EXPECT_LT((a.u - b.u).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Newton, ProgressCallbackSeesEveryIterationAndCanCancel) {
  const Problem p = make_problem(make_torus(20, 10));
  const Target target = flat_target(p.topology, {});
  FlowOptions options;
  std::vector<int> seen;
  options.progress = [&](const IterationRecord& r) {
    seen.push_back(r.iteration);
    return r.iteration < 2;
  };
  const FlowResult r = ricci_flow(p.topology, p.structure.structure, target, options);
  EXPECT_EQ(r.status, FlowStatus::Cancelled);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 2}));
}

TEST(Newton, IterationLimitIsAResultNotAnException) {
  const Problem p = make_problem(make_torus(20, 10));
  FlowOptions options;
  options.max_iterations = 1;
  const FlowResult r =
      ricci_flow(p.topology, p.structure.structure, flat_target(p.topology, {}), options);
  EXPECT_EQ(r.status, FlowStatus::MaxIterations);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_NE(r.message.find("1 iterations"), std::string::npos);
}

TEST(Newton, InadmissibleTargetsAreRejectedBeforeTheFlow) {
  const Problem p = make_problem(make_icosphere(2));
  // Gauss-Bonnet: one cone of pi on a sphere (needs 4 pi in all).
  EXPECT_THROW(ricci_flow(p.topology, p.structure.structure,
                          flat_target(p.topology, {{0, std::numbers::pi}})),
               InvalidInput);
}

// A step that breaks a triangle inequality is shortened, never accepted: a vertex-scaling
// gradient flow with a step far too long breaks triangles on its first tries.
TEST(Newton, StepsThatBreakATriangleAreShortened) {
  const Mesh sphere = make_icosphere(2);
  const Problem p = make_problem(sphere, Scheme::VertexScaling);
  const Target target = flat_target(p.topology, {{0, std::numbers::pi},
                                                 {50, std::numbers::pi},
                                                 {100, std::numbers::pi},
                                                 {150, std::numbers::pi}});
  FlowOptions options;
  options.solver = FlowSolver::Gradient;
  options.gradient_step = 20.0;
  options.max_iterations = 5;
  const FlowResult r = ricci_flow(p.topology, p.structure.structure, target, options);
  int failures = 0;
  for (const auto& record : r.history) {
    failures += record.triangle_failures;
    if (record.triangle_failures > 0) {
      EXPECT_LT(record.step_length, 20.0);
    }
  }
  EXPECT_GT(failures, 0);
  // The state it reports is a valid metric.
  EXPECT_TRUE(r.curvature.allFinite());
  EXPECT_TRUE(r.lengths.allFinite());
  EXPECT_LT(r.gauss_bonnet_relative_error, 1e-12);
}

TEST(Newton, AToleranceBelowTheFloatingPointFloorEndsAtTheFloor) {
  // 1e-17 radians is below what double angle sums resolve: the flow stops where it stagnates
  // within its estimated floor, converged, saying so, in a handful of iterations. On a mesh
  // with 0.1-degree needles the floor is two orders of magnitude higher than on a regular one.
  for (const Mesh& mesh :
       {make_icosphere(3), pull_vertices_to_neighbours(make_closed_surface(2, 20), 0.998, 7, 2)}) {
    MeshFlowOptions options;
    options.target.kind = TargetKind::Uniform;
    options.flow.tolerance = 1e-17;
    const MeshFlowResult r = flow_mesh(mesh, options);
    const FlowResult& f = r.components[0].flow;
    ASSERT_TRUE(r.converged) << f.message;
    EXPECT_NE(f.message.find("floating-point floor"), std::string::npos) << f.message;
    EXPECT_LE(f.max_error, f.error_floor);
    EXPECT_GT(f.error_floor, 1e-16);
    EXPECT_LT(f.error_floor, 1e-11);
    EXPECT_LE(f.iterations, 15);
  }
}

TEST(MeshFlow, SolvesEveryComponentOnItsOwn) {
  // A torus and a disk side by side.
  const Mesh torus = make_torus(16, 8), disk = make_disk(4, 0.5);
  Mesh both;
  both.positions.resize(torus.num_vertices() + disk.num_vertices(), 3);
  both.positions << torus.positions, (disk.positions.rowwise() + Eigen::RowVector3d(5, 0, 0));
  both.triangles.resize(torus.num_faces() + disk.num_faces(), 3);
  both.triangles << torus.triangles, (disk.triangles.array() + torus.num_vertices()).matrix();
  MeshFlowOptions options;
  const MeshFlowResult r = flow_mesh(both, options);
  ASSERT_TRUE(r.converged);
  ASSERT_EQ(r.components.size(), 2u);
  EXPECT_EQ(r.components[0].genus, 1);
  EXPECT_EQ(r.components[1].boundary_loops, 1);
  EXPECT_LE(r.max_error, 1e-10);
  for (int v = 0; v < both.num_vertices(); ++v) {
    if (!r.target.fixed[v]) {
      EXPECT_NEAR(r.curvature[v], 0.0, 1e-10);
    }
  }
  EXPECT_EQ(r.lengths.size(), r.intrinsic.topology().num_edges);
  EXPECT_TRUE(r.lengths.allFinite());
}

}  // namespace
}  // namespace ricci

namespace ricci {
namespace {

// The contract of ricci_flow.hpp: a Hessian that cannot be factorised (the metric degenerating)
// ends the flow with FlowStatus::SolverFailed and a message, never an exception. Inversive
// distances below 0 lose the energy's convexity: with eta = -0.9 on every edge the Hessian of an
// icosphere is indefinite at once.
TEST(Newton, AFactorisationThatFailsIsAStatusNotAnException) {
  const Mesh mesh = make_icosphere(2);
  const Topology t = build_topology(mesh.triangles, mesh.num_vertices());
  StructureOptions scheme;
  scheme.scheme = Scheme::InversiveDistance;
  ConformalStructure s = make_conformal_structure(t, input_edge_lengths(mesh, t), scheme).structure;
  s.eta.setConstant(-0.9);
  for (int v = 0; v < t.num_vertices; ++v) s.initial_u[v] = 0.3 * std::sin(7.0 * v);
  FlowOptions options;
  options.flips = EdgeFlips::Off;
  FlowResult r;
  ASSERT_NO_THROW(r = ricci_flow(t, s, uniform_target(t), options));
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.status, FlowStatus::SolverFailed);
  EXPECT_NE(r.message.find("not positive definite"), std::string::npos) << r.message;
  // Step by step the same.
  RicciFlow flow(t, s, uniform_target(t), options);
  while (flow.step()) {
  }
  EXPECT_EQ(flow.result().status, FlowStatus::SolverFailed);
}

}  // namespace
}  // namespace ricci
