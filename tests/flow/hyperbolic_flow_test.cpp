// The Ricci flow in the hyperbolic background (THEORY.md section 9): Hessians against finite
// differences, positive definiteness, convergence to the uniformization metric of genus >= 2
// surfaces (zero vertex curvature), geodesic boundaries, and Gauss-Bonnet with the area term.

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "flow_test_util.hpp"
#include "ricci/errors.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/flow/ricci_flow.hpp"
#include "ricci/hyperbolic/hyperbolic_refinement.hpp"
#include "ricci/intrinsic/delaunay_flips.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/hyperbolic.hpp"
#include "ricci/metric/lengths.hpp"
#include "support/hard_meshes.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

struct HyperbolicMetric {
  Eigen::VectorXd lengths, curvature;
  CornerAngles angles;
};

HyperbolicMetric evaluate(const Topology& t, const ConformalStructure& s,
                          const Eigen::VectorXd& u) {
  HyperbolicMetric m;
  EXPECT_EQ(edge_lengths(t, s, u, m.lengths).invalid_edges, 0);
  EXPECT_EQ(corner_angles(t, m.lengths, m.angles, s.geometry).first_bad_face, -1);
  vertex_curvature(t, m.angles, m.curvature);
  return m;
}

/// The dense Hessian dK/du the flow assembles (hyperbolic_hessian_terms).
Eigen::MatrixXd assembled_hessian(const Topology& t, const ConformalStructure& s,
                                  const Eigen::VectorXd& u) {
  const HyperbolicMetric m = evaluate(t, s, u);
  Eigen::VectorXd w, diag, ew;
  hyperbolic_hessian_terms(t, s, u, m.lengths, m.angles, w, diag);
  edge_weights(t, w, ew);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(t.num_vertices, t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    const int i = t.edge_vertices(e, 0), j = t.edge_vertices(e, 1);
    h(i, j) -= ew[e];
    h(j, i) -= ew[e];
    h(i, i) += ew[e];
    h(j, j) += ew[e];
  }
  for (int f = 0; f < t.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) h(t.triangles(f, k), t.triangles(f, k)) += diag[3 * f + k];
  }
  return h;
}

Eigen::MatrixXd finite_difference_hessian(const Topology& t, const ConformalStructure& s,
                                          const Eigen::VectorXd& u, double step) {
  Eigen::MatrixXd h(t.num_vertices, t.num_vertices);
  for (int v = 0; v < t.num_vertices; ++v) {
    Eigen::VectorXd up = u, down = u;
    up[v] += step;
    down[v] -= step;
    h.col(v) = (evaluate(t, s, up).curvature - evaluate(t, s, down).curvature) / (2 * step);
  }
  return h;
}

const Scheme kAllSchemes[] = {Scheme::Thurston, Scheme::Tangential, Scheme::InversiveDistance,
                              Scheme::VertexScaling};

StructureResult hyperbolic_structure(const Topology& t, const Mesh& mesh, Scheme scheme) {
  StructureOptions o;
  o.scheme = scheme;
  o.geometry = Geometry::Hyperbolic;
  return make_conformal_structure(t, input_edge_lengths(mesh, t), o);
}

TEST(HyperbolicHessian, MatchesFiniteDifferencesAndIsPositiveDefiniteForEveryScheme) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  for (Scheme scheme : kAllSchemes) {
    SCOPED_TRACE(scheme_name(scheme));
    const ConformalStructure s = hyperbolic_structure(t, mesh, scheme).structure;
    Eigen::VectorXd u = s.initial_u;
    for (int v = 0; v < t.num_vertices; ++v) u[v] += jitter(random);
    const Eigen::MatrixXd h = assembled_hessian(t, s, u);
    const Eigen::MatrixXd fd = finite_difference_hessian(t, s, u, 1e-6);
    const double scale = h.cwiseAbs().maxCoeff();
    EXPECT_LT((h - fd).cwiseAbs().maxCoeff(), 1e-7 * scale);
    // Symmetric before symmetrisation: the per-face Jacobians themselves.
    const HyperbolicMetric m = evaluate(t, s, u);
    double asymmetry = 0, size = 0;
    for (int f = 0; f < t.num_faces; ++f) {
      const Eigen::Matrix3d j = hyperbolic_face_jacobian(t, s, u, m.lengths, m.angles, f);
      asymmetry = std::max(asymmetry, (j - j.transpose()).cwiseAbs().maxCoeff());
      size = std::max(size, j.cwiseAbs().maxCoeff());
    }
    EXPECT_LT(asymmetry, 1e-12 * size);
    // Positive definite: no gauge direction (K changes when every u grows).
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(h);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 1e-8 * eig.eigenvalues().maxCoeff());
  }
}

TEST(HyperbolicStructure, ReproducesTheScaledInputLengths) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  for (Scheme scheme : {Scheme::InversiveDistance, Scheme::VertexScaling}) {
    const StructureResult r = hyperbolic_structure(t, mesh, scheme);
    EXPECT_LT(r.fit_max_relative_error, 1e-12) << scheme_name(scheme);
    EXPECT_GT(r.structure.length_scale, 0);
  }
  // The automatic scale gives the input the area 2 pi |chi| = 4 pi of the hyperbolic metric.
  const StructureResult r = hyperbolic_structure(t, mesh, Scheme::VertexScaling);
  Eigen::VectorXd l;
  CornerAngles a;
  edge_lengths(t, r.structure, r.structure.initial_u, l);
  corner_angles(t, l, a, Geometry::Hyperbolic);
  EXPECT_NEAR(hyperbolic_total_area(a), 4 * std::numbers::pi, 0.2 * 4 * std::numbers::pi);
}

/// Runs the default hyperbolic job (zero curvature, geodesic boundary) on a mesh.
MeshFlowResult uniformize(const Mesh& mesh, Scheme scheme = Scheme::Thurston) {
  MeshFlowOptions o;
  o.structure.scheme = scheme;
  o.structure.geometry = Geometry::Hyperbolic;
  o.target.boundary = BoundaryMode::Geodesic;
  return flow_mesh(mesh, o);
}

void expect_uniformized(const MeshFlowResult& r, int chi) {
  ASSERT_TRUE(r.converged) << r.components[0].flow.message;
  EXPECT_LE(r.max_error, 1e-10);
  const FlowResult& f = r.components[0].flow;
  // Gauss-Bonnet in curvature -1: sum K - area = 2 pi chi; with K = 0 the area is -2 pi chi.
  // |area + 2 pi chi| = |sum K| <= #V max |K|.
  EXPECT_NEAR(f.total_area, -2 * std::numbers::pi * chi, f.curvature.size() * f.max_error + 1e-12);
  EXPECT_LT(f.gauss_bonnet_relative_error, 1e-12);
  EXPECT_LT(f.iterations, 30);
}

TEST(HyperbolicFlow, UniformizesGeneratedGenus2And3WithEveryScheme) {
  for (int genus : {2, 3}) {
    const Mesh mesh = make_closed_surface(genus, 8);
    for (Scheme scheme : kAllSchemes) {
      SCOPED_TRACE(std::string(scheme_name(scheme)) + ", genus " + std::to_string(genus));
      const MeshFlowResult r = uniformize(mesh, scheme);
      expect_uniformized(r, 2 - 2 * genus);
      testing::expect_quadratic_convergence(r.components[0].flow);
    }
  }
}

TEST(HyperbolicFlow, GivesSurfacesWithBoundaryAGeodesicBoundary) {
  // Genus 1 with two holes (chi = -2) and genus 0 with three holes (a pair of pants, chi = -1).
  for (auto [genus, holes] : {std::pair{1, 2}, std::pair{0, 3}}) {
    const Mesh mesh = make_surface_with_holes(genus, holes, 10);
    const MeshFlowResult r = uniformize(mesh);
    expect_uniformized(r, 2 - 2 * genus - holes);
    // Boundary vertices reach zero geodesic curvature (pi - angle sum) like the others.
    const Topology& t = r.intrinsic.topology();
    for (int v = 0; v < t.num_vertices; ++v) {
      if (t.is_boundary_vertex[v]) {
        EXPECT_NEAR(r.curvature[v], 0, 1e-10);
      }
    }
  }
}

TEST(HyperbolicFlow, RefusesTargetsWithNoPositiveArea) {
  // A torus has chi = 0: zero curvature would need zero area.
  const Mesh torus = make_torus(12, 8);
  EXPECT_THROW(uniformize(torus), InvalidInput);
  // Gauss-Bonnet's Euclidean equality is not required: a uniform target below zero works.
  const Mesh mesh = make_closed_surface(2, 8);
  MeshFlowOptions o;
  o.structure.geometry = Geometry::Hyperbolic;
  o.target.kind = TargetKind::Values;
  o.target.values = Eigen::VectorXd::Constant(mesh.positions.rows(), -0.001);
  const MeshFlowResult r = flow_mesh(mesh, o);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.components[0].flow.total_area,
              -0.001 * static_cast<double>(mesh.positions.rows()) + 4 * std::numbers::pi, 1e-8);
}

TEST(HyperbolicStructure, RefusesTheVirtualRadiusScheme) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  EXPECT_THROW(hyperbolic_structure(t, mesh, Scheme::VirtualRadius), InvalidInput);
}

// ---- Intrinsic Delaunay flips in the hyperbolic background ----

/// The hyperbolic vertex-scaling job with flips as asked.
MeshFlowResult uniformize_vertex_scaling(const Mesh& mesh, EdgeFlips flips) {
  MeshFlowOptions o;
  o.structure.scheme = Scheme::VertexScaling;
  o.structure.geometry = Geometry::Hyperbolic;
  o.target.boundary = BoundaryMode::Geodesic;
  o.flow.flips = flips;
  return flow_mesh(mesh, o);
}

/// The final structure of a flow: the input's constants, eta as the flips left them.
ConformalStructure final_structure(const MeshFlowResult& r) {
  ConformalStructure s = r.structure.structure;
  s.eta = r.intrinsic.eta();
  return s;
}

TEST(HyperbolicFlips, AreOnForVertexScalingAndRefusedForCirclePackings) {
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  FlowOptions automatic, delaunay;
  delaunay.flips = EdgeFlips::Delaunay;
  EXPECT_TRUE(
      uses_edge_flips(hyperbolic_structure(t, mesh, Scheme::VertexScaling).structure, automatic));
  const ConformalStructure thurston = hyperbolic_structure(t, mesh, Scheme::Thurston).structure;
  EXPECT_FALSE(uses_edge_flips(thurston, automatic));
  EXPECT_THROW(uses_edge_flips(thurston, delaunay), InvalidInput);
}

TEST(HyperbolicFlips, ConvergeOnValence3SpikesWhereTheFixedTriangulationFails) {
  // Faces split 1-to-3 near a corner, the new vertex pushed out by a face's length: valence-3
  // spikes whose slivers vertex scaling cannot flatten without breaking a triangle.
  for (int genus : {2, 3}) {
    SCOPED_TRACE("genus " + std::to_string(genus));
    const Mesh mesh = testing::with_valence3_spikes(make_closed_surface(genus, 12), 5, 1.0);
    if (genus == 2) {  // (about 0.3 s of backtracking)
      const MeshFlowResult fixed = uniformize_vertex_scaling(mesh, EdgeFlips::Off);
      EXPECT_EQ(fixed.components[0].flow.status, FlowStatus::LineSearchFailed);
    }
    const MeshFlowResult r = uniformize_vertex_scaling(mesh, EdgeFlips::Auto);
    expect_uniformized(r, 2 - 2 * genus);
    const FlowResult& f = r.components[0].flow;
    EXPECT_GT(f.intrinsic.isometric_flips(), 0);
    EXPECT_GT(f.intrinsic.flips(),
              f.intrinsic.isometric_flips());  // Ptolemy flips during the flow too
    EXPECT_EQ(f.intrinsic.blocked_flips(), 0);
    // The final triangulation is Delaunay for the final metric, and the structure with the
    // flipped constants reproduces its lengths.
    EXPECT_EQ(
        count_non_delaunay_edges(r.intrinsic.topology(), r.lengths, 1e-12, Geometry::Hyperbolic),
        0);
    Eigen::VectorXd l;
    ASSERT_EQ(edge_lengths(r.intrinsic.topology(), final_structure(r), r.u, l).invalid_edges, 0);
    EXPECT_LT(((l - r.lengths).array() / r.lengths.array()).abs().maxCoeff(), 1e-14);
  }
}

TEST(HyperbolicFlips, ConvergeOnNeedlesAndNoise) {
  // 0.1-degree needles (edges split next to an end), and a surface whose vertices were moved in
  // their tangent planes by up to 45% of their shortest edge: far from Delaunay.
  const Mesh needles = testing::with_needles(make_closed_surface(2, 12), 3, 0.0017);
  const Mesh noisy = testing::jitter_tangentially(make_closed_surface(2, 16), 0.45, 3);
  for (const Mesh* mesh : {&needles, &noisy}) {
    const MeshFlowResult r = uniformize_vertex_scaling(*mesh, EdgeFlips::Auto);
    expect_uniformized(r, -2);
    EXPECT_GT(r.intrinsic.flips(), 100);
    testing::expect_quadratic_convergence(r.components[0].flow);
  }
}

TEST(HyperbolicFlips, HessianMatchesFiniteDifferencesOnTheFlippedTriangulation) {
  // The flow's Hessian on the intrinsic Delaunay triangulation it ends on (with the constants
  // the flips set), at points around its solution: central differences of K(u) on that fixed
  // triangulation agree, and it stays positive definite.
  const Mesh mesh = testing::with_valence3_spikes(make_closed_surface(2, 6), 3, 1.0);
  const MeshFlowResult r = uniformize_vertex_scaling(mesh, EdgeFlips::Auto);
  ASSERT_TRUE(r.converged);
  ASSERT_GT(r.intrinsic.flips(), 20);
  const ConformalStructure s = final_structure(r);
  std::mt19937 random(13);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  Eigen::VectorXd u = r.u;
  for (int v = 0; v < u.size(); ++v) u[v] += jitter(random);
  const Eigen::MatrixXd h = assembled_hessian(r.intrinsic.topology(), s, u);
  const Eigen::MatrixXd fd = finite_difference_hessian(r.intrinsic.topology(), s, u, 1e-6);
  EXPECT_LT((h - fd).cwiseAbs().maxCoeff(), 1e-7 * h.cwiseAbs().maxCoeff());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(h);
  EXPECT_GT(eig.eigenvalues().minCoeff(), 1e-8 * eig.eigenvalues().maxCoeff());
}

TEST(HyperbolicFlips, TheHessianIsContinuousAcrossAFlip) {
  // Where an edge's quad is concyclic (Delaunay margin 0) both triangulations describe the same
  // surface (the Ptolemy flip is isometric there), and the energy is twice differentiable across
  // the flip (Springborn 2020): the Hessians of the two triangulations agree.
  const Mesh mesh = make_closed_surface(2, 6);
  const Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  const ConformalStructure s = hyperbolic_structure(t, mesh, Scheme::VertexScaling).structure;
  int tested = 0;
  for (int e = 0; e < t.num_edges && tested < 5; e += 37) {
    if (!can_flip_edge(t, e)) continue;
    const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
    const int a = t.tail(h0), b = t.head(h0);
    // Growing a and b lengthens ab more than the sides: the angles opposite it open until the
    // quad turns non-Delaunay at some x.
    auto scaled = [&](double x) {
      Eigen::VectorXd u = s.initial_u;
      u[a] += x;
      u[b] += x;
      return u;
    };
    auto margin_at = [&](double x) {
      Eigen::VectorXd l;
      edge_lengths(t, s, scaled(x), l);
      return hyperbolic_delaunay_margin(l[e], l[t.face_edges(h0 / 3, (h0 % 3 + 2) % 3)],
                                        l[t.face_edges(h0 / 3, (h0 % 3 + 1) % 3)],
                                        l[t.face_edges(h1 / 3, (h1 % 3 + 1) % 3)],
                                        l[t.face_edges(h1 / 3, (h1 % 3 + 2) % 3)]);
    };
    if (a == b || !(margin_at(0) > 0) || !(margin_at(1.5) < 0)) continue;
    double lo = 0, hi = 1.5;
    for (int i = 0; i < 100; ++i) (margin_at(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
    const Eigen::VectorXd u = scaled(lo);
    Eigen::VectorXd l;
    ASSERT_EQ(edge_lengths(t, s, u, l).invalid_edges, 0);
    Topology flipped = t;
    ConformalStructure s_flipped = s;
    ptolemy_flip(flipped, s_flipped, u, l, e);
    const Eigen::MatrixXd before = assembled_hessian(t, s, u);
    const Eigen::MatrixXd after = assembled_hessian(flipped, s_flipped, u);
    EXPECT_LT((before - after).cwiseAbs().maxCoeff(), 1e-8 * before.cwiseAbs().maxCoeff())
        << "edge " << e;
    // And the curvature itself is the same.
    EXPECT_LT((evaluate(t, s, u).curvature - evaluate(flipped, s_flipped, u).curvature)
                  .cwiseAbs()
                  .maxCoeff(),
              1e-12);
    ++tested;
  }
  EXPECT_GE(tested, 3);
}

TEST(HyperbolicFlips, FlowAndRefinementWorkOnADeltaComplex) {
  // A coarse genus-2 surface flipped to its Delaunay triangulation at log radii -2 on two
  // vertices: the small vertices are surrounded by edges wrapping round them, and the result is
  // a Delta-complex (an edge joining a vertex to itself, or two edges the same two vertices).
  // On it, with its flipped constants: the Hessian against finite differences, Newton from a
  // perturbed start back to the curvature of that metric, and the long double refinement.
  const Mesh mesh = make_closed_surface(2, 2);
  Topology t = build_topology(mesh.triangles, static_cast<int>(mesh.positions.rows()));
  ConformalStructure s = hyperbolic_structure(t, mesh, Scheme::VertexScaling).structure;
  Eigen::VectorXd u = s.initial_u, l;
  u[0] = u[10] = -2.0;
  ASSERT_EQ(edge_lengths(t, s, u, l).invalid_edges, 0);
  const DelaunayFlipResult flips = flip_to_delaunay(t, s, u, l);
  ASSERT_GT(flips.flips, 20);
  ASSERT_FALSE(is_simplicial(t));
  const Target target = values_target(t, evaluate(t, s, u).curvature);
  const Eigen::MatrixXd h = assembled_hessian(t, s, u);
  const Eigen::MatrixXd fd = finite_difference_hessian(t, s, u, 1e-6);
  EXPECT_LT((h - fd).cwiseAbs().maxCoeff(), 1e-7 * h.cwiseAbs().maxCoeff());

  FlowOptions o;
  o.flips = EdgeFlips::Off;
  o.tolerance = 1e-12;
  s.initial_u = u;  // where this triangulation's triangles exist
  RicciFlow flow(t, s, target, o);
  std::mt19937 random(31);
  std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
  Eigen::VectorXd start = u;
  for (int v = 0; v < start.size(); ++v) start[v] += jitter(random);
  flow.set_u(start);
  while (flow.step()) {
  }
  const FlowResult r = flow.result();
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_LT((r.u - u).cwiseAbs().maxCoeff(), 1e-9);  // the energy is strictly convex
  const HyperbolicRefinement refined = refine_hyperbolic_metric(t, s, target, r.u);
  EXPECT_LT(refined.max_error_after, 1e-16);
  EXPECT_LE(refined.max_error_after, refined.max_error_before);
}

TEST(HyperbolicFlips, EachComponentOfAMeshFlowsInTheHyperbolicBackground) {
  // Two disjoint surfaces (genus 2 with spikes, genus 3): each component's flow runs on its own
  // copy of the structure, which must keep the hyperbolic geometry (area 2 pi |chi| each).
  const Mesh a = testing::with_valence3_spikes(make_closed_surface(2, 8), 5, 1.0);
  const Mesh b = make_closed_surface(3, 8);
  Mesh both;
  both.positions.resize(a.num_vertices() + b.num_vertices(), 3);
  both.positions << a.positions, b.positions.rowwise() + Eigen::RowVector3d(20, 0, 0);
  both.triangles.resize(a.num_faces() + b.num_faces(), 3);
  both.triangles << a.triangles, b.triangles.array() + a.num_vertices();
  const MeshFlowResult r = uniformize_vertex_scaling(both, EdgeFlips::Auto);
  ASSERT_TRUE(r.converged);
  ASSERT_EQ(r.components.size(), 2u);
  EXPECT_NEAR(r.components[0].flow.total_area, 4 * std::numbers::pi, 1e-8);
  EXPECT_NEAR(r.components[1].flow.total_area, 8 * std::numbers::pi, 1e-8);
  EXPECT_GT(r.components[0].flow.intrinsic.flips(), 0);
  // The whole mesh's final triangulation and constants reproduce the gathered lengths.
  Eigen::VectorXd l;
  ASSERT_EQ(edge_lengths(r.intrinsic.topology(), final_structure(r), r.u, l).invalid_edges, 0);
  EXPECT_LT(((l - r.lengths).array() / r.lengths.array()).abs().maxCoeff(), 1e-14);
}

TEST(HyperbolicFlow, UniformizesEveryClosedSharedMeshOfGenusAtLeastTwo) {
  RICCI_REQUIRE_SHARED_MESHES();
  const std::vector<testing::SharedMesh> meshes = testing::closed_hyperbolic_shared_meshes();
  EXPECT_GE(meshes.size(), 3u);  // eight (g2), 3holes (g3), fertility (g4)
  for (const auto& m : meshes) {
    SCOPED_TRACE(m.file);
    expect_uniformized(uniformize(read_mesh(m.path).mesh), m.euler_characteristic);
  }
}

}  // namespace
}  // namespace ricci
